// peers: masq against Embree 3 (the Debian package; round linear curves for capsules
// and links, round Bezier curves closed by sphere points for cubics, triangles) on the
// same rays, as ratios of CPU time (and wall time) measured round by round in one run.
// masq's tracer is chosen on pilot rays of their own (a camera of another resolution),
// never on the timed ones.
#include "bench/bench_report.h"
#include "bench/occlusion_pilot.h"
#include "bench/peer_builds.h"
#include "bench/peer_rounds.h"
#include "bench/peer_scenes.h"
#include "bench/suite.h"
#include "oracle/oracle.h"
#include "peers/embree_peer.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <fmt/format.h>

namespace masq {

namespace {

struct Agreement {
  double rays = 0, hit_miss = 0, common = 0, other_prim = 0;
  std::vector<std::size_t> differing; // indices of the rays counted in hit_miss or other_prim
  std::string text() const {
    if (rays == 0) return "n/a";
    return fmt::format("{:.3f}% / {:.3f}%", 100.0 * hit_miss / rays, common > 0 ? 100.0 * other_prim / common : 0.0);
  }
};

// Hit/miss disagreements over all rays, and common hits on a different primitive at a
// t more than 1e-3 relative away (the closest hit is another surface). Distances on the
// same primitive are not compared: Embree's round curves are accurate to about 1% of r
// near a ray origin, far looser than masq's.
Agreement agree(const std::vector<kernel::Hit>& a, const std::vector<kernel::Hit>& b, Query query) {
  Agreement g;
  g.rays = double(std::min(a.size(), b.size()));
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    bool ha = a[i].prim >= 0, hb = b[i].prim >= 0;
    if (ha != hb) {
      g.hit_miss++;
      g.differing.push_back(i);
    } else if (ha && query == Query::Closest) { // occlusion: only occluded or not is asked
      g.common++;
      bool same = a[i].prim == b[i].prim && a[i].geom == b[i].geom && a[i].inst == b[i].inst;
      // Where two primitives meet (consecutive segments of a strand) either may be the
      // closest at the same t: a tie, not a different surface.
      bool tie = std::fabs(double(a[i].t) - double(b[i].t)) <= 1e-3 * std::max(double(a[i].t), double(b[i].t));
      if (!same && !tie) {
        g.other_prim++;
        g.differing.push_back(i);
      }
    }
  }
  return g;
}

bool matches_oracle(const kernel::Hit& h, const oracle::OracleHit& o, Query query) {
  if ((h.prim >= 0) != (o.prim >= 0)) return false;
  if (h.prim < 0 || query == Query::Any) return true;
  if (h.prim == o.prim && h.geom == o.geom && h.inst == o.inst) return true;
  return std::fabs(double(h.t) - double(o.t)) <= 1e-3 * double(o.t); // a tie at a joint
}

// Who is right where two tracers disagree: the long-double oracle traces (at most
// `cap`, evenly spread) of the differing rays. "a a_right of n / b b_right of n".
struct Arbitration {
  int traced = 0, a_right = 0, b_right = 0;
  std::string text() const { return traced ? fmt::format("{} / {} of {}", a_right, b_right, traced) : "-"; }
};

Arbitration arbitrate(const oracle::Oracle& orc, const std::vector<kernel::Ray>& rays, const std::vector<kernel::Hit>& a,
                      const std::vector<kernel::Hit>& b, const std::vector<std::size_t>& differing, Query query,
                      std::size_t cap = 300) {
  Arbitration r;
  std::vector<kernel::Ray> sel;
  std::vector<std::size_t> idx;
  std::size_t stride = std::max<std::size_t>(1, (differing.size() + cap - 1) / cap);
  for (std::size_t k = 0; k < differing.size(); k += stride) {
    idx.push_back(differing[k]);
    sel.push_back(rays[differing[k]]);
  }
  std::vector<oracle::OracleHit> truth = orc.trace_all(sel);
  for (std::size_t k = 0; k < idx.size(); ++k) {
    r.traced++;
    r.a_right += matches_oracle(a[idx[k]], truth[k], query);
    r.b_right += matches_oracle(b[idx[k]], truth[k], query);
  }
  return r;
}

// The structure a row traced: auto by pilot's kept candidate, else the method's own.
const PackedScene& row_structure(const BuiltMethods& built, const BenchRow& row) {
  if (row.method == Method::Auto)
    for (const PackedScene& c : built.auto_candidates.built)
      if (c.method == row.build.auto_choice) return c;
  return built.scenes.at(row.method);
}

constexpr int kSoloSlot = 3000; // bench/backend_pool.h: past the lanes' and pilots'
constexpr int kOrderSlot = kSoloSlot + 1; // the occlusion order pilot's second backend
// The occlusion order pilot: rounds of both orders, and how much faster starts-last must
// be to be kept (within the noise, nearest: the order of every closest-hit query).
constexpr int kOrderRounds = 5;
constexpr double kOrderMargin = 0.02;

// The fastest available pilot row of a ray set among masq's own tracers, by CPU time
// (the figure the rounds decide by: PoCL's workers, say, can win by wall time and lose
// by CPU time), by device time where a row has none.
const BenchRow* fastest_row(const std::vector<BenchRow>& rows, RaySet set) {
  const BenchRow* best = nullptr;
  auto cost = [](const BenchRow& r) { return r.cpu_s > 0 ? r.cpu_s : r.median_s; };
  for (const BenchRow& r : rows) {
    if (r.ray_set != set || !r.unavailable.empty()) continue;
    if (!best || cost(r) < cost(*best)) best = &r;
  }
  return best;
}

// The BLAS occlusion order that traced the pilot's shadow rays through `structure` faster
// (bench/occlusion_pilot.h), timed on `be` and a second backend of its kind.
OcclusionOrderChoice occlusion_order_pilot(SuiteContext& ctx, const std::string& label, const BenchRun& run,
                                           const std::string& backend, const PackedScene& structure, Backend& be,
                                           std::size_t sample_rays) {
  const RayBatch* shadow = nullptr;
  for (const RayBatch& b : run.batches)
    if (b.set == RaySet::Shadow) shadow = &b;
  if (!shadow) throw Error("peers: the pilot traced no shadow rays to choose an occlusion order on");
  Backend* other = ctx.pool.get(backend, kOrderSlot);
  if (!other) throw Error("occlusion order pilot: " + ctx.pool.why(backend));
  ctx.say("peers " + label + ": the BLAS occlusion order, nearest against starts-last, on the pilot's shadow rays");
  try {
    OcclusionOrderChoice c = choose_blas_occlusion(be, *other, structure, shadow->rays, sample_rays, kOrderRounds,
                                                   kOrderMargin);
    ctx.pool.close(backend, kOrderSlot);
    return c;
  } catch (...) {
    ctx.pool.close(backend, kOrderSlot);
    throw;
  }
}

// masq's candidate tracers: its CPU-side backends of the run (cpu, and OpenCL: PoCL here;
// lavapipe's Vulkan has never been the fastest on a CPU and its compiles take minutes)
// x method x builder x node format (x curve intersector), traced on the pilot's rays.
// Quick: ref and masq, w4, w8 and o4, roving curves.
BenchOptions pilot_options(const SuiteContext& ctx, bool curves) {
  const bool quick = ctx.config.quick;
  BenchOptions o = ctx.bench_options(quick ? 128 : 192, quick ? 96 : 192);
  o.backends.clear();
  for (const std::string& b : ctx.config.backends)
    if (b == "cpu" || b == "opencl") o.backends.push_back(b);
  o.methods = quick ? std::vector<Method>{Method::Ref, Method::Masq}
                    : std::vector<Method>{Method::Ref, Method::Masq, Method::Cluster};
  o.builders = {Builder::Sah, Builder::Sah4};
  o.node_formats = quick ? std::vector<NodeFormat>{NodeFormat::W4, NodeFormat::W8, NodeFormat::O4}
                         : std::vector<NodeFormat>{NodeFormat::W4, NodeFormat::W8, NodeFormat::O4, NodeFormat::Q8};
  if (curves)
    o.curve_isects = quick ? std::vector<CurveIsect>{CurveIsect::Roving}
                           : std::vector<CurveIsect>{CurveIsect::Phantom, CurveIsect::Roving};
  o.warmup = 1;
  o.repetitions = 3;
  // Every sample of a set at least the pilot camera's rays, as the timed rounds take
  // theirs: the hair's pilot shadow and diffuse sets are 850-5,000 rays, about a
  // millisecond a trace, and the choice between close tracers went by wake-ups.
  o.sample_rays = std::size_t(o.width) * std::size_t(o.height);
  return o;
}

// Camera rays of the timed sets: 512 x 512 (262,144) in the full suite; quick: 256 x 256,
// indicative only.
int timed_side(bool quick) { return quick ? 256 : 512; }
int timed_rounds(bool quick) { return quick ? 5 : 7; }
// f, n times over.
std::function<void()> repeated(std::function<void()> f, int n) {
  return [f = std::move(f), n] {
    for (int i = 0; i < n; ++i) f();
  };
}

std::string config_label(const BenchRow& r) {
  std::string s = fmt::format("{} {}", r.backend, method_label(r));
  if (r.nodes != NodeFormat::W4) s += std::string(" ") + node_format_name(r.nodes);
  return s;
}

std::string ratio_text(const Spread& s) { return fmt::format("{:.2f}x ({:.2f}-{:.2f})", s.median, s.min, s.max); }

double cpu_ratio(const TraceClock& embree, const TraceClock& masq) { return embree.cpu / masq.cpu; }
double wall_ratio(const TraceClock& embree, const TraceClock& masq) { return embree.wall / masq.wall; }

// Embree on one ray set with one API: the closest hits, or occluded flags as hits (prim
// 0: occluded) after the timing.
struct EmbreeTracer {
  EmbreePeer* peer;
  EmbreeTrace how;
  Query query;
  const std::vector<kernel::Ray>* rays;
  std::vector<kernel::Hit> hits;
  std::vector<std::uint8_t> occluded;
  void trace() {
    if (query == Query::Any) {
      occluded.resize(rays->size());
      peer->occluded(*rays, occluded, how);
    } else {
      hits.resize(rays->size());
      peer->trace(*rays, hits, how);
    }
  }
  const std::vector<kernel::Hit>& answers() {
    if (query == Query::Any) {
      hits.assign(rays->size(), kernel::Hit{});
      for (std::size_t r = 0; r < rays->size(); ++r) hits[r].prim = occluded[r] ? 0 : -1;
    }
    return hits;
  }
};

// The curve scenes' Embree shapes, the main table's (strand ends) among them: how much
// the end spheres change the answers and cost Embree (full suite only).
struct EndVariant {
  CurveEnds ends;
  const char* name;
};
constexpr EndVariant kEndVariants[] = {{CurveEnds::Open, "open (no spheres)"},
                                       {CurveEnds::StrandEnds, "strand ends (main table)"},
                                       {CurveEnds::EveryEnd, "every curve end"}};

} // namespace

