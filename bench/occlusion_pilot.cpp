#include "bench/occlusion_pilot.h"
#include "bench/bench_runner.h"
#include "masq/error.h"
#include <cstdint>
#include <functional>
#include <set>
#include <vector>

namespace masq {

nlohmann::json OcclusionOrderChoice::json() const {
  return {{"order", blas_occlusion_name(order)},
          {"nearest_cpu_seconds", nearest_cpu_s.json()},
          {"starts_last_cpu_seconds", starts_last_cpu_s.json()}};
}

bool blas_order_matters(const PackedScene& ps) {
  std::set<std::int32_t> roots;
  for (const kernel::Instance& inst : ps.instances)
    if (inst.blas_root >= 0) roots.insert(inst.blas_root);
  return ps.stats.blas_nodes > roots.size();
}

PackedScene with_blas_occlusion(PackedScene ps, BlasOcclusion order) {
  ps.features.blas_starts_last = order == BlasOcclusion::StartsLast;
  return ps;
}

OcclusionOrderChoice choose_blas_occlusion(Backend& nearest, Backend& starts_last, const PackedScene& ps,
                                           std::span<const kernel::Ray> rays, std::size_t sample_rays, int rounds,
                                           double margin) {
  if (rays.empty()) throw Error("occlusion order pilot: no rays to time");
  nearest.set_scene(with_blas_occlusion(ps, BlasOcclusion::Nearest));
  starts_last.set_scene(with_blas_occlusion(ps, BlasOcclusion::StartsLast));
  const int passes = traces_per_sample(rays.size(), sample_rays);
  std::vector<kernel::Hit> hits(rays.size());
  auto sample = [&](Backend& be) {
    return [&be, &hits, rays, passes] {
      for (int i = 0; i < passes; ++i) be.trace(rays, hits, {}, Query::Any);
    };
  };
  const std::vector<std::vector<TraceClock>> times =
      time_round_by_round({sample(nearest), sample(starts_last)}, 1, rounds);
  auto cpu = [](const std::vector<TraceClock>& tc) {
    std::vector<double> c;
    for (const TraceClock& x : tc) c.push_back(x.cpu);
    return spread_of(c);
  };
  OcclusionOrderChoice out;
  out.nearest_cpu_s = cpu(times[0]);
  out.starts_last_cpu_s = cpu(times[1]);
  if (out.starts_last_cpu_s.median < out.nearest_cpu_s.median * (1.0 - margin)) out.order = BlasOcclusion::StartsLast;
  return out;
}

} // namespace masq
