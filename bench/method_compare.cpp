#include "bench/method_compare.h"
#include "bench/bench_report.h"
#include <algorithm>
#include <fmt/format.h>

namespace masq {

std::string method_cell(const std::vector<BenchRow>& rows, const std::string& backend, RaySet set, MethodTally& tally) {
  const BenchRow* ref = find_row(rows, backend, Method::Ref, set);
  const BenchRow* masq = find_row(rows, backend, Method::Masq, set);
  const BenchRow* cluster = find_row(rows, backend, Method::Cluster, set);
  const BenchRow* automatic = find_row(rows, backend, Method::Auto, set);
  std::string c = ref && cluster ? fmt::format("{:.2f}x", cluster->mrays_per_s() / ref->mrays_per_s()) : "n/a";
  std::string a = "n/a";
  if (ref && masq && automatic) {
    double best = std::max(ref->mrays_per_s(), masq->mrays_per_s());
    double r = automatic->mrays_per_s() / best;
    Method kept = automatic->build.auto_choice;
    const BenchRow* same =
        kept == Method::Auto ? automatic : find_row(rows, backend, kept, set, automatic->builder, automatic->nodes);
    // auto's cluster candidate may have another shape than the cluster row's: then no
    // row holds the same bytes.
    if (same && kept == Method::Cluster &&
        (same->build.cluster_size != automatic->build.cluster_size ||
         same->build.cluster_leaf_price != automatic->build.cluster_leaf_price))
      same = automatic;
    double rk = (same ? same : automatic)->mrays_per_s() / best;
    a = fmt::format("{:.2f}x ({})", r, kept == Method::Auto ? "mix" : method_name(kept));
    tally.cells++;
    tally.auto_within += r >= 0.95;
    tally.worst = tally.cells == 1 ? r : std::min(tally.worst, r);
    tally.kept_within += rk >= 0.95;
    tally.kept_worst = tally.cells == 1 ? rk : std::min(tally.kept_worst, rk);
  }
  return c + " / " + a;
}

std::string method_note(const MethodTally& tally) {
  std::string held =
      tally.cells == 0
          ? std::string("no cell had ref, masq and auto")
          : fmt::format("auto within 5% of the better of ref and masq in {} of {} cells by its own row (worst {:.2f}x), "
                        "in {} of {} by the row of the structure it kept (worst {:.2f}x; the same bytes timed twice, "
                        "so the difference is timing noise)",
                        tally.auto_within, tally.cells, tally.worst, tally.kept_within, tally.cells, tally.kept_worst);
  return "each backend: cluster/ref speedup / auto over the better of ref and masq (rays/s, same rays) and the "
         "candidate auto kept (bvh/structure_cost.h: ref, masq, cluster or its per-cluster mix); " +
         held;
}

} // namespace masq
