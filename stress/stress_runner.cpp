#include "stress/stress_runner.h"
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "oracle/oracle.h"
#include "stress/stress_prim_rows.h"
#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <memory>

namespace masq::stress {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double dir_length(const kernel::Ray& r) {
  return std::sqrt(double(r.dir[0]) * r.dir[0] + double(r.dir[1]) * r.dir[1] + double(r.dir[2]) * r.dir[2]);
}

bool surface_kind(RayKind k) { return k == RayKind::SurfaceOut || k == RayKind::SurfaceIn; }

// Which rays are ambiguous in fp32. Two tests:
//  - clearance: the ray passes the surface closer than the cell's band. A
//    surface-start ray touches its own surface at t = 0, so its clearance is measured
//    from 4x the self window on (only what lies beyond the window can flip).
//  - conditioning: the oracle's answer (hit/miss or primitive) changes when the origin
//    moves by twice the band (8u (r + D + L)), or by 1/4, 1/16 ... 1/1024 of it, along
//    any coordinate axis (twice: the kernels round several intermediate points, each within
//    the band; the smaller steps because a grazing ray's crossing moves by step/angle
//    and a large step can jump clean over a small primitive). This catches grazing
//    rays, whose entry point moves by the band divided by the grazing angle.
// The same perturbations give each ray's t sensitivity (world units): how far the hit
// moves when the origin moves by the band. A grazing ray's hit slides along the surface
// by band / angle; |dt| within r + 2 x that spread is the same surface.
struct Conditioning {
  std::vector<char> ambiguous; // not vector<bool>: rays are decided in parallel, each in its own byte
  std::vector<double> t_spread;
};

Conditioning ambiguous_rays(const Cell& cell, const oracle::Oracle& oracle,
                            const std::vector<oracle::OracleHit>& truth) {
  Conditioning cond;
  cond.ambiguous.assign(truth.size(), false);
  cond.t_spread.assign(truth.size(), 0.0);
  auto& amb = cond.ambiguous;
  const double delta = 2.0 * cell.ambiguity * cell.radius;
  // Up to 37 oracle traces a ray, each ray on its own: on oneTBB's threads (most of
  // `masq stress`'s time is here), every ray writing only its own slots.
  tbb::parallel_for(std::size_t(0), truth.size(), [&](std::size_t i) {
    const RayKind kind = cell.kinds[i];
    if (kind == RayKind::Invalid) return;
    kernel::Ray r = cell.rays[i];
    if (surface_kind(kind)) {
      kernel::Ray w = r;
      w.tmin = float(4.0 * cell.radius / 1024.0 / dir_length(r));
      amb[i] = double(oracle.trace(w).clearance) < cell.ambiguity;
      // Conditioning along the ray: the self window (prim_hit.h) is a cut in t, and on a
      // long primitive it reaches the diameter (32u (|o - c| + L) > 2r at L = 1e6 r), so
      // an exit just past it flips with the origin moved by the band along the ray,
      // as any other ray's answer that flips under a band-sized origin move.
      // The step is twice the band of a ray starting ON the primitive, 4u (1 + L / r)
      // (no D: the cell's D is not this ray's distance).
      const double len_r = stress_prim_row(cell.spec.type).sized_by_length ? 1.0 : cell.spec.length_r;
      const double surf_delta = 2.0 * 4.0 * 5.9604645e-8 * (1.0 + len_r) * cell.radius;
      for (int k = 0; k < 2 && !amb[i]; ++k) {
        kernel::Ray p = r;
        const double step = (k ? surf_delta : -surf_delta) / dir_length(r);
        for (int j = 0; j < 3; ++j) p.org[j] = float(double(p.org[j]) + step * double(p.dir[j]));
        amb[i] = oracle.trace(p).prim != truth[i].prim;
      }
      return;
    }
    if (double(truth[i].clearance) < cell.ambiguity) {
      amb[i] = true;
      return;
    }
    for (int k = 0; k < 36 && !amb[i]; ++k) {
      kernel::Ray p = r;
      const double step = delta / double(1 << (2 * (k / 6)));
      // At least one ulp: far from the world origin a step below the coordinate's
      // spacing would round back to the same ray.
      float& c = p.org[(k % 6) / 2];
      const float moved = float(double(c) + (k % 2 ? step : -step));
      c = moved != c ? moved : std::nextafter(c, k % 2 ? INFINITY : -INFINITY);
      oracle::OracleHit h = oracle.trace(p);
      amb[i] = h.prim != truth[i].prim;
      if (h.prim >= 0 && truth[i].prim >= 0)
        cond.t_spread[i] = std::max(cond.t_spread[i], std::fabs(double(h.t - truth[i].t)) * dir_length(r));
    }
  });
  return cond;
}

Metrics compare(const Cell& cell, const std::vector<oracle::OracleHit>& truth, const Conditioning& cond,
                const std::vector<kernel::Hit>& hits) {
  Metrics m;
  m.rays = cell.rays.size();
  for (std::size_t i = 0; i < cell.rays.size(); ++i) {
    const oracle::OracleHit& o = truth[i];
    const kernel::Hit& h = hits[i];
    const RayKind kind = cell.kinds[i];
    m.rays_by_kind[std::size_t(kind)]++;
    const double dl = dir_length(cell.rays[i]);
    const bool khit = h.prim >= 0, ohit = o.prim >= 0;
    // A self hit: the kernel reports a crossing within r/100 of a surface-start ray's
    // origin that the oracle does not have there.
    if (surface_kind(kind) && khit && double(h.t) * dl < 0.01 * cell.radius &&
        !(ohit && std::fabs(double(h.t) - double(o.t)) * dl <= 1e-3 * cell.radius + 2.0 * cond.t_spread[i])) {
      m.self_hits++;
    }
    if (cond.ambiguous[i]) {
      m.ambiguous++;
      continue;
    }
    m.compared++;
    bool bad = khit != ohit;
    if (!bad && khit) {
      double dt = std::fabs(double(h.t) - double(o.t)) * dl / cell.radius;
      if (dt > 1.0 + 2.0 * cond.t_spread[i] / cell.radius || h.prim != o.prim) {
        bad = true;
      } else if (cond.t_spread[i] <= 1e-3 * cell.radius) {
        // Error statistics over well-conditioned hits only: a grazing ray's hit slides
        // by band / angle under any fp32 evaluation (checked above, not averaged here).
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
      if (m.example.empty()) {
        const kernel::Ray& r = cell.rays[i];
        m.example = fmt::format(
            "ray {} ({}): org ({:.9g} {:.9g} {:.9g}) dir ({:.9g} {:.9g} {:.9g}); oracle prim {} t {:.9g} clearance "
            "{:.3g}; kernel prim {} t {:.9g}; t spread {:.3g}",
            i, ray_kind_name(kind), r.org[0], r.org[1], r.org[2], r.dir[0], r.dir[1], r.dir[2], o.prim, double(o.t),
            double(o.clearance), h.prim, double(h.t), cond.t_spread[i]);
      }
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
  Cell cell;
  std::vector<oracle::OracleHit> truth;
  Conditioning cond;
  for (std::size_t ci = 0; ci < specs.size(); ++ci) {
    const CellSpec& spec = specs[ci];
    say(fmt::format("cell {}/{}: {} {}", ci + 1, specs.size(), prim_type_key(spec.type), spec.label));
    // A cell with the rays of the one before (another curve intersector) reuses its
    // scene, rays and oracle answers.
    if (!(ci > 0 && spec.ray_seed == specs[ci - 1].ray_seed && spec.type == specs[ci - 1].type)) {
      cell = make_cell(spec, opt.sweep.rays_per_cell, opt.sweep.seed + spec.ray_seed * 7919);
      auto t0 = Clock::now();
      oracle::Oracle oracle(cell.scene);
      truth = oracle.trace_all(cell.rays);
      cond = ambiguous_rays(cell, oracle, truth);
      report.oracle_seconds += since(t0);
    }
    cell.spec = spec;
    for (Mode mode : opt.modes) {
      std::map<Method, PackedScene> built;
      AccelOptions ao;
      ao.mode = mode;
      ao.curve_isect = spec.curve_isect;
      const bool baseline = opt.nodes != NodeFormat::W4;
      std::optional<PackedScene> w4_ref;
      if (baseline) w4_ref = build_accel(cell.scene, Method::Ref, ao);
      ao.nodes = opt.nodes;
      if (opt.nodes == NodeFormat::O4) ao.oriented_gain = INFINITY;
      for (Method method : {Method::Ref, Method::Masq}) built[method] = build_accel(cell.scene, method, ao);
      for (auto& [name, be] : backends) {
        std::map<Method, std::vector<kernel::Hit>> hits;
        std::vector<kernel::Hit> w4_hits;
        if (baseline) {
          w4_hits.resize(cell.rays.size());
          be->set_scene(*w4_ref);
          be->trace(cell.rays, w4_hits, {});
        }
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
          res.m = compare(cell, truth, cond, h);
          res.m.trace_seconds = be->timing().trace_seconds;
          if (method == Method::Masq) res.m.false_culls = false_culls(cell, hits[Method::Ref], h);
          if (method == Method::Ref && baseline) res.m.false_culls = false_culls(cell, w4_hits, h);
          report.results.push_back(std::move(res));
        }
      }
    }
  }
  report.total_seconds = since(t_start);
  return report;
}

} // namespace masq::stress
