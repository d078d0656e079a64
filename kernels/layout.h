// GPU-visible structs, defined once for GLSL std430, OpenCL C and C++.
// Only 4-byte scalars and fixed arrays of them, each struct a multiple of 16 bytes, so
// all three languages agree without scalar-layout extensions. Sizes and offsets are
// checked by static asserts (C++ and OpenCL) and by a GLSL round-trip kernel test.
#ifndef MASQ_KERNEL_LAYOUT_H
#define MASQ_KERNEL_LAYOUT_H
#include "shim.h"

LAYOUT_NS_BEGIN

#define MASQ_WIDTH 4 // children per wide BVH node (node format w4)
#define MASQ_WIDTH8 8 // children per 8-wide node (formats w8 and q8)

// Node formats (docs/kernels.md, "Node formats"): one per scene, for the TLAS and every
// BLAS alike; the kernels are compiled for one (MASQ_NODE_FORMAT, kernels/variants.h).
#define MASQ_NODES_W4 0
#define MASQ_NODES_W8 1
#define MASQ_NODES_Q8 2
#define MASQ_NODES_O4 3

#define MASQ_NODE_FORMAT_COUNT 4 // the cpu units of MASQ_NODE_FORMAT (kernels/variant_table.h) cover them all

// Cubic-curve intersectors (the MASQ_CURVE_ISECT switch; host: CurveIsect).
#define MASQ_CURVE_PHANTOM 0
#define MASQ_CURVE_ROVING 1

// Primitive types. A geometry holds primitives of one type.
#define MASQ_PRIM_TRIANGLE 0
#define MASQ_PRIM_CAPSULE 1
#define MASQ_PRIM_ROUND_CONE 2
#define MASQ_PRIM_SPHERE 3
#define MASQ_PRIM_CURVE 4
#define MASQ_PRIM_RIBBON 5
#define MASQ_PRIM_TYPE_COUNT 6

// A 4-wide BVH node with structure-of-arrays child boxes (one slab test per axis for
// all children). Child slot i: count[i] > 0 is a leaf of count[i] references starting
// at child[i] in the reference array; count[i] == 0 is an inner node child[i];
// count[i] < 0 is an empty slot.
STRUCT_BEGIN(WideNode)
  float lo_x[MASQ_WIDTH];
  float hi_x[MASQ_WIDTH];
  float lo_y[MASQ_WIDTH];
  float hi_y[MASQ_WIDTH];
  float lo_z[MASQ_WIDTH];
  float hi_z[MASQ_WIDTH];
  int child[MASQ_WIDTH];
  int count[MASQ_WIDTH];
STRUCT_END(WideNode)

// The 8-wide float node (format w8): WideNode with 8 slots, same slot rules. 256 bytes.
STRUCT_BEGIN(WideNode8)
  float lo_x[MASQ_WIDTH8];
  float hi_x[MASQ_WIDTH8];
  float lo_y[MASQ_WIDTH8];
  float hi_y[MASQ_WIDTH8];
  float lo_z[MASQ_WIDTH8];
  float hi_z[MASQ_WIDTH8];
  int child[MASQ_WIDTH8];
  int count[MASQ_WIDTH8];
STRUCT_END(WideNode8)

// The quantised 8-wide node (format q8, after Ylitie, Karras and Laine 2017). Child
// boxes are 8-bit grid coordinates against the node's own frame: on axis k, plane q
// lies at origin[k] + q * 2^(e_k - 127), which fp32 evaluates exactly up to the one
// rounding of the sum (q * 2^e is exact), so fma or not gives the same value; the host
// (bvh/nodes/quant_node.cpp) rounds lo down and hi up and checks that decode. Bytes are packed
// into uints, byte j of a pair of words being slot j (slot j: word j / 4, bits 8 (j % 4)).
//  exps: bytes 0..2 the biased exponents e_x, e_y, e_z (1..254); byte 3 unused.
//  meta: per slot 0 = empty, 0x80 = inner node, 1..127 = leaf of that many references.
//  Inner children are the nodes child_base, child_base + 1, ... in slot order; leaf
//  references are contiguous from ref_base in slot order. 80 bytes.
#define MASQ_Q8_INNER 128u
#define MASQ_Q8_MAX_LEAF 127
STRUCT_BEGIN(QuantNode8)
  float origin[3];
  uint exps;
  int child_base;
  int ref_base;
  uint meta[2];
  uint qlo_x[2];
  uint qhi_x[2];
  uint qlo_y[2];
  uint qhi_y[2];
  uint qlo_z[2];
  uint qhi_z[2];
