// Scene: the public face of masq::Scene (scenes/scene.h) and of the file loaders.
#include "api/api_impl.h"
#include "masq/error.h"
#include "scenes/camera.h"
#include "scenes/curve_tools.h"
#include "scenes/loaders/load_any.h"
#include <cmath>
#include <cstring>
#include <filesystem>

namespace masq::api {
namespace {

glm::vec3 to_glm(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 to_api(const glm::vec3& v) { return {v.x, v.y, v.z}; }
glm::dvec3 to_glm(const Vec3d& v) { return {v.x, v.y, v.z}; }
Vec3d to_api(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

masq::Camera to_scene_camera(const Camera& c) {
  masq::Camera out;
  out.eye = to_glm(c.eye);
  out.target = to_glm(c.target);
  out.up = to_glm(c.up);
  out.fov_y_deg = c.fov_y_deg;
  out.orthographic = c.orthographic;
  out.ortho_height = c.ortho_height;
  return out;
}

// Every array of the geometry converted; only its type's array holds anything, so no
// question of which type it is needs asking.
GeometryData geometry_data(const masq::Geometry& g) {
  GeometryData d;
  d.type = prim_type_key(g.type);
  for (const glm::vec3& v : g.vertices) d.vertices.push_back(to_api(v));
  for (const glm::uvec3& t : g.triangles) d.indices.insert(d.indices.end(), {t.x, t.y, t.z});
  for (const CapsulePrim& c : g.capsules) d.capsules.push_back({to_api(c.a), to_api(c.b), c.radius});
  for (const RoundConePrim& c : g.round_cones) d.round_cones.push_back({to_api(c.a), c.ra, to_api(c.b), c.rb});
  for (const SpherePrim& c : g.spheres) d.spheres.push_back({to_api(c.center), c.radius});
  for (const CurvePrim& c : g.curves)
    d.curves.push_back({{to_api(c.p[0]), to_api(c.p[1]), to_api(c.p[2]), to_api(c.p[3])}, c.radius});
  for (const RibbonPrim& r : g.ribbons) d.ribbons.push_back({to_api(r.p0), r.r0, to_api(r.p1), r.r1, to_api(r.n)});
  d.strands = strand_ids(g);
  return d;
}

std::uint32_t push(masq::Scene& s, masq::Geometry g) {
  s.geometries.push_back(std::move(g));
  return static_cast<std::uint32_t>(s.geometries.size() - 1);
}

} // namespace

masq::Scene Scene::Impl::placed() const {
  masq::Scene s = scene;
  if (s.instances.empty())
    for (std::uint32_t g = 0; g < s.geometries.size(); ++g) s.instances.push_back({g, {}});
  return s;
}

Scene::Scene() : impl_(std::make_unique<Impl>()) { impl_->scene.name = "api"; }
Scene::~Scene() = default;
Scene::Scene(const Scene& o) : impl_(std::make_unique<Impl>(*o.impl_)) {}
Scene& Scene::operator=(const Scene& o) {
  if (this != &o) impl_ = std::make_unique<Impl>(*o.impl_);
  return *this;
}
// Moves do not allocate: a moved-from Scene may only be assigned to or destroyed.
Scene::Scene(Scene&& o) noexcept : impl_(std::move(o.impl_)) {}
Scene& Scene::operator=(Scene&& o) noexcept {
  std::swap(impl_, o.impl_);
  return *this;
}

Scene Scene::load(const std::string& path, const LoadOptions& options) {
  // A negative radius would otherwise read as "the loader's default" (radius > 0 is the
  // loaders' test for a given one).
  if (!std::isfinite(options.radius) || options.radius < 0.0f)
    throw Error("Scene::load: radius " + std::to_string(options.radius) +
                " (must be > 0, or 0 for the file's radii or the loader's default)");
  masq::LoadOptions lo;
  lo.radius = options.radius;
  lo.strand_type = options.round_cones ? PrimType::RoundCone : PrimType::Capsule;
  lo.warn = options.warn;
  Scene s;
  s.impl_->scene = load_scene_file(path, lo);
  // .json and .nff files carry their own camera; the others' loaders framed what they hold,
  // which camera_rays does again so that geometry added after loading is in view too.
  s.impl_->has_camera = scene_file_carries_view(path);
  return s;
}

std::vector<std::string> Scene::file_extensions() { return scene_file_extensions(); }

std::uint32_t Scene::add_triangles(std::span<const Vec3> vertices, std::span<const std::uint32_t> indices) {
  if (indices.size() % 3 != 0)
    throw Error("Scene::add_triangles: " + std::to_string(indices.size()) +
                " indices is not a multiple of 3");
  masq::Geometry g;
  g.type = PrimType::Triangle;
  for (const Vec3& v : vertices) g.vertices.push_back(to_glm(v));
  for (std::size_t i = 0; i < indices.size(); i += 3)
    g.triangles.push_back({indices[i], indices[i + 1], indices[i + 2]});
  return push(impl_->scene, std::move(g));
}

std::uint32_t Scene::add_capsules(std::span<const Capsule> capsules) {
  masq::Geometry g;
  g.type = PrimType::Capsule;
  for (const Capsule& c : capsules) g.capsules.push_back({to_glm(c.a), to_glm(c.b), c.radius});
  return push(impl_->scene, std::move(g));
}

std::uint32_t Scene::add_round_cones(std::span<const RoundCone> round_cones) {
  masq::Geometry g;
  g.type = PrimType::RoundCone;
  for (const RoundCone& c : round_cones) g.round_cones.push_back({to_glm(c.a), c.ra, to_glm(c.b), c.rb});
  return push(impl_->scene, std::move(g));
}

std::uint32_t Scene::add_spheres(std::span<const Sphere> spheres) {
  masq::Geometry g;
  g.type = PrimType::Sphere;
  for (const Sphere& s : spheres) g.spheres.push_back({to_glm(s.center), s.radius});
  return push(impl_->scene, std::move(g));
}

std::uint32_t Scene::add_curves(std::span<const Curve> curves) {
  masq::Geometry g;
  g.type = PrimType::Curve;
  for (const Curve& c : curves)
    g.curves.push_back({{{to_glm(c.p[0]), to_glm(c.p[1]), to_glm(c.p[2]), to_glm(c.p[3])}}, c.radius});
  return push(impl_->scene, std::move(g));
}

std::uint32_t Scene::add_ribbons(std::span<const Ribbon> ribbons) {
  masq::Geometry g;
  g.type = PrimType::Ribbon;
  for (const Ribbon& r : ribbons) g.ribbons.push_back({to_glm(r.p0), r.r0, to_glm(r.p1), r.r1, to_glm(r.n)});
  return push(impl_->scene, std::move(g));
}

std::uint32_t Scene::add_instance(std::uint32_t geometry, const Transform& t) {
  if (geometry >= impl_->scene.geometries.size())
    throw Error("Scene::add_instance: geometry " + std::to_string(geometry) + " does not exist (the scene has " +
                std::to_string(impl_->scene.geometries.size()) + ")");
  masq::Instance inst;
  inst.geometry = geometry;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) inst.object_to_world.linear[c][r] = t.m[r][c]; // glm is column-major
    inst.object_to_world.translation[r] = t.m[r][3];
  }
  impl_->scene.instances.push_back(inst);
  return static_cast<std::uint32_t>(impl_->scene.instances.size() - 1);
}

std::size_t Scene::geometry_count() const { return impl_->scene.geometries.size(); }

GeometryData Scene::geometry(std::uint32_t id) const {
  if (id >= impl_->scene.geometries.size())
    throw Error("Scene::geometry: geometry " + std::to_string(id) + " does not exist (the scene has " +
                std::to_string(impl_->scene.geometries.size()) + ")");
  return geometry_data(impl_->scene.geometries[id]);
}
std::size_t Scene::instance_count() const { return impl_->scene.instances.size(); }
std::size_t Scene::primitive_count() const {
  const masq::Scene& s = impl_->scene;
  if (!s.instances.empty()) return s.primitive_count();
  std::size_t n = 0;
  for (const masq::Geometry& g : s.geometries) n += g.primitive_count();
  return n;
}

void Scene::validate() const { validate_scene(impl_->placed()); }

Box Scene::bounds() const {
  glm::dvec3 lo, hi;
  scene_world_bounds(impl_->placed(), lo, hi);
  return {to_api(lo), to_api(hi)};
}

Camera Scene::camera() const {
  masq::Scene framed = impl_->placed();
  if (!impl_->has_camera) frame_scene(framed);
  const masq::Camera& c = framed.camera;
  return {to_api(c.eye), to_api(c.target), to_api(c.up), c.fov_y_deg, c.orthographic, c.ortho_height};
}

std::vector<Ray> Scene::camera_rays(int width, int height) const {
  if (width <= 0 || height <= 0)
    throw Error("Scene::camera_rays: width and height must be positive, got " + std::to_string(width) + "x" +
                std::to_string(height));
  return api::camera_rays(camera(), width, height);
}

std::vector<Ray> camera_rays(const Camera& camera, int width, int height) {
  if (width <= 0 || height <= 0)
    throw Error("camera_rays: width and height must be positive, got " + std::to_string(width) + "x" +
                std::to_string(height));
  const masq::Camera c = to_scene_camera(camera);
  auto finite3 = [](const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  const bool finite = finite3(c.eye) && finite3(c.target) && finite3(c.up) && std::isfinite(c.fov_y_deg) &&
                      std::isfinite(c.ortho_height);
  if (!finite) throw Error("camera_rays: the camera has a non-finite eye, target, up, fov or height");
  // tan(fov / 2) is 0 or negative outside (0, 180): no image, or one upside down.
  if (!c.orthographic && !(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0))
    throw Error("camera_rays: fov_y_deg " + std::to_string(c.fov_y_deg) + " (must be in (0, 180) degrees)");
  if (c.orthographic && !(c.ortho_height > 0.0))
    throw Error("camera_rays: ortho_height " + std::to_string(c.ortho_height) + " (must be > 0)");
  std::vector<kernel::Ray> kr = make_camera_rays(c, width, height);
  static_assert(sizeof(Ray) == sizeof(kernel::Ray));
  std::vector<Ray> rays(kr.size());
  std::memcpy(static_cast<void*>(rays.data()), kr.data(), kr.size() * sizeof(Ray));
  return rays;
}

} // namespace masq::api
