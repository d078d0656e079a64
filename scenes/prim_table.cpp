#include "scenes/prim_table.h"
#include "scenes/reserve_more.h"
#include "masq/error.h"
#include "scenes/generators.h"
#include "scenes/strand_generators.h"
#include <algorithm>
#include <iterator>
#include <random>
#include <cmath>
#include <string>

namespace masq {

namespace {

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string where(std::size_t g, const char* what, std::size_t i) {
  return "geometry " + std::to_string(g) + " " + what + " " + std::to_string(i);
}

void check_radius(float r, std::size_t g, const char* what, std::size_t i) {
  if (!std::isfinite(r) || r < 0.0f)
    throw Error("scene: " + where(g, what, i) + " has radius " + std::to_string(r) + " (must be finite and >= 0)");
}

void check_point(const glm::vec3& p, std::size_t g, const char* what, std::size_t i) {
  if (!finite3(p)) throw Error("scene: " + where(g, what, i) + " has a non-finite point");
}

template <auto Array>
std::size_t count_of(const Geometry& g) {
  return (g.*Array).size();
}
template <auto Array>
bool holds(const Geometry& g) {
  return !(g.*Array).empty();
}

void validate_triangles(const Geometry& geo, std::size_t g) {
  for (std::size_t i = 0; i < geo.vertices.size(); ++i)
    if (!finite3(geo.vertices[i])) throw Error("scene: " + where(g, "vertex", i) + " is not finite");
  for (std::size_t i = 0; i < geo.triangles.size(); ++i) {
    const glm::uvec3& t = geo.triangles[i];
    if (t.x >= geo.vertices.size() || t.y >= geo.vertices.size() || t.z >= geo.vertices.size())
      throw Error("scene: " + where(g, "triangle", i) + " indexes a vertex beyond " + std::to_string(geo.vertices.size()));
  }
}
void validate_capsules(const Geometry& geo, std::size_t g) {
  for (std::size_t i = 0; i < geo.capsules.size(); ++i) {
    const CapsulePrim& c = geo.capsules[i];
    if (!finite3(c.a) || !finite3(c.b)) throw Error("scene: " + where(g, "capsule", i) + " has a non-finite endpoint");
    check_radius(c.radius, g, "capsule", i);
  }
}
void validate_round_cones(const Geometry& geo, std::size_t g) {
  for (std::size_t i = 0; i < geo.round_cones.size(); ++i) {
    const RoundConePrim& c = geo.round_cones[i];
    check_point(c.a, g, "round cone", i);
    check_point(c.b, g, "round cone", i);
    check_radius(c.ra, g, "round cone", i);
    check_radius(c.rb, g, "round cone", i);
  }
}
void validate_spheres(const Geometry& geo, std::size_t g) {
  for (std::size_t i = 0; i < geo.spheres.size(); ++i) {
    check_point(geo.spheres[i].center, g, "sphere", i);
    check_radius(geo.spheres[i].radius, g, "sphere", i);
  }
}
void validate_curves(const Geometry& geo, std::size_t g) {
  for (std::size_t i = 0; i < geo.curves.size(); ++i) {
    for (const glm::vec3& p : geo.curves[i].p) check_point(p, g, "curve", i);
    check_radius(geo.curves[i].radius, g, "curve", i);
  }
}

void validate_ribbons(const Geometry& geo, std::size_t g) {
  for (std::size_t i = 0; i < geo.ribbons.size(); ++i) {
    const RibbonPrim& r = geo.ribbons[i];
    check_point(r.p0, g, "ribbon", i);
    check_point(r.p1, g, "ribbon", i);
    if (!finite3(r.n)) throw Error("scene: " + where(g, "ribbon", i) + " has a non-finite normal");
    check_radius(r.r0, g, "ribbon", i);
    check_radius(r.r1, g, "ribbon", i);
  }
}

int triangle_balls(const Geometry& g, std::size_t prim, PrimBalls& out) {
  const glm::uvec3& t = g.triangles.at(prim);
  for (int k = 0; k < 3; ++k) out[std::size_t(k)] = {g.vertices.at(t[k]), 0.0f};
  return 3;
}
int capsule_balls(const Geometry& g, std::size_t prim, PrimBalls& out) {
  const CapsulePrim& c = g.capsules.at(prim);
  out[0] = {c.a, c.radius};
  out[1] = {c.b, c.radius};
  return 2;
}
int round_cone_balls(const Geometry& g, std::size_t prim, PrimBalls& out) {
  const RoundConePrim& c = g.round_cones.at(prim);
  out[0] = {c.a, c.ra};
  out[1] = {c.b, c.rb};
  return 2;
}
int sphere_balls(const Geometry& g, std::size_t prim, PrimBalls& out) {
  const SpherePrim& s = g.spheres.at(prim);
  out[0] = {s.center, s.radius};
  return 1;
}
int curve_balls(const Geometry& g, std::size_t prim, PrimBalls& out) { // the control points' balls
  const CurvePrim& c = g.curves.at(prim);
  for (std::size_t k = 0; k < 4; ++k) out[k] = {c.p[k], c.radius};
  return 4;
}

// A ribbon lies in the round cone of its end balls (its half-width at s is r(s), the
// cone's radius there is at least that): the hull, clipping and OBBs are conservative
// without a shape of their own, at the price of the ribbon's thickness direction.
int ribbon_balls(const Geometry& g, std::size_t prim, PrimBalls& out) {
  const RibbonPrim& r = g.ribbons.at(prim);
  out[0] = {r.p0, r.r0};
  out[1] = {r.p1, r.r1};
  return 2;
}

// ---- strands

void capsule_segment(Geometry& g, const glm::vec3& a, float ra, const glm::vec3& b, float rb) {
  g.capsules.push_back({a, b, 0.5f * (ra + rb)});
}
void round_cone_segment(Geometry& g, const glm::vec3& a, float ra, const glm::vec3& b, float rb) {
  g.round_cones.push_back({a, ra, b, rb});
}

template <auto Array>
void reserve_more(Geometry& g, std::size_t n) {
  (g.*Array).reserve((g.*Array).size() + n);
}

template <auto AddSegment>
void segment_piece(Geometry& g, const Strand& s, std::size_t i) {
  AddSegment(g, glm::vec3(s.points[i]), float(s.radii[i]), glm::vec3(s.points[i + 1]), float(s.radii[i + 1]));
}
void curve_piece(Geometry& g, const Strand& s, std::size_t i) {
  const std::size_t n = s.points.size();
  const glm::dvec3& p0 = s.points[i > 0 ? i - 1 : i];
  const glm::dvec3& p3 = s.points[i + 2 < n ? i + 2 : i + 1];
  CurvePrim c{};
  c.p = {glm::vec3(s.points[i]), glm::vec3(s.points[i] + (s.points[i + 1] - p0) / 6.0),
         glm::vec3(s.points[i + 1] - (p3 - s.points[i]) / 6.0), glm::vec3(s.points[i + 1])};
  c.radius = 0.5f * (float(s.radii[i]) + float(s.radii[i + 1]));
  g.curves.push_back(c);
}

void capsule_bundle_strand(Geometry& g, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3&, float r) {
  g.capsules.push_back({glm::vec3(a), glm::vec3(b), r});
}
void round_cone_bundle_strand(Geometry& g, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3&, float r) {
  g.round_cones.push_back({glm::vec3(a), r, glm::vec3(b), 0.5f * r});
}
void curve_bundle_strand(Geometry& g, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& bend, float r) {
  CurvePrim cv{};
  cv.p = {glm::vec3(a), glm::vec3(a + (b - a) / 3.0 + bend), glm::vec3(a + 2.0 * (b - a) / 3.0 - bend), glm::vec3(b)};
  cv.radius = r;
  g.curves.push_back(cv);
}
void sphere_bundle_strand(Geometry& g, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3&, float r) {
  for (int k = 0; k < 8; ++k) g.spheres.push_back({glm::vec3(a + (b - a) * ((k + 0.5) / 8.0)), 3.0f * r});
}

// A bundle strand as a ribbon: its normal along the bend (perpendicular to the axis)
// or, for a straight bundle, any perpendicular, so the ribbons face across the bundle.
void ribbon_bundle_strand(Geometry& g, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& bend, float r) {
  glm::dvec3 axis = b - a;
  glm::dvec3 n = glm::length(bend) > 0 ? bend : glm::cross(axis, std::abs(axis.x) < std::abs(axis.y) ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0));
  g.ribbons.push_back({glm::vec3(a), r, glm::vec3(b), r, glm::vec3(n)});
}

Geometry random_ribbons(int count, float min_radius, float max_radius, double extent, std::uint64_t seed) {
  Geometry g = make_random_cones(count, min_radius, max_radius, extent, seed); // the same axes and radii
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ull);
  std::normal_distribution<double> gauss;
  g.type = PrimType::Ribbon;
  for (const RoundConePrim& c : g.round_cones)
    g.ribbons.push_back({c.a, c.ra, c.b, c.rb, glm::vec3(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)))});
  g.round_cones.clear();
  return g;
}