STRUCT_END(QuantNode8)

// The oriented 4-wide node (format o4, after Woop et al. 2014 and Kern et al. 2025's
// DOBB-BVH): a WideNode whose child boxes are in the node's own frame x' = M x, with M
// stored as nine signed 8-bit entries q (M = q / 128, exact in fp32; M need not be
// orthonormal, only the one the host fitted the boxes with). rot: byte j of word j / 4
// is entry (j / 3, j % 3), row-major. oriented == 0: an axis-aligned node (M is the
// identity, rot unused): tested exactly as a w4 node. The kernels pad the rotated test
// by the fp32 error of M o and M d (kernels/node_formats.h, docs/robustness.md). 144 B.
STRUCT_BEGIN(OrientedNode4)
  WideNode boxes;
  uint rot[3];
  uint oriented;
STRUCT_END(OrientedNode4)

// Word offsets of the node formats read as raw words (kernels/node_formats.h; GLSL
// binds the node array once, as words). Checked against the structs below.
#define MASQ_W8_WORDS 64
#define MASQ_W8_LO_X 0
#define MASQ_W8_HI_X 8
#define MASQ_W8_LO_Y 16
#define MASQ_W8_HI_Y 24
#define MASQ_W8_LO_Z 32
#define MASQ_W8_HI_Z 40
#define MASQ_W8_CHILD 48
#define MASQ_W8_COUNT 56
#define MASQ_Q8_WORDS 20
#define MASQ_Q8_ORIGIN 0
#define MASQ_Q8_EXPS 3
#define MASQ_Q8_CHILD_BASE 4
#define MASQ_Q8_REF_BASE 5
#define MASQ_Q8_META 6
#define MASQ_Q8_QLO_X 8
#define MASQ_Q8_QHI_X 10
#define MASQ_Q8_QLO_Y 12
#define MASQ_Q8_QHI_Y 14
#define MASQ_Q8_QLO_Z 16
#define MASQ_Q8_QHI_Z 18
#define MASQ_O4_WORDS 36
#define MASQ_O4_ROT 32 // the boxes: WideNode's words 0..31
#define MASQ_O4_ORIENTED 35

// One entry of the top-level structure (what a hardware TLAS instance is).
// world_to_object is a row-major 3x4 affine map (rows 0..2: x, y, z; column 3 the
// translation). blas_root >= 0: traverse that BLAS with the transformed ray.
// blas_root < 0: a masquerade instance: the transform maps the primitive's OBB onto
// the unit box [-1,1]^3, whose test is the whole BLAS; then the world-space
// intersector runs on primitive `prim` of geometry `geom`, in the frame of scene
// instance `scene_inst`. 64 bytes, as a hardware instance; masq's default packs a
// masquerade entry into a 32-byte MasqInstance instead (below).
// blas_root >= 0 and prim == MASQ_INST_CLUSTER: an oriented cluster (method cluster,
// docs/methods.md): the transform maps the world into the cluster's local frame, the
// BLAS boxes are the members' bounds in that frame (OBBs in the world), and the BLAS
// leaves' primitives are intersected with the world ray in scene instance
// `scene_inst`'s frame, as masquerade leaves are. Ordinary BLAS instances have prim -1.
#define MASQ_INST_CLUSTER (-2)
STRUCT_BEGIN(Instance)
  float world_to_object[12];
  int blas_root;
  int geom;
  int prim;
  int scene_inst;
STRUCT_END(Instance)

