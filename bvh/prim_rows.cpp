#include "bvh/prim_rows.h"
#include "masq/error.h"
#include <string>

namespace masq {

namespace {

void copy3(float* dst, const glm::vec3& v) {
  for (int k = 0; k < 3; ++k) dst[k] = v[k];
}
glm::vec3 v3(const float* p) { return {p[0], p[1], p[2]}; }

int pack_triangles(const Geometry& g, PackedScene& ps) {
  const int first = int(ps.triangles.size());
  for (const glm::uvec3& t : g.triangles) {
    kernel::Triangle kt{};
    copy3(kt.v0, g.vertices[t.x]);
    copy3(kt.v1, g.vertices[t.y]);
    copy3(kt.v2, g.vertices[t.z]);
    ps.triangles.push_back(kt);
  }
  return first;
}
int pack_capsules(const Geometry& g, PackedScene& ps) {
  const int first = int(ps.capsules.size());
  for (const CapsulePrim& c : g.capsules) {
    kernel::Capsule kc{};
    copy3(kc.a, c.a);
    copy3(kc.b, c.b);
    kc.radius = c.radius;
    ps.capsules.push_back(kc);
  }
  return first;
}
int pack_round_cones(const Geometry& g, PackedScene& ps) {
  const int first = int(ps.round_cones.size());
  for (const RoundConePrim& c : g.round_cones) {
    kernel::RoundCone kc{};
    copy3(kc.a, c.a);
    copy3(kc.b, c.b);
    kc.ra = c.ra;
    kc.rb = c.rb;
    ps.round_cones.push_back(kc);
  }
  return first;
}
int pack_spheres(const Geometry& g, PackedScene& ps) {
  const int first = int(ps.spheres.size());
  for (const SpherePrim& sp : g.spheres) {
    kernel::Sphere ks{};
    copy3(ks.center, sp.center);
    ks.radius = sp.radius;
    ps.spheres.push_back(ks);
  }
  return first;
}
int pack_curves(const Geometry& g, PackedScene& ps) {
  const int first = int(ps.curves.size());
  for (const CurvePrim& c : g.curves) {
    kernel::Curve kc{};
    copy3(kc.p0, c.p[0]);
    copy3(kc.p1, c.p[1]);
    copy3(kc.p2, c.p[2]);
    copy3(kc.p3, c.p[3]);
    kc.radius = c.radius;
    ps.curves.push_back(kc);
  }
  return first;
}

int triangle_balls(const PackedScene& ps, std::size_t i, PrimBalls& out) {
  const kernel::Triangle& t = ps.triangles.at(i);
  out[0] = {v3(t.v0), 0.0f};
  out[1] = {v3(t.v1), 0.0f};
  out[2] = {v3(t.v2), 0.0f};
  return 3;
}
int capsule_balls(const PackedScene& ps, std::size_t i, PrimBalls& out) {
  const kernel::Capsule& c = ps.capsules.at(i);
  out[0] = {v3(c.a), c.radius};
  out[1] = {v3(c.b), c.radius};
  return 2;
}
int round_cone_balls(const PackedScene& ps, std::size_t i, PrimBalls& out) {
  const kernel::RoundCone& c = ps.round_cones.at(i);
  out[0] = {v3(c.a), c.ra};
  out[1] = {v3(c.b), c.rb};
  return 2;
}
int sphere_balls(const PackedScene& ps, std::size_t i, PrimBalls& out) {
  const kernel::Sphere& s = ps.spheres.at(i);
  out[0] = {v3(s.center), s.radius};
  return 1;
}
int curve_balls(const PackedScene& ps, std::size_t i, PrimBalls& out) {
  const kernel::Curve& c = ps.curves.at(i);
  const float* p[4] = {c.p0, c.p1, c.p2, c.p3};
  for (std::size_t k = 0; k < 4; ++k) out[k] = {v3(p[k]), c.radius};
  return 4;
}

template <auto Array>
std::size_t bytes_of(const PackedScene& ps) {
  return (ps.*Array).size() * sizeof((ps.*Array)[0]);
}

// isect_factor: measured on the cpu backend with the bear fur (docs/methods.md): the robust
// phantom curve costs about six capsule calls; round cones a little more than capsules.
constexpr BvhPrimRow rows[] = {
    {PrimType::Triangle, MASQ_PRIM_TRIANGLE, &KernelFeatures::triangles, 0.7, pack_triangles, triangle_balls,
     bytes_of<&PackedScene::triangles>},
    {PrimType::Capsule, MASQ_PRIM_CAPSULE, &KernelFeatures::capsules, 1.0, pack_capsules, capsule_balls,
     bytes_of<&PackedScene::capsules>},
    {PrimType::RoundCone, MASQ_PRIM_ROUND_CONE, &KernelFeatures::round_cones, 1.1, pack_round_cones,
     round_cone_balls, bytes_of<&PackedScene::round_cones>},
    {PrimType::Sphere, MASQ_PRIM_SPHERE, &KernelFeatures::spheres, 0.6, pack_spheres, sphere_balls,
     bytes_of<&PackedScene::spheres>},
    {PrimType::Curve, MASQ_PRIM_CURVE, &KernelFeatures::curves, 6.0, pack_curves, curve_balls,
     bytes_of<&PackedScene::curves>},
};
static_assert(one_row_per_prim_type(rows), "bvh prim rows: one row per PrimType, in enum order");
static_assert(std::size(rows) == MASQ_PRIM_TYPE_COUNT, "bvh prim rows: one row per MASQ_PRIM_* id");
constexpr bool kernel_ids_in_order() {
  for (std::size_t i = 0; i < std::size(rows); ++i)
    if (rows[i].kernel_type != int(i)) return false;
  return true;
}
static_assert(kernel_ids_in_order(), "bvh prim rows: row i has MASQ_PRIM_* id i");

} // namespace

const BvhPrimRow& bvh_prim_row(PrimType t) {
  const auto i = static_cast<std::size_t>(t);
  if (i >= std::size(rows)) throw Error("bvh: primitive type " + std::to_string(i) + " has no row");
  return rows[i];
}

const BvhPrimRow& bvh_prim_row(int kernel_type) {
  if (kernel_type < 0 || kernel_type >= int(std::size(rows)))
    throw Error("bvh: kernel primitive type " + std::to_string(kernel_type) + " has no row");
  return rows[std::size_t(kernel_type)];
}

const ScenePrimRow& scene_prim_row_of_kernel_type(int kernel_type) {
  return scene_prim_row(bvh_prim_row(kernel_type).type);
}

} // namespace masq
