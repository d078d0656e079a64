// The in-memory scene every loader and generator produces: geometries of one primitive
// type each, placed by instances with affine transforms, and a camera.
#pragma once
#include "masq/names.h"
#include <array>
#include <glm/glm.hpp>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

namespace masq {

enum class PrimType { Triangle, Capsule, RoundCone, Sphere, Curve, Ribbon };

// A primitive type's row: its one name (options, files, output and messages), help, and
// the older name users may still type (the JSON scene format's and the CLI's "cone").
struct PrimTypeRow {
  PrimType value;
  const char* name;
  const char* help;
  const char* alias;
};
inline constexpr PrimTypeRow prim_type_rows[] = {
    {PrimType::Triangle, "triangle", "watertight triangles", nullptr},
    {PrimType::Capsule, "capsule", "a segment swept by a ball", nullptr},
    {PrimType::RoundCone, "round_cone", "the hull of two balls, Han et al.'s link", "cone"},
    {PrimType::Sphere, "sphere", "a ball", nullptr},
    {PrimType::Curve, "curve", "cubic Bezier swept by a ball", nullptr},
    {PrimType::Ribbon, "ribbon", "a flat strip along a segment, facing its normal", nullptr},
};
inline constexpr NameTable prim_type_table{"primitive type", prim_type_rows};
inline constexpr std::size_t prim_type_count = std::size(prim_type_rows);

// True when `rows` holds exactly one row per primitive type, row i for PrimType(i): every
// layer's table of primitive types static_asserts it, so a new type cannot miss a row.
// A row names its type in `type` (or `value`, as NameTable rows do).
template <class Row, std::size_t N>
constexpr bool one_row_per_prim_type(const Row (&rows)[N]) {
  if (N != prim_type_count) return false;
  for (std::size_t i = 0; i < N; ++i) {
    if constexpr (requires { rows[i].type; }) {
      if (rows[i].type != static_cast<PrimType>(i)) return false;
    } else {
      if (rows[i].value != static_cast<PrimType>(i)) return false;
    }
  }
  return true;
}
static_assert(one_row_per_prim_type(prim_type_rows), "prim_type_rows: one row per PrimType, in enum order");
inline const char* prim_type_name(PrimType t) { return prim_type_table.name(t); } // for messages
inline const char* prim_type_key(PrimType t) { return prim_type_table.name(t); }  // for options and files
inline PrimType parse_prim_type(std::string_view key) { return prim_type_table.parse(key); } // throws masq::Error

struct CapsulePrim {
  glm::vec3 a;
  glm::vec3 b;
  float radius;
};

// Convex hull of the spheres (a, ra) and (b, rb) (Han et al.'s "link").
struct RoundConePrim {
  glm::vec3 a;
  float ra;
  glm::vec3 b;
  float rb;
};

struct SpherePrim {
  glm::vec3 center;
  float radius;
};

// Cubic Bezier curve swept by a sphere of constant radius (round ends).
struct CurvePrim {
  std::array<glm::vec3, 4> p;
  float radius;
};

// Flat linear ribbon, normal oriented: the planar strip through the segment p0-p1 of
// half-width r0 at p0 and r1 at p1 along normalize(cross(n, p1 - p0)) (kernels/layout.h,
// Ribbon). n need not be unit length; a zero n or one along the axis gives no surface.
struct RibbonPrim {
  glm::vec3 p0;
  float r0;
  glm::vec3 p1;
  float r1;
  glm::vec3 n;
};

struct Geometry {
  PrimType type = PrimType::Triangle;
  std::vector<glm::vec3> vertices;      // triangles: vertex positions
  std::vector<glm::uvec3> triangles;    // triangles: vertex indices
  std::vector<CapsulePrim> capsules;    // capsules
  std::vector<RoundConePrim> round_cones;     // round cones
  std::vector<SpherePrim> spheres;      // spheres
  std::vector<CurvePrim> curves;        // cubic curves
  std::vector<RibbonPrim> ribbons;      // flat ribbons
  std::size_t primitive_count() const; // the size of its type's array (scenes/prim_table.h)
};

// object -> world: p_world = linear * p_object + translation (double precision; the GPU
// copy is rounded to fp32 by the accel builder).
struct Affine3 {
  glm::dmat3 linear{1.0};
  glm::dvec3 translation{0.0};
  glm::dvec3 apply_point(const glm::dvec3& p) const { return linear * p + translation; }
  bool is_identity() const { return linear == glm::dmat3(1.0) && translation == glm::dvec3(0.0); }
};

struct Instance {
  std::uint32_t geometry = 0;
  Affine3 object_to_world;
};

struct Camera {
  glm::dvec3 eye{0.0, 0.0, -5.0};
  glm::dvec3 target{0.0, 0.0, 0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double fov_y_deg = 40.0;      // perspective
  bool orthographic = false;
  double ortho_height = 2.0;    // orthographic: height of the view in world units
};

struct Scene {
  std::string name;
  std::vector<Geometry> geometries;
  std::vector<Instance> instances;
  Camera camera;
  std::size_t primitive_count() const;
};

// The farthest a primitive may reach from the origin, |coordinate| + radius, in object
// and in world space: 2^60. A difference of two points of the scene is then below 2^61 per
// axis, and the intersectors' largest sums of squared distances (3 axes, with a factor of
// 16 for their products: 3 * 16 * 2^122 < 2^128) stay below FLT_MAX; at 1e19 they overflow
// and every ray misses (docs/robustness.md, "Scene range").
inline constexpr double kMaxSceneReach = 1152921504606846976.0; // 2^60

// Throws masq::Error naming the offending geometry/primitive/instance: out-of-range
// indices, NaN/Inf coordinates, negative or NaN radii, singular or non-finite
// transforms, primitives beyond kMaxSceneReach, empty scenes. Zero-length capsules (spheres) and zero-radius capsules
// (no surface, never hit) are allowed and documented.
void validate_scene(const Scene& scene);

} // namespace masq
