#include "bvh/builder.h"
#include "scenes/error.h"

namespace masq {

const char* builder_name(Builder b) {
  switch (b) {
    case Builder::Sah: return "sah";
    case Builder::Sbvh: return "sbvh";
    case Builder::SahReinsert: return "sah+reinsert";
    case Builder::SbvhReinsert: return "sbvh+reinsert";
    case Builder::Sah4: return "sah4";
    case Builder::SahPriced: return "sah-priced";
  }
  return "?";
}

const std::vector<Builder>& all_builders() {
  static const std::vector<Builder> all{Builder::Sah, Builder::Sbvh, Builder::SahReinsert, Builder::SbvhReinsert,
                                       Builder::Sah4, Builder::SahPriced};
  return all;
}

Builder parse_builder(const std::string& name) {
  for (Builder b : all_builders())
    if (name == builder_name(b)) return b;
  throw Error("builder: unknown builder '" + name + "' (choose sah, sbvh, sah+reinsert, sbvh+reinsert, sah4 or sah-priced)");
}

BinaryBvh build_blas_binary(const std::vector<Aabb>& boxes, const PrimClipper& clip, const SahOptions& sah,
                            const BuilderOptions& opt, std::size_t* references) {
  SahOptions blas_sah = sah;
  blas_sah.leaf_block = builder_leaf_block(opt.kind);
  BinaryBvh bvh =
      builder_splits(opt.kind) ? build_sbvh(boxes, clip, blas_sah, opt.sbvh) : build_binned_sah(boxes, blas_sah);
  if (builder_reinserts(opt.kind)) bvh = reinsert_optimize(bvh, blas_sah, opt.reinsert);
  if (references) *references = bvh.order.size();
  return bvh;
}

BinaryBvh build_boxes_binary(const std::vector<Aabb>& boxes, const SahOptions& sah, const BuilderOptions& opt) {
  BinaryBvh bvh = build_binned_sah(boxes, sah);
  if (builder_reinserts(opt.kind)) bvh = reinsert_optimize(bvh, sah, opt.reinsert);
  return bvh;
}

} // namespace masq
