#include "stress/stress_report.h"
#include <fmt/format.h>
#include <algorithm>
#include <map>
#include <set>

namespace masq::stress {

namespace {

std::string rate_str(double r) { return r == 0.0 ? "0" : fmt::format("{:.1e}", r); }

std::vector<std::string> backends_of(const StressReport& r) {
  std::vector<std::string> out;
  for (const CellResult& c : r.results)
    if (std::find(out.begin(), out.end(), c.backend) == out.end()) out.push_back(c.backend);
  return out;
}

std::string cell_key(const CellSpec& s) { return std::string(prim_type_key(s.type)) + " " + s.label; }

} // namespace

std::string stress_matrix(const StressReport& r, Mode mode) {
  std::vector<std::string> bes = backends_of(r);
  std::string out = fmt::format("{} mode: disagreement rate per backend (masq method; ambiguous rays excluded)\n",
                                mode_name(mode));
  out += fmt::format("{:<9} {:<16} {:>6} {:>6}", "prim", "cell", "rays", "amb%");
  for (const std::string& b : bes) out += fmt::format(" {:>9}", b);
  out += fmt::format(" {:>9} {:>9} {:>8} {:>6} {:>5}\n", "max|dt|/r", "mean", "max n deg", "culls", "self");
  std::vector<std::string> order;
  std::map<std::string, std::vector<const CellResult*>> by_cell;
  for (const CellResult& c : r.results) {
    if (c.mode != mode) continue;
    std::string k = cell_key(c.spec);
    if (!by_cell.count(k)) order.push_back(k);
    by_cell[k].push_back(&c);
  }
  for (const std::string& k : order) {
    const auto& rows = by_cell[k];
    const CellSpec& s = rows.front()->spec;
    const Metrics& m0 = rows.front()->m;
    out += fmt::format("{:<9} {:<16} {:>6} {:>6.2f}", prim_type_key(s.type), s.label, m0.rays,
                       m0.rays ? 100.0 * double(m0.ambiguous) / double(m0.rays) : 0.0);
    double max_dt = 0, sum_dt = 0, max_n = 0;
    std::size_t n_dt = 0, culls = 0, self = 0;
    for (const std::string& b : bes) {
      const CellResult* masq = nullptr;
      for (const CellResult* c : rows)
        if (c->backend == b && c->method == Method::Masq) masq = c;
      out += fmt::format(" {:>9}", masq ? rate_str(masq->m.rate()) : "-");
      for (const CellResult* c : rows) {
        if (c->backend != b) continue;
        max_dt = std::max(max_dt, c->m.max_dt);
        sum_dt += c->m.sum_dt;
        n_dt += c->m.dt_count;
        max_n = std::max(max_n, c->m.max_normal_deg);
        culls += c->m.false_culls;
        self += c->m.self_hits;
      }
    }
    out += fmt::format(" {:>9.2e} {:>9.2e} {:>8.3f} {:>6} {:>5}\n", max_dt, n_dt ? sum_dt / double(n_dt) : 0.0, max_n,
                       culls, self);
  }
  return out;
}

std::string stress_summary(const StressReport& r) {
  struct Acc {
    std::size_t rays = 0, compared = 0, disagree = 0, culls = 0, self = 0;
    double worst = 0, seconds = 0, max_dt = 0;
    std::string worst_cell;
  };
  std::map<std::pair<std::string, int>, Acc> acc;
  std::vector<std::pair<std::string, int>> order;
  for (const CellResult& c : r.results) {
    auto key = std::make_pair(c.backend, int(c.mode));
    if (!acc.count(key)) order.push_back(key);
    Acc& a = acc[key];
    a.rays += c.m.rays;
    a.compared += c.m.compared;
    a.disagree += c.m.disagree;
    a.culls += c.m.false_culls;
    a.self += c.m.self_hits;
    a.seconds += c.m.trace_seconds;
    a.max_dt = std::max(a.max_dt, c.m.max_dt);
    if (c.m.rate() > a.worst) {
      a.worst = c.m.rate();
      a.worst_cell = fmt::format("{} {} ({})", prim_type_key(c.spec.type), c.spec.label, method_name(c.method));
    }
  }
  std::string out = fmt::format("{:<9} {:<7} {:>9} {:>10} {:>9} {:>9} {:>6} {:>5} {:>8}  {}\n", "backend", "mode",
                                "rays", "disagree", "rate", "max|dt|/r", "culls", "self", "Mrays/s", "worst cell");
  for (const auto& key : order) {
    const Acc& a = acc[key];
    out += fmt::format("{:<9} {:<7} {:>9} {:>10} {:>9} {:>9.2e} {:>6} {:>5} {:>8.2f}  {}\n", key.first,
                       mode_name(Mode(key.second)), a.rays, a.disagree,
                       rate_str(a.compared ? double(a.disagree) / double(a.compared) : 0.0), a.max_dt, a.culls, a.self,
                       a.seconds > 0 ? double(a.rays) / a.seconds * 1e-6 : 0.0,
                       a.worst > 0 ? fmt::format("{} at {}", rate_str(a.worst), a.worst_cell) : "-");
  }
  return out;
}

std::string stress_by_kind(const StressReport& r) {
  std::string out = fmt::format("{:<7}", "mode");
  for (int k = 0; k < kRayKinds; ++k) out += fmt::format(" {:>13}", ray_kind_name(RayKind(k)));
  out += "\n";
  for (Mode mode : {Mode::Robust, Mode::Fast}) {
    std::array<std::size_t, kRayKinds> rays{}, bad{};
    bool any = false;
    for (const CellResult& c : r.results) {
      if (c.mode != mode) continue;
      any = true;
      for (int k = 0; k < kRayKinds; ++k) {
        rays[std::size_t(k)] += c.m.rays_by_kind[std::size_t(k)];
        bad[std::size_t(k)] += c.m.disagree_by_kind[std::size_t(k)];
      }
    }
    if (!any) continue;
    out += fmt::format("{:<7}", mode_name(mode));
    for (int k = 0; k < kRayKinds; ++k) {
      std::size_t n = rays[std::size_t(k)];
      out += fmt::format(" {:>13}", n ? rate_str(double(bad[std::size_t(k)]) / double(n)) : "-");
    }
    out += "\n";
  }
  return out;
}

nlohmann::json stress_json(const StressReport& r) {
  nlohmann::json j;
  j["devices"] = r.devices;
  for (const auto& [b, why] : r.unavailable) j["unavailable"][b] = why;
  j["oracle_seconds"] = r.oracle_seconds;
  j["total_seconds"] = r.total_seconds;
  for (const CellResult& c : r.results) {
    nlohmann::json e;
    e["prim"] = prim_type_key(c.spec.type);
    e["sweep"] = c.spec.sweep;
    e["cell"] = c.spec.label;
    e["radius"] = c.spec.radius;
    e["length_over_r"] = c.spec.length_r;
    e["distance_over_r"] = c.spec.distance_r;
    e["offset"] = c.spec.offset;
    e["backend"] = c.backend;
    e["mode"] = mode_name(c.mode);
    e["method"] = method_name(c.method);
    const Metrics& m = c.m;
    e["rays"] = m.rays;
    e["ambiguous"] = m.ambiguous;
    e["compared"] = m.compared;
    e["disagree"] = m.disagree;
    e["rate"] = m.rate();
    e["self_hits"] = m.self_hits;
    e["false_culls"] = m.false_culls;
    e["max_dt_over_r"] = m.max_dt;
    e["mean_dt_over_r"] = m.mean_dt();
    e["max_normal_deg"] = m.max_normal_deg;
    e["mean_normal_deg"] = m.mean_normal_deg();
    e["trace_seconds"] = m.trace_seconds;
    if (!m.example.empty()) e["first_disagreement"] = m.example;
    for (int k = 0; k < kRayKinds; ++k) {
      e["by_kind"][ray_kind_name(RayKind(k))] = {{"rays", m.rays_by_kind[std::size_t(k)]},
                                                 {"disagree", m.disagree_by_kind[std::size_t(k)]}};
    }
    j["results"].push_back(e);
  }
  return j;
}

std::string stress_failures(const StressReport& r, double max_rate) {
  std::string out;
  for (const CellResult& c : r.results) {
    if (c.mode != Mode::Robust) continue;
    if (c.m.rate() > max_rate || c.m.false_culls > 0 || c.m.self_hits > 0)
      out += fmt::format("{} {} {} {}: rate {} ({} of {} rays disagree), false culls {}, self hits {}\n", c.backend,
                         prim_type_key(c.spec.type), c.spec.label, method_name(c.method), rate_str(c.m.rate()),
                         c.m.disagree, c.m.compared, c.m.false_culls, c.m.self_hits) +
             (c.m.example.empty() ? "" : "    first: " + c.m.example + "\n");
  }
  return out;
}

} // namespace masq::stress