Geometry random_mesh(int count, float, float, double extent, std::uint64_t seed) {
  return make_random_mesh(count, extent, seed);
}

// ---- the kernels' arrays (fp32 copies; the values the kernels and the bvh see)

void copy3(float* dst, const glm::vec3& v) {
  for (int k = 0; k < 3; ++k) dst[k] = v[k];
}
glm::vec3 v3(const float* p) { return {p[0], p[1], p[2]}; }

int pack_triangles(const Geometry& g, KernelPrimArrays& ps) {
  const int first = int(ps.triangles.size());
  reserve_more(ps.triangles, g.triangles.size());
  for (const glm::uvec3& t : g.triangles) {
    kernel::Triangle kt{};
    copy3(kt.v0, g.vertices[t.x]);
    copy3(kt.v1, g.vertices[t.y]);
    copy3(kt.v2, g.vertices[t.z]);
    ps.triangles.push_back(kt);
  }
  return first;
}
int pack_capsules(const Geometry& g, KernelPrimArrays& ps) {
  const int first = int(ps.capsules.size());
  reserve_more(ps.capsules, g.capsules.size());
  for (const CapsulePrim& c : g.capsules) {
    kernel::Capsule kc{};
    copy3(kc.a, c.a);
    copy3(kc.b, c.b);
    kc.radius = c.radius;
    ps.capsules.push_back(kc);
  }
  return first;
}
int pack_round_cones(const Geometry& g, KernelPrimArrays& ps) {
  const int first = int(ps.round_cones.size());
  reserve_more(ps.round_cones, g.round_cones.size());
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
int pack_spheres(const Geometry& g, KernelPrimArrays& ps) {
  const int first = int(ps.spheres.size());
  reserve_more(ps.spheres, g.spheres.size());
  for (const SpherePrim& sp : g.spheres) {
    kernel::Sphere ks{};
    copy3(ks.center, sp.center);
    ks.radius = sp.radius;
    ps.spheres.push_back(ks);
  }
  return first;
}
int pack_curves(const Geometry& g, KernelPrimArrays& ps) {
  const int first = int(ps.curves.size());
  reserve_more(ps.curves, g.curves.size());
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

// The normal goes to the kernels unit length (normalised in double), so their cross
// products stay of the size of the ribbon whatever |n| the user gave; a zero n stays 0.
int pack_ribbons(const Geometry& g, KernelPrimArrays& ps) {
  const int first = int(ps.ribbons.size());
  reserve_more(ps.ribbons, g.ribbons.size());
  for (const RibbonPrim& r : g.ribbons) {
    kernel::Ribbon kr{};
    copy3(kr.p0, r.p0);
    copy3(kr.p1, r.p1);
    kr.r0 = r.r0;
    kr.r1 = r.r1;
    const glm::dvec3 n(r.n);
    const double len = glm::length(n);
    copy3(kr.n, len > 0 ? glm::vec3(n / len) : glm::vec3(0.0f));
    ps.ribbons.push_back(kr);
  }
  return first;
}

int kernel_triangle_balls(const KernelPrimArrays& ps, std::size_t i, PrimBalls& out) {
  const kernel::Triangle& t = ps.triangles.at(i);
  out[0] = {v3(t.v0), 0.0f};
  out[1] = {v3(t.v1), 0.0f};
  out[2] = {v3(t.v2), 0.0f};
  return 3;
}
int kernel_capsule_balls(const KernelPrimArrays& ps, std::size_t i, PrimBalls& out) {
  const kernel::Capsule& c = ps.capsules.at(i);
  out[0] = {v3(c.a), c.radius};
  out[1] = {v3(c.b), c.radius};
  return 2;
}
int kernel_round_cone_balls(const KernelPrimArrays& ps, std::size_t i, PrimBalls& out) {
  const kernel::RoundCone& c = ps.round_cones.at(i);
  out[0] = {v3(c.a), c.ra};
  out[1] = {v3(c.b), c.rb};
  return 2;
}
int kernel_sphere_balls(const KernelPrimArrays& ps, std::size_t i, PrimBalls& out) {
  const kernel::Sphere& s = ps.spheres.at(i);
  out[0] = {v3(s.center), s.radius};
  return 1;
}
int kernel_curve_balls(const KernelPrimArrays& ps, std::size_t i, PrimBalls& out) {
  const kernel::Curve& c = ps.curves.at(i);
  const float* p[4] = {c.p0, c.p1, c.p2, c.p3};
  for (std::size_t k = 0; k < 4; ++k) out[k] = {v3(p[k]), c.radius};
  return 4;
}

int kernel_ribbon_balls(const KernelPrimArrays& ps, std::size_t i, PrimBalls& out) {
  const kernel::Ribbon& r = ps.ribbons.at(i);
  out[0] = {v3(r.p0), r.r0};
  out[1] = {v3(r.p1), r.r1};
  return 2;
}

template <auto Array>
std::size_t bytes_of(const KernelPrimArrays& ps) {
  return (ps.*Array).size() * sizeof((ps.*Array)[0]);
}

// isect_factor: measured on the cpu backend with the bear fur (docs/methods.md): the robust
// phantom curve costs about six capsule calls; round cones a little more than capsules.
// The ribbon (a plane crossing and two range tests) is priced as a triangle (not measured).
//  type, mesh, oriented, shape, strand_file_type, singular, the functions, then the kernels' columns
// (order_free: the capsule's and the curves' crossings, docs/kernels.md "Packets of camera rays")
constexpr ScenePrimRow rows[] = {
    {PrimType::Triangle, true, false, PrimShape::Triangle, PrimType::Capsule, "triangle", count_of<&Geometry::triangles>,
     holds<&Geometry::triangles>, validate_triangles, triangle_balls, nullptr, reserve_more<&Geometry::triangles>,
     nullptr, nullptr, random_mesh,
     MASQ_PRIM_TRIANGLE, 0.7, false, pack_triangles, kernel_triangle_balls, bytes_of<&KernelPrimArrays::triangles>},
    {PrimType::Capsule, false, true, PrimShape::Segment, PrimType::Capsule, "capsule", count_of<&Geometry::capsules>,
     holds<&Geometry::capsules>, validate_capsules, capsule_balls, capsule_segment, reserve_more<&Geometry::capsules>,
     segment_piece<capsule_segment>, capsule_bundle_strand, make_random_capsules,
     MASQ_PRIM_CAPSULE, 1.0, true, pack_capsules, kernel_capsule_balls, bytes_of<&KernelPrimArrays::capsules>},
    {PrimType::RoundCone, false, true, PrimShape::Segment, PrimType::RoundCone, "round cone",
     count_of<&Geometry::round_cones>, holds<&Geometry::round_cones>, validate_round_cones, round_cone_balls,
     round_cone_segment, reserve_more<&Geometry::round_cones>, segment_piece<round_cone_segment>,
     round_cone_bundle_strand, make_random_cones,
     MASQ_PRIM_ROUND_CONE, 1.1, false, pack_round_cones, kernel_round_cone_balls, bytes_of<&KernelPrimArrays::round_cones>},
    {PrimType::Sphere, false, false, PrimShape::Ball, PrimType::Capsule, "sphere", count_of<&Geometry::spheres>,
     holds<&Geometry::spheres>, validate_spheres, sphere_balls, nullptr, reserve_more<&Geometry::spheres>, nullptr,
     sphere_bundle_strand, make_random_spheres,
     MASQ_PRIM_SPHERE, 0.6, false, pack_spheres, kernel_sphere_balls, bytes_of<&KernelPrimArrays::spheres>},
    {PrimType::Curve, false, true, PrimShape::Bezier, PrimType::RoundCone, "curve", count_of<&Geometry::curves>,
     holds<&Geometry::curves>, validate_curves, curve_balls, nullptr, reserve_more<&Geometry::curves>, curve_piece,
     curve_bundle_strand, make_random_curves,
     MASQ_PRIM_CURVE, 6.0, true, pack_curves, kernel_curve_balls, bytes_of<&KernelPrimArrays::curves>},
    {PrimType::Ribbon, false, true, PrimShape::Segment, PrimType::Capsule, "ribbon", count_of<&Geometry::ribbons>,
     holds<&Geometry::ribbons>, validate_ribbons, ribbon_balls, nullptr, reserve_more<&Geometry::ribbons>, nullptr,
     ribbon_bundle_strand, random_ribbons,
     MASQ_PRIM_RIBBON, 0.7, false, pack_ribbons, kernel_ribbon_balls, bytes_of<&KernelPrimArrays::ribbons>},
};
static_assert(one_row_per_prim_type(rows), "scene_prim_rows: one row per PrimType, in enum order");
static_assert(std::size(rows) == MASQ_PRIM_TYPE_COUNT, "scene_prim_rows: one row per MASQ_PRIM_* id");
constexpr bool kernel_ids_in_order() {
  for (std::size_t i = 0; i < std::size(rows); ++i)
    if (rows[i].kernel_type != int(i)) return false;
  return true;
}
static_assert(kernel_ids_in_order(), "scene_prim_rows: row i has MASQ_PRIM_* id i");

} // namespace

const ScenePrimRow& scene_prim_row(PrimType t) {
  const auto i = static_cast<std::size_t>(t);
  if (i >= prim_type_count) throw Error("scene: primitive type " + std::to_string(i) + " has no row");
  return rows[i];
}

const ScenePrimRow& scene_prim_row_of_kernel_type(int kernel_type) {
  if (kernel_type < 0 || kernel_type >= int(std::size(rows)))
    throw Error("scene: kernel primitive type " + std::to_string(kernel_type) + " has no row");
  return rows[std::size_t(kernel_type)];
}

std::string strand_type_names() {
  std::string names;
  for (const ScenePrimRow& row : rows)
    if (row.add_segment) names += (names.empty() ? "" : " or ") + std::string(row.singular) + "s";
  return names;
}

float prim_max_radius(const Geometry& g, std::size_t prim) {
  PrimBalls b;
  const int n = scene_prim_row(g.type).balls(g, prim, b);
  float r = 0.0f;
  for (int i = 0; i < n; ++i) r = std::max(r, b[std::size_t(i)].radius);
  return r;
}

} // namespace masq
