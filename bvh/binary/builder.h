// Which binary-BVH builder makes a scene's hierarchies (docs/builders.md):
//  sah            binned SAH (bvh/binary/binned_sah.h), the default;
//  sbvh           spatial splits for every BLAS over primitives (bvh/binary/sbvh.h), binned SAH
//                 for the TLAS and the cluster BLAS;
//  sah+reinsert   binned SAH, then insertion optimisation (bvh/binary/reinsertion.h) of the TLAS
//                 and of every BLAS;
//  sbvh+reinsert  both;
//  sah4           binned SAH pricing every BLAS leaf over primitives per block of four
//                 (SahOptions::leaf_block), as the cpu's four-lane capsule test costs it.
// The wide collapse (bvh/nodes/wide_bvh.h) comes after, whichever builder ran.
#pragma once
#include "bvh/binary/binned_sah.h"
#include "bvh/bounds/clip_bounds.h"
#include "bvh/options.h"
#include "bvh/binary/reinsertion.h"
#include "bvh/binary/sbvh.h"
#include <string>
#include <vector>

namespace masq {

struct BuilderOptions {
  Builder kind = Builder::Sah;
  SbvhOptions sbvh;
  ReinsertOptions reinsert;
};

// A BLAS over primitives: spatial splits where the builder has them (clip bounds the
// pieces), then reinsertion where it has that. `references` gets the leaf reference
// count (>= boxes.size() with spatial splits).
BinaryBvh build_blas_binary(std::span<const Aabb> boxes, const PrimClipper& clip, const SahOptions& sah,
                            const BuilderOptions& opt, std::size_t* references = nullptr);
// A TLAS over instance boxes, or a BLAS without a clipper (clusters): binned SAH, then
// reinsertion where the builder has it.
BinaryBvh build_boxes_binary(std::span<const Aabb> boxes, const SahOptions& sah, const BuilderOptions& opt);

} // namespace masq
