#include "stress/stress_runner.h"
#include "bvh/build_accel.h"
#include "host/backend.h"
#include "oracle/oracle.h"
#include <fmt/format.h>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>

namespace masq::stress {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double dir_length(const kernel::Ray& r) {
  return std::sqrt(double(r.dir[0]) * r.dir[0] + double(r.dir[1]) * r.dir[1] + double(r.dir[2]) * r.dir[2]);
}

bool surface_kind(RayKind k) { return k == RayKind::SurfaceOut || k == RayKind::SurfaceIn; }

Metrics compare(const Cell& cell, const std::vector<oracle::OracleHit>& truth, const std::vector<kernel::Hit>& hits) {
  Metrics m;
  m.rays = cell.rays.size();
  for (std::size_t i = 0; i < cell.rays.size(); ++i) {
    const oracle::OracleHit& o = truth[i];
    const kernel::Hit& h = hits[i];
    const RayKind kind = cell.kinds[i];
    m.rays_by_kind[std::size_t(kind)]++;
    const double dl = dir_length(cell.rays[i]);
    const bool khit = h.prim >= 0, ohit = o.prim >= 0;
    if (surface_kind(kind) && khit && double(h.t) * dl < 0.01 * cell.radius && !(ohit && double(o.t) * dl < 0.01 * cell.radius))
      m.self_hits++;
    if (kind != RayKind::Invalid && double(o.clearance) < cell.ambiguity) {
      m.ambiguous++;
      continue;
    }
    m.compared++;
    bool bad = khit != ohit;
    if (!bad && khit) {
      double dt = std::fabs(double(h.t) - double(o.t)) * dl / cell.radius;
      if (dt > 1.0 || h.prim != o.prim) {
        bad = true;
      } else {
        glm::dvec3 kn(h.normal[0], h.normal[1], h.normal[2]);
        double c = std::clamp(glm::dot(kn, o.normal) / std::max(glm::length(kn), 1e-30), -1.0, 1.0);
        double deg = std::acos(c) * 180.0 / M_PI;
        m.max_dt = std::max(m.max_dt, dt);
        m.sum_dt += dt;
        m.max_normal_deg = std::max(m.max_normal_deg, deg);
        m.sum_normal_deg += deg;
        m.dt_count++;
      }
    }
    if (bad) {
      m.disagree++;
      m.disagree_by_kind[std::size_t(kind)]++;
    }
  }
  return m;
}

std::size_t false_culls(const Cell& cell, const std::vector<kernel::Hit>& ref, const std::vector<kernel::Hit>& masq) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    if (ref[i].prim < 0) continue;
    double dl = dir_length(cell.rays[i]);
    bool missed = masq[i].prim < 0 || (double(masq[i].t) - double(ref[i].t)) * dl > cell.radius;
    if (missed) ++n;
  }
  return n;
}

} // namespace

StressReport run_stress(const StressOptions& opt) {
  auto t_start = Clock::now();
  StressReport report;
  auto say = [&](const std::string& s) {
    if (opt.progress) opt.progress(s);
  };
  std::vector<std::pair<std::string, std::unique_ptr<Backend>>> backends;
  for (const std::string& name : opt.backends.empty() ? backend_names() : opt.backends) {
    try {
      backends.emplace_back(name, make_backend(name));
      report.devices.push_back(name + ": " + backends.back().second->device_name());
    } catch (const std::exception& e) {
      report.unavailable.emplace_back(name, e.what());
    }
  }
  std::vector<CellSpec> specs = sweep_cells(opt.sweep);
  for (std::size_t ci = 0; ci < specs.size(); ++ci) {
    const CellSpec& spec = specs[ci];
    say(fmt::format("cell {}/{}: {} {}", ci + 1, specs.size(), prim_type_key(spec.type), spec.label));
    Cell cell = make_cell(spec, opt.sweep.rays_per_cell, opt.sweep.seed + ci * 7919);
    auto t0 = Clock::now();
    std::vector<oracle::OracleHit> truth = oracle::Oracle(cell.scene).trace_all(cell.rays);
    report.oracle_seconds += since(t0);
    for (Mode mode : opt.modes) {
      std::map<Method, PackedScene> built;
      for (Method method : {Method::Ref, Method::Masq}) {
        AccelOptions ao;
        ao.mode = mode;
        built[method] = build_accel(cell.scene, method, ao);
      }
      for (auto& [name, be] : backends) {
        std::map<Method, std::vector<kernel::Hit>> hits;
        for (Method method : {Method::Ref, Method::Masq}) {
          CellResult res;
          res.spec = spec;
          res.backend = name;
          res.mode = mode;
          res.method = method;
          std::vector<kernel::Hit>& h = hits[method];
          h.resize(cell.rays.size());
          be->set_scene(built[method]);
          be->trace(cell.rays, h, {});
          res.m = compare(cell, truth, h);
          res.m.trace_seconds = be->timing().trace_seconds;
          if (method == Method::Masq) res.m.false_culls = false_culls(cell, hits[Method::Ref], h);
          report.results.push_back(std::move(res));
        }
      }
    }
  }
  report.total_seconds = since(t_start);
  return report;
}

} // namespace masq::stress
