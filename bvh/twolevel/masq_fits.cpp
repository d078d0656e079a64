#include "bvh/twolevel/masq_fits.h"
#include "bvh/binary/parallel.h"
#include "masq/error.h"
#include <algorithm>
#include <string>

namespace masq {

void fit_masquerades(const Geometry& g, std::span<const std::int32_t> prims, const Affine3& object_to_world,
                     CurveObb curve_obb, bool try_compact, std::span<MasqFit> fits) {
  if (fits.size() != prims.size()) throw Error("fit_masquerades: " + std::to_string(fits.size()) + " fits for " +
                                               std::to_string(prims.size()) + " primitives");
  // A fit is a few microseconds (an OBB in double, a verified fp32 map): chunks of 256 keep
  // the task overhead small and still spread the bear's 144K primitives evenly.
  parallel_chunks(prims.size(), 256, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i0 = lo; i0 < hi; i0 += kCompactLanes) {
      const std::size_t n = std::min(hi - i0, std::size_t(kCompactLanes));
      std::optional<CompactMasquerade>* out[kCompactLanes];
      for (std::size_t l = 0; l < n; ++l) out[l] = &fits[i0 + l].compact;
      if (try_compact) {
        compact_masquerades(g, prims.subspan(i0, n), object_to_world, out); // sets every out[l]
      } else {
        for (std::size_t l = 0; l < n; ++l) out[l]->reset();
      }
      for (std::size_t i = i0; i < i0 + n; ++i)
        if (!fits[i].compact) fits[i].full = masquerade_box(g, std::size_t(prims[i]), object_to_world, curve_obb);
    }
  });
}

} // namespace masq
