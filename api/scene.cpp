// Scene: the public face of masq::Scene (scenes/scene.h) and of the file loaders.
#include "api/api_impl.h"
#include "masq/error.h"
#include "scenes/camera.h"
#include "scenes/loaders/load_any.h"
#include <cstring>
#include <filesystem>

namespace masq::api {
namespace {

glm::vec3 to_glm(const Vec3& v) { return {v.x, v.y, v.z}; }

std::uint32_t push(masq::Scene& s, masq::Geometry g) {
  s.geometries.push_back(std::move(g));
  return static_cast<std::uint32_t>(s.geometries.size() - 1);
}

} // namespace

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
  masq::LoadOptions lo;
  lo.radius = options.radius;
  lo.strand_type = options.round_cones ? PrimType::RoundCone : PrimType::Capsule;
  Scene s;
  s.impl_->scene = load_scene_file(path, lo);
  // A .json description carries (or frames) its own camera; other formats have none.
  s.impl_->has_camera = std::filesystem::path(path).extension() == ".json";
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
std::size_t Scene::instance_count() const { return impl_->scene.instances.size(); }
std::size_t Scene::primitive_count() const { return impl_->scene.primitive_count(); }

void Scene::validate() const {
  if (impl_->scene.instances.empty()) {
    // The documented default placement, checked the same way the Accel will see it.
    masq::Scene placed = impl_->scene;
    for (std::uint32_t g = 0; g < placed.geometries.size(); ++g) placed.instances.push_back({g, {}});
    validate_scene(placed);
    return;
  }
  validate_scene(impl_->scene);
}

std::vector<Ray> Scene::camera_rays(int width, int height) const {
  if (width <= 0 || height <= 0)
    throw Error("Scene::camera_rays: width and height must be positive, got " + std::to_string(width) + "x" +
                std::to_string(height));
  masq::Scene framed = impl_->scene;
  if (framed.instances.empty())
    for (std::uint32_t g = 0; g < framed.geometries.size(); ++g) framed.instances.push_back({g, {}});
  if (!impl_->has_camera) frame_scene(framed);
  std::vector<kernel::Ray> kr = make_camera_rays(framed.camera, width, height);
  static_assert(sizeof(Ray) == sizeof(kernel::Ray));
  std::vector<Ray> rays(kr.size());
  std::memcpy(static_cast<void*>(rays.data()), kr.data(), kr.size() * sizeof(Ray));
  return rays;
}

} // namespace masq::api
