#include "scenes/camera.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <algorithm>
#include <cmath>

namespace masq {

kernel::Ray make_ray(const glm::dvec3& org, const glm::dvec3& dir, float tmin, float tmax) {
  kernel::Ray r{};
  for (int k = 0; k < 3; ++k) {
    r.org[k] = static_cast<float>(org[k]);
    r.dir[k] = static_cast<float>(dir[k]);
  }
  r.tmin = tmin;
  r.tmax = tmax;
  return r;
}

std::vector<kernel::Ray> make_camera_rays(const Camera& cam, int width, int height) {
  if (width <= 0 || height <= 0)
    throw Error("camera: image size " + std::to_string(width) + "x" + std::to_string(height) + " is empty");
  glm::dvec3 fwd = cam.target - cam.eye;
  if (!(glm::length(fwd) > 0.0)) throw Error("camera: eye and target coincide");
  fwd = glm::normalize(fwd);
  glm::dvec3 right = glm::cross(fwd, cam.up);
  if (!(glm::length(right) > 0.0)) throw Error("camera: up is parallel to the view direction");
  right = glm::normalize(right);
  glm::dvec3 up = glm::cross(right, fwd);
  double aspect = double(width) / double(height);
  double half_h = cam.orthographic ? 0.5 * cam.ortho_height : std::tan(glm::radians(cam.fov_y_deg) * 0.5);
  double half_w = half_h * aspect;
  std::vector<kernel::Ray> rays;
  rays.reserve(std::size_t(width) * height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double sx = (2.0 * (x + 0.5) / width - 1.0) * half_w;
      double sy = (1.0 - 2.0 * (y + 0.5) / height) * half_h;
      if (cam.orthographic)
        rays.push_back(make_ray(cam.eye + sx * right + sy * up, fwd));
      else
        rays.push_back(make_ray(cam.eye, glm::normalize(fwd + sx * right + sy * up)));
    }
  }
  return rays;
}

void scene_world_bounds(const Scene& scene, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(INFINITY);
  hi = glm::dvec3(-INFINITY);
  for (const Instance& inst : scene.instances) {
    const Geometry& g = scene.geometries.at(inst.geometry);
    const Affine3& xf = inst.object_to_world;
    // A ball of radius r becomes an ellipsoid reaching r * |row i| along axis i (glm is
    // column-major: row i is (linear[0][i], linear[1][i], linear[2][i])).
    glm::dvec3 reach;
    for (int i = 0; i < 3; ++i) reach[i] = glm::length(glm::dvec3(xf.linear[0][i], xf.linear[1][i], xf.linear[2][i]));
    const ScenePrimRow& row = scene_prim_row(g.type);
    PrimBalls balls;
    for (std::size_t p = 0, n = row.count(g); p < n; ++p) {
      const int count = row.balls(g, p, balls);
      for (int k = 0; k < count; ++k) {
        const glm::dvec3 w = xf.apply_point(glm::dvec3(balls[std::size_t(k)].centre));
        const glm::dvec3 s = double(balls[std::size_t(k)].radius) * reach;
        lo = glm::min(lo, w - s);
        hi = glm::max(hi, w + s);
      }
    }
  }
}

void frame_scene(Scene& scene) {
  glm::dvec3 lo, hi;
  scene_world_bounds(scene, lo, hi);
  if (!(lo.x <= hi.x)) return; // nothing to frame
  glm::dvec3 centre = 0.5 * (lo + hi);
  double size = std::max(glm::length(hi - lo), 1e-30);
  scene.camera = Camera{};
  scene.camera.target = centre;
  scene.camera.eye = centre + glm::dvec3(0.0, 0.2 * size, -1.4 * size);
  scene.camera.fov_y_deg = 40.0;
}

} // namespace masq