// A compact masquerade entry (docs/kernels.md, "Compact masquerade instances"): the
// same world -> unit-box map as a masquerade Instance in 32 bytes instead of 64, so
// that masq's memory stays within 1.5x ref's. TLAS leaves reference it by a negative
// ref r (entry ~r); refs >= 0 are Instances, so both kinds share one TLAS.
//  t:   the translation of the map, fp32, as verified by the host.
//  q01, q23: a rotation as a quaternion (x, y | z, w), 16-bit two's complement
//       integers (x in the low half of q01). The kernel forms N = |q|^2 R(q) with the
//       homogeneous formula in EXACT integer arithmetic (|N_ij| <= |q|^2 < 2^31), so
//       the decoded axes are exactly orthonormal whatever q's norm.
//  s01, s2_owner: per-axis scales sigma_x (low half of s01), sigma_y (high half),
//       sigma_z (high half of s2_owner) as bfloat16, i.e. the upper 16 bits of an fp32;
//       the host folds 1/|q|^2 into them. The low half of s2_owner is an index into
//       the MasqOwner table (geometry and scene instance).
// Linear part: M_ij = sigma_i * N_ji (M = diag(s) R^T), two roundings per entry and no
// addition, so fma contraction cannot change it: each entry is within two roundings of
// sigma_i * N_ji, and the host proves the primitive inside the unit box under every
// matrix that close (with a 2x margin; bvh/nodes/compact_instance.cpp).
#define MASQ_OWNER_MASK 0xFFFFu
#define MASQ_MAX_OWNERS 65536
STRUCT_BEGIN(MasqInstance)
  float t[3];
  int prim;
  uint q01;
  uint q23;
  uint s01;
  uint s2_owner;
STRUCT_END(MasqInstance)

// What compact masquerade entries share: their geometry and scene instance.
STRUCT_BEGIN(MasqOwner)
  int geom;
  int scene_inst;
  int pad[2];
STRUCT_END(MasqOwner)

// A scene instance's frame (what the user placed): world-to-object, row-major 3x4.
STRUCT_BEGIN(Frame)
  float world_to_object[12];
  float pad[4];
STRUCT_END(Frame)

// type: MASQ_PRIM_*; first: index of its first primitive in that type's array.
STRUCT_BEGIN(Geometry)
  int type;
  int first;
  int count;
  int pad;
STRUCT_END(Geometry)

STRUCT_BEGIN(Triangle)
  float v0[3];
  float v1[3];
  float v2[3];
  float pad[3];
STRUCT_END(Triangle)

// The primitive type whose BLAS leaves the cpu tests four at a time from its own
// leaf-ordered copy (kernels/traverse.h's intersect_leaf, host/cpu/leaf_capsules.h): one
// name for the kernel's test and the host's copy, which must agree.
#define MASQ_CPU_LEAF_COPY_TYPE MASQ_PRIM_CAPSULE
// The primitive type whose compact masquerade entries the cpu intersects from its own
// entry-ordered copy (kernels/traverse.h's TLAS walk, host/cpu/entry_curves.h): one name
// for the walk and the host's copy, which must agree.
#define MASQ_CPU_ENTRY_COPY_TYPE MASQ_PRIM_CURVE

// Constant-radius linear segment with spherical caps.
STRUCT_BEGIN(Capsule)
  float a[3];
  float radius;
  float b[3];
  float pad;
STRUCT_END(Capsule)

// Round cone (Han et al.'s "link"): the convex hull of the spheres (a, ra) and
// (b, rb). One sphere may contain the other (the primitive is then that sphere).
STRUCT_BEGIN(RoundCone)
  float a[3];
  float ra;
  float b[3];
  float rb;
STRUCT_END(RoundCone)

STRUCT_BEGIN(Sphere)
  float center[3];
  float radius;
STRUCT_END(Sphere)

// Cubic Bezier curve p0..p3 swept by a sphere of constant radius (round ends, as
// Embree's round curves), intersected with the phantom method of Reshetov & Luebke.
STRUCT_BEGIN(Curve)
  float p0[3];
  float radius;
  float p1[3];
  float pad1;
  float p2[3];
  float pad2;
  float p3[3];
  float pad3;
STRUCT_END(Curve)

// Flat linear ribbon, normal oriented (Embree's and OptiX's ribbons, linear basis): the
// planar strip through the axis p0 -> p1 whose half-width runs linearly from r0 to r1
// along the width direction normalize(cross(n, p1 - p0)), so its surface normal is n's
// part perpendicular to the axis. Flat ends, no thickness, two-sided. n is stored unit
// length (the host normalises it in double), so the kernels' products stay in range.
STRUCT_BEGIN(Ribbon)
  float p0[3];
  float r0;
  float p1[3];
  float r1;
  float n[3];
  float pad;
