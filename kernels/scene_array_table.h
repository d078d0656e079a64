// THE table of scene arrays: every array of scene data a kernel reads, once. Everything
// else is generated from it (docs/architecture.md, "Add a scene array"):
//  - GLSL: one storage buffer (or buffer reference, addressed mode) per row at its
//    binding, read as KD(name)[i] (kernels/kernel_data.h);
//  - C++ and OpenCL C: the KernelData struct of pointers passed as `kd`, the OpenCL
//    kernels' parameter lists (MASQ_CL_SCENE_PARAMS) and their `kd` set-up;
//  - host: the row's name, binding and element size (host/scene_arrays.h), where its data
//    comes from, the OpenCL kernel arguments and uploads, the Vulkan buffers, descriptor
//    writes and address table, and the cpu's pointers.
//
// X(element type, name, binding, kernels that read it, where the host finds the data)
//   binding: the Vulkan binding and the slot in the address table; every row its own
//     number below MASQ_ADDRESS_SLOTS, and none of the other bindings in kernel_data.h
//     (host/scene_arrays.cpp checks both at compile time).
//   kernels: TWO_LEVEL (the TLAS/BLAS kernels: trace, rayquery, the cpu's trace units),
//     BV (the binary-hierarchy kernels, kernels/bv_traverse.h) or BOTH. Every kernel
//     declares every row; a backend uploads the rows its kernel reads and binds an empty
//     buffer (or nothing, on Vulkan) for the others.
//   source: SCENE = the PackedScene member of the same name (bvh/packed_scene.h); PRIM =
//     a primitive type's array: the member of the same name that this row generates in
//     KernelPrimArrays (scenes/kernel_prims.h, which PackedScene inherits), filled by the
//     type's row of scenes/prim_table.cpp;
//     NODES = PackedScene::node_data(), the node array of the scene's format (w8, q8 and o4
//     nodes are read as words through the node_words view below); BV = the BvScene
//     member of the same name (bvh/bv/bv_scene.h).
// Comments inside the macro are /* */ ones: a // comment would swallow the line splice.
#ifndef MASQ_KERNEL_SCENE_ARRAY_TABLE_H
#define MASQ_KERNEL_SCENE_ARRAY_TABLE_H

#define MASQ_SCENE_ARRAYS(X)                                                        \
  X(WideNode,     nodes,          0,  TWO_LEVEL, NODES) /* TLAS and every BLAS */   \
  X(int,          refs,           1,  TWO_LEVEL, SCENE) /* leaf references */       \
  X(Instance,     instances,      2,  TWO_LEVEL, SCENE) /* TLAS entries */          \
  X(Frame,        frames,         3,  BOTH,      SCENE) /* scene instances */       \
  X(Geometry,     geoms,          4,  BOTH,      SCENE)                             \
  X(Triangle,     triangles,      5,  BOTH,      PRIM)                             \
  X(Capsule,      capsules,       6,  BOTH,      PRIM)                             \
  X(RoundCone,    round_cones,    10, BOTH,      PRIM)                             \
  X(Sphere,       spheres,        11, BOTH,      PRIM)                             \
  X(Curve,        curves,         12, BOTH,      PRIM)                             \
  X(BvNodeAabb,   bv_aabb,        13, BV,        BV) /* one of the four node arrays */ \
  X(BvPrimRef,    bv_prims,       14, BV,        BV) /* bv leaf entries */          \
  X(MasqInstance, masq_instances, 15, TWO_LEVEL, SCENE) /* compact masquerade */    \
  X(MasqOwner,    masq_owners,    16, TWO_LEVEL, SCENE)                             \
  X(BvNodeSphere, bv_sphere,      17, BV,        BV)                                \
  X(BvNodeObb,    bv_obb,         18, BV,        BV)                                \
  X(BvNodeScb,    bv_scb,         19, BV,        BV)                                \
  X(Ribbon,       ribbons,        22, BOTH,      PRIM)

// Views: a second element type over a row's buffer (GLSL cannot reinterpret a buffer,
// so it declares the block twice at one binding; C++ and OpenCL cast the pointer).
// X(element type, name, the row it views)
#define MASQ_SCENE_ARRAY_VIEWS(X) X(uint, node_words, nodes) /* node formats w8, q8 and o4 */

#endif
