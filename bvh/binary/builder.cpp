#include "bvh/binary/builder.h"
#include "masq/error.h"

namespace masq {

BinaryBvh build_blas_binary(std::span<const Aabb> boxes, const PrimClipper& clip, const SahOptions& sah,
                            const BuilderOptions& opt, std::size_t* references) {
  SahOptions blas_sah = sah;
  blas_sah.leaf_block = builder_leaf_block(opt.kind);
  BinaryBvh bvh =
      builder_splits(opt.kind) ? build_sbvh(boxes, clip, blas_sah, opt.sbvh) : build_binned_sah(boxes, blas_sah);
  if (builder_reinserts(opt.kind)) bvh = reinsert_optimize(bvh, blas_sah, opt.reinsert);
  if (references) *references = bvh.order.size();
  return bvh;
}

BinaryBvh build_boxes_binary(std::span<const Aabb> boxes, const SahOptions& sah, const BuilderOptions& opt) {
  BinaryBvh bvh = build_binned_sah(boxes, sah);
  if (builder_reinserts(opt.kind)) bvh = reinsert_optimize(bvh, sah, opt.reinsert);
  return bvh;
}

} // namespace masq