STRUCT_END(Ribbon)

// dir need not be unit length; t is in units of dir.
STRUCT_BEGIN(Ray)
  float org[3];
  float tmin;
  float dir[3];
  float tmax;
STRUCT_END(Ray)

// prim < 0: miss. normal: unit geometric normal in world space, facing the side the
// surface was hit from is NOT enforced (outward for capsules, winding for triangles).
// u, v: triangle barycentrics; capsule/round cone: (axial parameter in [0,1], 0);
// curve: (curve parameter in [0,1], 0); sphere: (0, 0); ribbon: (axial parameter in
// [0,1], signed width coordinate over the half-width there, in [-1,1]).
// fault != 0: the traversal stopped this ray instead of finishing it (a push onto a full
// stack, or a walk past its step budget: a cycle in the structure or data read wrong);
// the host turns any such ray into an error (host/trace_faults.h), so a user never sees
// one as a miss. fault = MASQ_FAULT_* | level << 8 (MASQ_LEVEL_*), fault_node the node
// the walk was at, fault_depth its stack depth then. All three are 0 otherwise.
#define MASQ_FAULT_STACK_FULL 1
#define MASQ_FAULT_STEP_BUDGET 2
#define MASQ_LEVEL_TLAS 0
#define MASQ_LEVEL_BLAS 1
#define MASQ_LEVEL_BV 2
STRUCT_BEGIN(Hit)
  float t;
  int prim;
  int geom;
  int inst;
  float normal[3];
  float u;
  float v;
  int fault;
  int fault_node;
  int fault_depth;
STRUCT_END(Hit)

// Per-ray counters, filled only by the stats variant of the kernels.
STRUCT_BEGIN(RayStats)
  int tlas_nodes;  // TLAS wide-node visits (each tests up to MASQ_WIDTH boxes)
  int blas_nodes;  // BLAS wide-node visits, including masquerade unit-box tests
  int transforms;  // instance ray transforms
  int isect_calls; // primitive intersector calls
STRUCT_END(RayStats)

// step_budget: the most loop steps one tree walk may take (MASQ_STEP_CHECK); the host
// passes the node array's length, which no correct walk of any one tree exceeds (each
// step visits or skips one node, and a walk reaches each node of its tree at most once).
STRUCT_BEGIN(TraceParams)
  int ray_count;
  int tlas_root;
  int ray_offset;
  int step_budget;
STRUCT_END(TraceParams)

STATIC_ASSERT(sizeof(WideNode) == 128, wide_node_size);
STATIC_ASSERT(sizeof(WideNode8) == 4 * MASQ_W8_WORDS, wide_node8_size);
STATIC_ASSERT(sizeof(QuantNode8) == 4 * MASQ_Q8_WORDS, quant_node8_size);
STATIC_ASSERT(sizeof(OrientedNode4) == 4 * MASQ_O4_WORDS, oriented_node4_size);
STATIC_ASSERT(sizeof(Instance) == 64, instance_size);
STATIC_ASSERT(sizeof(MasqInstance) == 32, masq_instance_size);
STATIC_ASSERT(sizeof(MasqOwner) == 16, masq_owner_size);
STATIC_ASSERT(sizeof(Frame) == 64, frame_size);
STATIC_ASSERT(sizeof(Geometry) == 16, geometry_size);
STATIC_ASSERT(sizeof(Triangle) == 48, triangle_size);
STATIC_ASSERT(sizeof(Capsule) == 32, capsule_size);
STATIC_ASSERT(sizeof(RoundCone) == 32, round_cone_size);
STATIC_ASSERT(sizeof(Sphere) == 16, sphere_size);
STATIC_ASSERT(sizeof(Curve) == 64, curve_size);
STATIC_ASSERT(sizeof(Ribbon) == 48, ribbon_size);
STATIC_ASSERT(sizeof(Ray) == 32, ray_size);
STATIC_ASSERT(sizeof(Hit) == 48, hit_size);
STATIC_ASSERT(sizeof(RayStats) == 16, ray_stats_size);
STATIC_ASSERT(sizeof(TraceParams) == 16, trace_params_size);

LAYOUT_NS_END
#include "bv_layout.h"
#endif
