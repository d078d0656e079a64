/// @file masq/types.h
/// Plain value types of the public API: vectors, rays, hits, primitives, transforms, and
/// the build options with their name tables (masq/names.h).
/// Rays, hits and counters have the same 32/48/16-byte layouts as the kernels' own
/// structs, so a batch crosses into a backend with one copy.
#pragma once
#include "masq/names.h"
#include <array>
#include <cstdint>

namespace masq::api {

/// A point or direction in single precision.
struct Vec3 {
  float x = 0, y = 0, z = 0;
};

/// How thin primitives are bounded in the acceleration structure (docs/methods.md).
/// Each value's name and meaning: method_table.
enum class Method { Ref, Masq, Cluster, Auto };

inline constexpr NameRow<Method> method_rows[] = {
    {Method::Ref, "ref", "one BLAS of primitive AABBs per geometry: the masquerade paper's reference method"},
    {Method::Masq, "masq",
     "one TLAS instance per thin primitive, its transform mapping the unit box onto the primitive's OBB"},
    {Method::Cluster, "cluster",
     "one TLAS instance per cluster of similarly oriented thin primitives, its BLAS built in the cluster's frame"},
    {Method::Auto, "auto",
     "builds ref, masq, cluster and a per-cluster mix and keeps the one a whole-structure cost model prices lowest"},
};
inline constexpr NameTable method_table{"method", method_rows};

/// Which binary BVH builder makes the hierarchies (before they are collapsed to wide
/// nodes). Each value's name, meaning and parts: builder_table; docs/builders.md says
/// what each costs and gains.
enum class Builder { Sah, Sbvh, SahReinsert, SbvhReinsert, Sah4, SahPriced };

/// A builder's row: its name and help, and the parts it is made of.
struct BuilderRow {
  Builder value;
  const char* name;
  const char* help;
  bool spatial_splits; ///< spatial splits with clipped references in every BLAS over primitives
  bool reinsertion;    ///< insertion optimisation of the TLAS and every BLAS
  int leaf_block;      ///< a BLAS leaf over primitives is priced per block of this many primitives
  bool priced_isect;   ///< a BLAS leaf primitive is priced at its type's intersector cost (else at 1)
};

// Columns: value, name, help, spatial_splits, reinsertion, leaf_block, priced_isect.
inline constexpr BuilderRow builder_rows[] = {
    {Builder::Sah, "sah", "binned SAH", false, false, 1, false},
    {Builder::Sbvh, "sbvh", "binned SAH plus spatial splits in every BLAS over primitives, after Stich et al. 2009",
     true, false, 1, false},
    {Builder::SahReinsert, "sah+reinsert",
     "binned SAH, then insertion optimisation of the TLAS and every BLAS, after Bittner et al. 2013",
     false, true, 1, false},
    {Builder::SbvhReinsert, "sbvh+reinsert", "spatial splits, then insertion optimisation",
     true, true, 1, false},
    {Builder::Sah4, "sah4",
     "binned SAH pricing each BLAS leaf per block of four primitives: fuller leaves, for the cpu's four-lane "
     "capsule test",
     false, false, 4, false},
    {Builder::SahPriced, "sah-priced",
     "binned SAH pricing each BLAS leaf primitive at its type's intersector cost: mostly one-primitive leaves, "
     "fewer intersector calls, more nodes",
     false, false, 1, true},
};
inline constexpr NameTable builder_table{"builder", builder_rows};

/// Which intersectors and box test the kernels use. Each value's name and meaning: mode_table.
enum class Mode { Robust, Fast };

inline constexpr NameRow<Mode> mode_rows[] = {
    {Mode::Robust, "robust", "fp32-hardened intersectors and a conservatively padded box test"},
    {Mode::Fast, "fast",
     "the intersectors as their papers write them and an unpadded box test; can miss silhouette hits"},
};
inline constexpr NameTable mode_table{"mode", mode_rows};

/// Which intersector cubic curves get (in either Mode). Each value's name and meaning:
/// curve_isect_table.
enum class CurveIsect { Phantom, Roving };

inline constexpr NameRow<CurveIsect> curve_isect_rows[] = {
    {CurveIsect::Phantom, "phantom",
     "fast mode: Reshetov & Luebke's phantom iteration; robust mode: certified subdivision of the whole curve"},
    {CurveIsect::Roving, "roving",
     "roving capsules (after Reshetov & Hart 2024): clip the curve to where its balls can meet the ray, then "
     "capsules on what is left"},
};
inline constexpr NameTable curve_isect_table{"curve intersector", curve_isect_rows};

/// The order in which an occlusion query (Query::Any) takes a BLAS node's hit inner
/// children. It decides only how soon the query meets an occluder: whether a ray is
/// occluded is the same either way. Each value's meaning: blas_occlusion_table.
enum class BlasOcclusion { Nearest, StartsLast };

inline constexpr NameRow<BlasOcclusion> blas_occlusion_rows[] = {
    {BlasOcclusion::Nearest, "nearest", "nearest first, as closest-hit queries take them"},
    {BlasOcclusion::StartsLast, "starts-last",
     "those the ray enters after t_min first, those it starts in last, each group in slot order; faster on thin "
     "hair in one BLAS, whose shadow rays mostly leave the boxes around their origin"},
};
inline constexpr NameTable blas_occlusion_table{"BLAS occlusion order", blas_occlusion_rows};

/// How the BVH nodes of the TLAS and every BLAS are stored (same hits either way). Each
/// value's name and layout: node_format_table.
enum class NodeFormat { W4, W8, Q8, O4 };

inline constexpr NameRow<NodeFormat> node_format_rows[] = {
    {NodeFormat::W4, "w4", "4 children, float boxes, 128 B per node"},
    {NodeFormat::W8, "w8", "8 children, float boxes, 256 B per node"},
    {NodeFormat::Q8, "q8", "8 children, boxes quantised conservatively to 8 bits per plane, 80 B per node"},
    {NodeFormat::O4, "o4", "4 children, float boxes in the node's own rotated frame (8-bit rotation), 144 B per node"},
};
inline constexpr NameTable node_format_table{"node format", node_format_rows};

/// A ray. dir need not be unit length; t is measured in units of dir. Only hits with
/// tmin <= t <= tmax count.
struct Ray {
  Vec3 org;
  float tmin = 0.0f;
  Vec3 dir{0, 0, 1};
  float tmax = 3.0e38f;
};

/// The closest hit of one ray. prim < 0 means no hit.
struct Hit {
  float t = 0;
  std::int32_t prim = -1;     ///< primitive index within its geometry
  std::int32_t geometry = -1; ///< geometry id (as returned by Scene::add_*)
  std::int32_t instance = -1; ///< instance id (as returned by Scene::add_instance)
  Vec3 normal;                ///< unit geometric normal in world space
  float u = 0, v = 0;         ///< triangle barycentrics; strands: axial/curve parameter in u
  float reserved[3] = {0, 0, 0};
  bool hit() const { return prim >= 0; }
};

/// Per-ray traversal counters (filled only when asked for; costs some speed).
struct RayStats {
  std::int32_t tlas_nodes = 0;  ///< TLAS wide-node visits
  std::int32_t blas_nodes = 0;  ///< BLAS wide-node visits, masquerade unit-box tests included
  std::int32_t transforms = 0;  ///< instance ray transforms
  std::int32_t isect_calls = 0; ///< primitive intersector calls
};

/// Capsule: the points within radius of the segment a-b.
struct Capsule {
  Vec3 a, b;
  float radius = 0;
};

/// Round cone (Han et al.'s "link"): convex hull of the spheres (a, ra) and (b, rb).
struct RoundCone {
  Vec3 a;
  float ra = 0;
  Vec3 b;
  float rb = 0;
};

struct Sphere {
  Vec3 center;
  float radius = 0;
};

/// Cubic Bezier curve (control points p[0..3]) swept by a ball of constant radius.
struct Curve {
  std::array<Vec3, 4> p{};
  float radius = 0;
};

/// Flat linear ribbon, normal oriented: the planar strip through the segment p0-p1 whose
/// half-width runs from r0 at p0 to r1 at p1 along normalize(cross(n, p1 - p0)), so that
/// its surface faces n (Embree's and OptiX's normal-oriented ribbons, linear basis). Flat
/// ends, no thickness. n need not be unit length; a zero n, or one within 2^-12 rad of
/// the axis, gives no surface (never hit).
struct Ribbon {
  Vec3 p0;
  float r0 = 0;
  Vec3 p1;
  float r1 = 0;
  Vec3 n{0, 0, 1};
};

/// Affine object-to-world transform, row-major 3x4: world = m[.][0..2] * p + m[.][3].
struct Transform {
  double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
  static Transform identity() { return {}; }
  static Transform translation(double x, double y, double z) {
    Transform t;
    t.m[0][3] = x;
    t.m[1][3] = y;
    t.m[2][3] = z;
    return t;
  }
  static Transform scale(double sx, double sy, double sz) {
    Transform t;
    t.m[0][0] = sx;
    t.m[1][1] = sy;
    t.m[2][2] = sz;
    return t;
  }
};

} // namespace masq::api