SuiteResult run_peers(SuiteContext& ctx) {
  auto t0 = std::chrono::steady_clock::now();
  const bool quick = ctx.config.quick;
  const bool robust = ctx.config.mode == Mode::Robust;
  const int side = timed_side(quick), rounds = timed_rounds(quick), warmup = 1;
  const std::size_t oracle_cap = quick ? 30 : 100; // the oracle takes up to 0.2 s a ray on the bear's curves
  SuiteResult res;
  res.name = "peers";
  res.title = "Peers: masq vs Embree 3 on the CPU";
  const std::string embree_why = EmbreePeer::unavailable_reason();
  Table t;
  t.title = fmt::format("masq's tracer (chosen on pilot rays) against Embree 3 (its faster API), {} x {} camera rays "
                        "and the rays from their hits{}; masq/Embree: Embree's time over masq's, median of {} rounds "
                        "(min-max); agreement = rays hit by one and missed by the other / common hits on another "
                        "primitive (not a tie in t)",
                        side, side, quick ? " (quick: indicative only)" : "", rounds);
  t.header = {"scene", "rays", "masq (pilot's choice)", "masq Mrays/s", "Embree Mrays/s", "masq/Embree CPU time",
              "masq/Embree wall", "Embree agreement", "oracle: masq / Embree right"};
  t.left_columns = 3;
  t.label_columns = 2; // scene and rays name a row; the pilot's choice is the run's answer (masq report)
  Table ends;
  ends.title = "curve ends: Embree's round Bezier curves open, and closed by sphere points of the curve's radius at "
               "the strand ends (the shape of masq's curves; the table above) or at every curve end";
  ends.header = {"scene", "rays", "Embree curve ends", "end spheres", "Embree build ms", "Embree MiB",
                 "Embree Mrays/s", "vs open", "Embree agreement", "oracle: masq / Embree right"};
  ends.left_columns = 3;
  Table build;
  build.title = fmt::format("build time and memory: masq's ref and masq structures (builder sah4, host build and the cpu "
                            "backend's upload) and Embree's scene (geometry and every BVH build), each alone, round by "
                            "round; ms: median (min-max) of {} rounds after 1 warm-up; masq/Embree: masq's time over "
                            "Embree's, per round (below 1: masq builds faster), by wall time and by CPU time",
                            rounds);
  build.header = {"scene",           "masq ref build ms", "masq ref MiB",     "masq masq build ms", "masq masq MiB",
                  "Embree build ms", "Embree MiB",        "ref/Embree wall",  "masq/Embree wall",   "ref/Embree CPU",
                  "masq/Embree CPU"};
  build.left_columns = 1;
  res.data["scenes"] = nlohmann::json::array();
  res.data["indicative"] = quick;
  int decided = 0, at_least_even = 0;
  std::string embree_description;
  for (const PeerScene& ps : peer_scenes(quick)) {
    Scene scene;
    try {
      scene = load_peer_scene(ctx.config, ps);
    } catch (const std::exception& e) {
      t.add({ps.label, "-", "unavailable: " + std::string(e.what())});
      continue;
    }
    BenchOptions pilot = pilot_options(ctx, ps.curves);
    pilot.progress = [&](const std::string& line) { ctx.say("peers " + ps.label + ": pilot: " + line); };
    BenchRun run = run_bench_kept(scene, pilot, ctx.pool);
    BenchOptions timed = pilot;
    timed.width = timed.height = side;
    ctx.say("peers " + ps.label + ": the timed rays");
    const std::vector<RayBatch> batches = make_ray_batches(scene, run.built.front(), timed, ctx.pool);
    std::unique_ptr<EmbreePeer> embree;
    std::string embree_error = embree_why;
    if (embree_error.empty()) {
      try {
        ctx.say("peers " + ps.label + ": Embree build");
        embree = std::make_unique<EmbreePeer>(2);
        embree->set_scene(scene, robust);
        embree_description = embree->description();
      } catch (const std::exception& e) {
        embree_error = e.what();
        embree.reset();
      }
    }
    nlohmann::json sj = {{"scene", ps.label},
                         {"primitives", scene.primitive_count()},
                         {"mean_radius", mean_radius(scene)},
                         {"pilot", {{"width", pilot.width}, {"height", pilot.height}}},
                         {"timed", {{"width", side}, {"height", side}, {"rounds", rounds}, {"warmup", warmup}}}};
    if (embree) sj["embree_end_spheres"] = embree->end_spheres();
    for (const BenchRow& r : run.rows) sj["pilot"]["rows"].push_back(bench_row_json(r));
    const oracle::Oracle orc(scene); // arbitrates where masq and Embree disagree
    for (const RayBatch& batch : batches) {
      const std::string set_label = std::string(ray_set_name(batch.set)) +
                                    (batch.set == RaySet::Shadow && pilot.shadow_any_hit ? " (any)" : "");
      std::vector<std::string> line = {ps.label, set_label};
      const BenchRow* best = fastest_row(run.rows, batch.set);
      if (!best) {
        line.push_back("no masq backend ran");
        t.add(line);
        continue;
      }
      line.push_back(config_label(*best));
      nlohmann::json pj = {{"rays", ray_set_name(batch.set)}, {"ray_count", batch.rays.size()},
                           {"masq_choice", bench_row_json(*best)}};
      Backend* be = ctx.pool.get(best->backend, kSoloSlot);
      if (!be) {
        line.push_back("unavailable: " + ctx.pool.why(best->backend));
        t.add(line);
        continue;
      }
      // Every sample traces at least as many rays as the camera's (side x side). The
      // shadow and diffuse sets hold only the rays from hits (6K-33K on the hair, 4-15 ms
      // a trace): traced once, a trace that short often ran on one of the two threads,
      // the other joining late or not at all (masq's and Embree's CPU time over wall time
      // 1.0-1.4 in their rounds), so their ratios measured wake-ups as much as tracing.
      const int passes = traces_per_sample(batch.rays.size(), std::size_t(side) * std::size_t(side));
      pj["traces_per_sample"] = passes;
      // Occlusion queries: the chosen structure's BLAS order by a pilot of its own, on the
      // pilot's shadow rays, where its BLAS have inner nodes (bench/occlusion_pilot.h).
      const PackedScene& structure = row_structure(run.built_for(*best), *best);
      const BlasOcclusion own = structure.features.blas_starts_last ? BlasOcclusion::StartsLast : BlasOcclusion::Nearest;
      BlasOcclusion order = own;
      if (best->query == Query::Any && blas_order_matters(structure)) {
        try {
          const OcclusionOrderChoice oc =
              occlusion_order_pilot(ctx, ps.label, run, best->backend, structure, *be, pilot.sample_rays);
          order = oc.order;
          pj["blas_occlusion"] = oc.json();
        } catch (const std::exception& e) {
          ctx.pool.close(best->backend, kSoloSlot);
          line.push_back(std::string("unavailable: ") + e.what());
          t.add(line);
          continue;
        }
        if (order == BlasOcclusion::StartsLast) line.back() += " starts-last";
      }
      std::vector<kernel::Hit> masq_hits(batch.rays.size());
      std::vector<std::function<void()>> tracers = {
          repeated([&] { be->trace(batch.rays, masq_hits, {}, best->query); }, passes)};
      std::vector<EmbreeTracer> embree_tracers;
      if (embree)
        for (EmbreeApi api : {EmbreeApi::PerRay, EmbreeApi::Stream})
          embree_tracers.push_back({embree.get(), {api, batch.set == RaySet::Primary}, best->query, &batch.rays, {}, {}});
      for (EmbreeTracer& et : embree_tracers) tracers.push_back(repeated([&et] { et.trace(); }, passes));
      std::vector<std::vector<TraceClock>> times;
      try {
        ctx.say(fmt::format("peers {}: {} rays, masq's {} and Embree, {} rounds", ps.label, set_label,
                            config_label(*best), rounds));
        if (order == own) be->set_scene(structure);
        else be->set_scene(with_blas_occlusion(structure, order));
        times = time_round_by_round(tracers, warmup, rounds);
      } catch (const std::exception& e) {
        ctx.pool.close(best->backend, kSoloSlot);
        line.push_back(std::string("unavailable: ") + e.what());
        t.add(line);
        continue;
      }
      ctx.pool.close(best->backend, kSoloSlot);
      auto rate = [&](const std::vector<TraceClock>& tc) {
        std::vector<double> w;
        for (const TraceClock& c : tc) w.push_back(c.wall);
        return double(batch.rays.size()) * passes / spread_of(w).median * 1e-6;
      };
      auto clock_json = [](const std::vector<TraceClock>& tc) {
        std::vector<double> w, c;
        for (const TraceClock& x : tc) w.push_back(x.wall), c.push_back(x.cpu);
        return nlohmann::json{{"wall_seconds", spread_of(w).json()}, {"cpu_seconds", spread_of(c).json()}};
      };
      const double masq_rate = rate(times[0]);
      line.push_back(fmt::format("{:.3f}", masq_rate));
      pj["masq"] = clock_json(times[0]);
      pj["masq"]["mrays_per_s"] = masq_rate;
      if (!embree) {
        line.insert(line.end(), {"unavailable", "-", "-", "-", "-"});
        pj["embree"] = {{"unavailable", embree_error}};
        t.add(line);
        sj["peers"].push_back(pj);
        continue;
      }
      // Embree's faster API by median CPU time is the one masq is measured against.
      std::size_t fast = 0;
      std::vector<Spread> cpu_of;
      for (std::size_t k = 0; k < embree_tracers.size(); ++k) {
        std::vector<double> c;
        for (const TraceClock& x : times[k + 1]) c.push_back(x.cpu);
        cpu_of.push_back(spread_of(c));
        if (cpu_of[k].median < cpu_of[fast].median) fast = k;
        nlohmann::json ej = clock_json(times[k + 1]);
        ej["api"] = embree_api_name(embree_tracers[k].how.api);
        ej["coherent_hint"] = embree_tracers[k].how.coherent;
        ej["mrays_per_s"] = rate(times[k + 1]);
        pj["embree_apis"].push_back(ej);
      }
      const Spread by_cpu = spread_of(per_round(times[fast + 1], times[0], cpu_ratio));
      const Spread by_wall = spread_of(per_round(times[fast + 1], times[0], wall_ratio));
      line.push_back(fmt::format("{:.3f} ({})", rate(times[fast + 1]), embree_api_name(embree_tracers[fast].how.api)));
      line.push_back(ratio_text(by_cpu));
      line.push_back(ratio_text(by_wall));
      ctx.say("peers " + ps.label + ": the oracle on the rays where masq and Embree differ");
      Agreement g = agree(masq_hits, embree_tracers[fast].answers(), best->query);
      Arbitration arb = arbitrate(orc, batch.rays, masq_hits, embree_tracers[fast].answers(), g.differing, best->query,
                                  oracle_cap);
      line.push_back(g.text());
      line.push_back(arb.text());
      ++decided;
      at_least_even += by_cpu.median >= 1.0;
      pj["embree"] = {{"api", embree_api_name(embree_tracers[fast].how.api)},
                      {"mrays_per_s", rate(times[fast + 1])},
                      {"hit_miss_disagree", g.hit_miss},
                      {"common_hits", g.common},
                      {"other_primitive", g.other_prim},
                      {"oracle", {{"traced", arb.traced}, {"masq_right", arb.a_right}, {"embree_right", arb.b_right}}}};
      pj["masq_over_embree_cpu"] = by_cpu.json();
      pj["masq_over_embree_wall"] = by_wall.json();
      t.add(line);
      // Full suite, curves at the file's radius: Embree's other curve ends, in turn.
      const bool has_curves = std::any_of(scene.geometries.begin(), scene.geometries.end(), [](const Geometry& geo) {
        return scene_prim_row(geo.type).shape == PrimShape::Bezier;
      });
      if (!quick && has_curves && !ps.thick) {
        try {
          std::vector<std::unique_ptr<EmbreePeer>> owned;
          std::vector<EmbreeTracer> variants;
          for (const EndVariant& v : kEndVariants) {
            EmbreePeer* peer = embree.get();
            if (v.ends != CurveEnds::StrandEnds) {
              ctx.say(std::string("peers ") + ps.label + ": Embree build, curve ends " + v.name);
              owned.push_back(std::make_unique<EmbreePeer>(2));
              owned.back()->set_scene(scene, robust, v.ends);
              peer = owned.back().get();
            }
            variants.push_back({peer, embree_tracers[fast].how, best->query, &batch.rays, {}, {}});
          }
          std::vector<std::function<void()>> vt;
          for (EmbreeTracer& et : variants) vt.push_back(repeated([&et] { et.trace(); }, passes));
          std::vector<std::vector<TraceClock>> vtimes = time_round_by_round(vt, warmup, rounds);
          const double open_rate = rate(vtimes[0]);
          for (std::size_t k = 0; k < variants.size(); ++k) {
            const EmbreePeer& peer = *variants[k].peer;
            Agreement vg = agree(masq_hits, variants[k].answers(), best->query);
            Arbitration va = arbitrate(orc, batch.rays, masq_hits, variants[k].answers(), vg.differing, best->query,
                                       oracle_cap);
            ends.add({ps.label, set_label, kEndVariants[k].name, std::to_string(peer.end_spheres()),
                      fmt::format("{:.1f}", peer.timing().build_seconds * 1e3),
                      fmt::format("{:.2f}", peer.bytes() / 1048576.0), fmt::format("{:.3f}", rate(vtimes[k])),
                      fmt::format("{:.2f}x", rate(vtimes[k]) / open_rate), vg.text(), va.text()});
            nlohmann::json vj = clock_json(vtimes[k]);
            vj["ends"] = kEndVariants[k].name;
            vj["end_spheres"] = peer.end_spheres();
            vj["build_seconds"] = peer.timing().build_seconds;
            vj["bytes"] = peer.bytes();
            vj["hit_miss_disagree"] = vg.hit_miss;
            pj["embree_curve_ends"].push_back(vj);
          }
        } catch (const std::exception& e) {
          ends.add({ps.label, set_label, "unavailable: " + std::string(e.what())});
        }
      }
      sj["peers"].push_back(pj);
    }
    const std::string& first = pilot.backends.empty() ? std::string() : pilot.backends.front();
    const BenchRow* rr = find_row(run.rows, first, Method::Ref, RaySet::Primary, Builder::Sah4);
    const BenchRow* rm = find_row(run.rows, first, Method::Masq, RaySet::Primary, Builder::Sah4);
    auto accel = [](const BenchRow* r) {
      return r ? fmt::format("{:.2f}", (r->accel_bytes + r->prim_bytes) / 1048576.0) : std::string("n/a");
    };
    ctx.say("peers " + ps.label + ": build rounds");
    AccelOptions build_opt = pilot.accel;
    build_opt.builder.kind = Builder::Sah4;
    build_opt.nodes = NodeFormat::W4;
    try {
      const PeerBuildTimes bt = time_peer_builds(scene, build_opt, 2, robust, warmup, rounds);
      auto ms = [](const std::vector<TraceClock>& tc) {
        std::vector<double> w;
        for (const TraceClock& c : tc) w.push_back(c.wall * 1e3);
        const Spread s = spread_of(w);
        return tc.empty() ? std::string("n/a") : fmt::format("{:.1f} ({:.1f}-{:.1f})", s.median, s.min, s.max);
      };
      // masq's time over Embree's: per_round(a, b, f) = f(a[k], b[k]).
      auto over = [&](const std::vector<TraceClock>& m, double (*f)(const TraceClock&, const TraceClock&)) {
        return bt.embree.empty() ? std::string("n/a") : ratio_text(spread_of(per_round(m, bt.embree, f)));
      };
      build.add({ps.label, ms(bt.ref), accel(rr), ms(bt.masq), accel(rm),
                 bt.embree.empty() ? "n/a: " + bt.embree_error : ms(bt.embree),
                 embree ? fmt::format("{:.2f}", embree->bytes() / 1048576.0) : "n/a", over(bt.ref, wall_ratio),
                 over(bt.masq, wall_ratio), over(bt.ref, cpu_ratio), over(bt.masq, cpu_ratio)});
      auto clocks = [](const std::vector<TraceClock>& tc) {
        std::vector<double> w, c;
        for (const TraceClock& x : tc) w.push_back(x.wall), c.push_back(x.cpu);
        return nlohmann::json{{"wall_seconds", spread_of(w).json()}, {"cpu_seconds", spread_of(c).json()}};
      };
      sj["builds"] = {{"ref", clocks(bt.ref)}, {"masq", clocks(bt.masq)}};
      if (!bt.embree.empty()) sj["builds"]["embree"] = clocks(bt.embree);
    } catch (const std::exception& e) {
      build.add({ps.label, "unavailable: " + std::string(e.what())});
    }
    if (embree) sj["embree_build_seconds"] = embree->timing().build_seconds, sj["embree_bytes"] = embree->bytes();
    res.data["scenes"].push_back(sj);
  }
  res.data["rows_decided"] = decided;
  res.data["rows_masq_at_least_even"] = at_least_even;
  t.notes = {
      embree_why.empty()
          ? fmt::format("Embree: {}; the same two oneTBB threads as masq's cpu backend, started once; timed with "
                        "rtcIntersect1 per ray and with its stream API rtcIntersect1M (rtcOccluded1 / rtcOccluded1M "
                        "for shadow rays, which stop at the first hit, as masq's occlusion kernel does; the coherent "
                        "hint on camera rays), the faster by CPU time counts. Capsules as round linear curves, cubic "
                        "curves as round Bezier curves closed by sphere points, the ground plane as triangles",
                        embree_description.empty() ? EmbreePeer::version() : embree_description)
          : "Embree: " + embree_why,
      fmt::format("masq/Embree: per round, Embree's time over masq's (above 1: masq is faster), median and range over "
                  "{} rounds after {} warm-up; each round traces masq and both Embree APIs once (a ray set of fewer "
                  "rays than the camera's several times over, to as many rays: traces_per_sample in the JSON), the "
                  "order rotating round by round, {} ms apart; CPU time: the process's, every thread (this machine is shared: "
                  "CPU time decides, wall time shown beside it)",
                  rounds, warmup, 30),
      fmt::format("masq (pilot's choice): the fastest of masq's tracers by CPU time on pilot rays of their own ({} camera rays "
                  "and the rays from their hits, never the timed ones; each sample of a set traces at least as many rays as "
                  "the pilot's camera, repeating the set): cpu and opencl x {} x builder sah, "
                  "sah4 x nodes {}{}; Embree's robust flag {} masq's {} mode",
                  quick ? "128 x 96" : "192 x 192", quick ? "ref, masq" : "ref, masq, cluster",
                  quick ? "w4, w8, o4" : "w4, w8, o4, q8", quick ? " (quick: roving curves)" : ", curves phantom and roving",
                  robust ? "set beside" : "off (its default) beside", mode_name(ctx.config.mode)),
      fmt::format("starts-last: shadow rows whose structure has BLAS inner nodes (not masq's over thin primitives "
                  "alone), its occlusion queries traced both ways on the pilot's shadow rays, {} rounds, and kept where "
                  "faster by more than {:.0f}%: each BLAS node's inner children "
                  "the ray enters after t_min first, those it starts in last (--blas-occlusion; the same rays occluded "
                  "either way), against nearest first; blas_occlusion in the JSON",
                  kOrderRounds, kOrderMargin * 100),
      fmt::format("oracle: of the differing rays (at most {}, evenly spread), how many masq and Embree answer as the "
                  "long-double oracle does",
                  oracle_cap),
      "curves: table1's phantom x1 cubics (the strands as round cones chained into Catmull-Rom curves, one Bezier "
      "piece per segment); Embree gets the same fp32 Bezier control points and radius. Embree 3's round Bezier curves "
      "are open tubes (man RTC_GEOMETRY_TYPE_CURVE(3), Round Curves), masq's the union of balls along the curve; "
      "sphere points of the curve's radius at every strand end give Embree masq's shape",
      fmt::format("thick: every radius {} x the scene's mean segment length", kThickRadius)};
  ends.notes = {fmt::format("the three Embree scenes traced in turn round by round with the main table's API, median "
                            "of {} rounds after {} warm-up; vs open: Embree's rate over its rate on open curves (the "
                            "cost of the spheres); agreement and oracle against the same masq tracer",
                            rounds, warmup)};
  build.notes = {"masq: build_accel (2 threads) then the cpu backend's set_scene, builder sah4 (leaves priced per "
                 "block of four, as Embree's SAH prices its four-wide leaves), nodes w4; MiB: nodes + instances + "
                 "primitives; Embree: its geometry and rtcCommitScene of every scene at its default (medium) quality, "
                 "memory from Embree's device memory monitor"};
  res.tables = {t, build};
  if (!ends.rows.empty()) res.tables.push_back(ends);
  res.method = fmt::format("{0}x{0} camera rays ({1}) and the shadow and diffuse rays derived from their hits; masq's "
                           "tracer chosen per ray set on separate pilot rays; masq and Embree traced round by round, "
                           "{2} rounds after {3} warm-up; masq faster than or even with Embree by median CPU time on "
                           "{4} of {5} rows.",
                           side, quick ? "quick: indicative only" : "at least 262,144", rounds, warmup, at_least_even,
                           decided);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

} // namespace masq
