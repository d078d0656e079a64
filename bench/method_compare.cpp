#include "bench/method_compare.h"
#include "bench/bench_report.h"
#include "bench/price_fit.h"
#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>

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
        kept == Method::Auto ? automatic
                             : find_row(rows, backend, kept, set, automatic->builder, automatic->nodes, automatic->curve_isect);
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
         "candidate auto kept (ref, masq, cluster or its per-cluster mix; by default the one a pilot sample of these "
         "rays traced fastest on that backend, bench/auto_pilot.h); " +
         held;
}

std::string price_fit_note(const std::vector<std::vector<BenchRow>>& groups, const std::vector<std::string>& backends,
                           nlohmann::json& data) {
  std::vector<BenchRow> all;
  for (const std::vector<BenchRow>& g : groups) all.insert(all.end(), g.begin(), g.end());
  std::vector<std::string> parts;
  for (const std::string& b : backends) {
    std::optional<PriceFit> f = fit_prices(all, b);
    if (!f) continue;
    FitChoices c = fit_choices(groups, b, *f);
    parts.push_back(fmt::format("{} {} of {} (prices 1 : {:.2g} : {:.2g}, fit error median {:.0f}%, leave-one-out "
                                "median {:.0f}% worst {:.0f}%)",
                                b, c.within, c.cells, f->prices.transform, f->prices.isect, 100.0 * f->median_rel_error,
                                100.0 * f->loo_median_rel_error, 100.0 * f->loo_max_rel_error));
    data[b] = {{"cells", c.cells},
               {"within_5_percent", c.within},
               {"ns_per_ray", f->ns_per_ray},
               {"ns_per_node", f->ns_per_node},
               {"transform", f->prices.transform},
               {"isect", f->prices.isect},
               {"median_rel_error", f->median_rel_error},
               {"max_rel_error", f->max_rel_error},
               {"rows", f->rows},
               {"loo_median_rel_error", f->loo_median_rel_error},
               {"loo_max_rel_error", f->loo_max_rel_error}};
  }
  if (parts.empty()) return "price fit: no backend had rows with counters to fit";
  return "a linear price model fitted per backend to all these rows (per ray + node + transform + intersector call; "
         "bench/price_fit.h), choosing among ref, masq and cluster from the MEASURED counters (the best a counter model "
         "can do), is within 5% of the better of ref and masq in: " +
         fmt::format("{}", fmt::join(parts, "; "));
}

} // namespace masq
