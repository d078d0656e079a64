// peers: masq against Embree 3 (the Debian package; round linear curves for capsules
// and links, round Bezier curves closed by sphere points for cubics, triangles) and the
// driver's ray query, on the same rays, as ratios measured in the same run.
#include "bench/bench_report.h"
#include "bench/suite.h"
#include "oracle/oracle.h"
#include "peers/embree_peer.h"
#include "masq/error.h"
#include "scenes/curve_tools.h"
#include "scenes/prim_table.h"
#include "scenes/generators.h"
#include "scenes/loaders/load_any.h"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
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

struct PeerTimes {
  double median = 0, min = 0, max = 0;
};

// masq's fastest row and Embree are each timed on their own: the row's structure is
// uploaded again into a slot of its own and traced warm-up + repetitions times in a
// row, before Embree traces anything in the scene; Embree then the same way. In the
// lanes every masq trace follows another method's, whose structure has pushed its own
// out of the caches, while Embree's traces follow each other. masq goes first because
// Embree's worker threads keep a core busy for a while after its traces return (timed
// right after Embree, masq's cpu rows lost up to half their rate).
// The structure a row traced: auto by pilot's kept candidate, else the method's own.
const PackedScene& row_structure(const BuiltMethods& built, const BenchRow& row) {
  if (row.method == Method::Auto)
    for (const PackedScene& c : built.auto_candidates.built)
      if (c.method == row.build.auto_choice) return c;
  return built.scenes.at(row.method);
}

PeerTimes times_of(std::vector<double> t) {
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front(), t.back()};
}

constexpr int kSoloSlot = 3000; // bench/backend_pool.h: past the lanes' and pilots'

PeerTimes time_masq_alone(BackendPool& pool, const BuiltMethods& built, const BenchRow& best,
                          const std::vector<kernel::Ray>& rays, const BenchOptions& opt) {
  Backend* be = pool.get(best.backend, kSoloSlot);
  if (!be) throw Error("peers: backend " + best.backend + " could not open a slot to time masq's fastest tracer");
  std::vector<double> t;
  std::vector<kernel::Hit> hits(rays.size());
  try {
    be->set_scene(row_structure(built, best));
    if (be->device_bytes() != best.device_bytes)
      throw Error(fmt::format("peers: {} {} uploaded again holds {} bytes on the device, its lane {}", best.backend,
                              method_name(best.method), be->device_bytes(), best.device_bytes));
    for (int i = 0; i < opt.warmup + opt.repetitions; ++i) {
      be->trace(rays, hits, {}, best.query);
      if (i >= opt.warmup) t.push_back(be->timing().trace_seconds);
    }
  } catch (...) {
    pool.close(best.backend, kSoloSlot);
    throw;
  }
  pool.close(best.backend, kSoloSlot);
  // Every method finds the same hits, so this only catches gross errors; the bytes
  // above tell the structures apart.
  std::size_t differ = 0;
  for (std::size_t i = 0; i < best.hits.size() && i < hits.size(); ++i) {
    const kernel::Hit &a = best.hits[i], &b = hits[i];
    differ += a.prim != b.prim || (a.prim >= 0 && (a.geom != b.geom || a.inst != b.inst || a.t != b.t));
  }
  if (differ)
    throw Error(fmt::format("peers: {} {} traced alone disagrees with its lane on {} of {} rays", best.backend,
                            method_name(best.method), differ, rays.size()));
  return times_of(t);
}

// Embree on the batch: rtcIntersect1 for closest-hit sets, rtcOccluded1 for occlusion
// sets (whose hits then only say occluded, prim 0, or not, prim -1). Several scenes
// take turns round by round, so that the machine's drift reaches each alike.
std::vector<PeerTimes> time_embree(const std::vector<EmbreePeer*>& peers, const std::vector<kernel::Ray>& rays,
                                   std::vector<std::vector<kernel::Hit>>& hits, Query query, int warmup, int rounds) {
  std::vector<std::vector<double>> t(peers.size());
  std::vector<std::uint8_t> occluded(rays.size());
  hits.assign(peers.size(), std::vector<kernel::Hit>(rays.size()));
  for (int i = 0; i < warmup + rounds; ++i)
    for (std::size_t k = 0; k < peers.size(); ++k) {
      if (query == Query::Any) {
        peers[k]->occluded(rays, occluded);
        for (std::size_t r = 0; r < rays.size(); ++r) {
          hits[k][r] = kernel::Hit{};
          hits[k][r].prim = occluded[r] ? 0 : -1;
        }
      } else {
        peers[k]->trace(rays, hits[k]);
      }
      if (i >= warmup) t[k].push_back(peers[k]->timing().trace_seconds);
    }
  std::vector<PeerTimes> out;
  for (std::vector<double>& tk : t) out.push_back(times_of(tk));
  return out;
}

// The fastest available row of a ray set among masq's tracers, or among the driver's
// (rayquery, rtpipeline: the driver's BVH calling masq's intersectors).
const BenchRow* fastest_row(const std::vector<BenchRow>& rows, RaySet set, bool driver) {
  const BenchRow* best = nullptr;
  for (const BenchRow& r : rows) {
    if (r.ray_set != set || !r.unavailable.empty() || driver_traversal(r.backend) != driver) continue;
    if (!best || r.mrays_per_s() > best->mrays_per_s()) best = &r;
  }
  return best;
}

struct PeerScene {
  std::string label;
  std::string file;    // under data_dir; empty: the embedded default bundle
  bool curves = false; // the strands as table1's cubic curves instead of as loaded
};

Scene load_peer_scene(const SuiteConfig& cfg, const PeerScene& ps) {
  if (ps.file.empty()) return make_default_scene();
  std::string path = (std::filesystem::path(cfg.data_dir) / ps.file).string();
  if (!ps.curves) return load_scene_file(path);
  // The cubics of table1's phantom x1 (bench/suite_hair.cpp make_case): the strands as
  // round cones, chained into Catmull-Rom curves through their points, one Bezier piece
  // per segment. Embree gets these very fp32 control points (embree_peer.cpp).
  LoadOptions lo;
  lo.strand_type = PrimType::RoundCone;
  return segments_to_curves(load_scene_file(path, lo));
}

// One Embree scene on one ray set: its time alone, its agreement with masq's best and
// the oracle's word on where they differ.
struct EmbreeRun {
  PeerTimes times;
  double mrays = 0;
  Agreement agreement;
  Arbitration oracle;
  nlohmann::json json() const {
    return {{"mrays_per_s", mrays},
            {"trace_seconds", {{"median", times.median}, {"min", times.min}, {"max", times.max}}},
            {"hit_miss_disagree", agreement.hit_miss},
            {"common_hits", agreement.common},
            {"other_primitive", agreement.other_prim},
            {"oracle", {{"traced", oracle.traced}, {"masq_right", oracle.a_right}, {"embree_right", oracle.b_right}}}};
  }
};

// Each of `peers` on one ray set (round by round: time_embree), against masq's best;
// the oracle traces at most oracle_cap of the differing rays of each.
std::vector<EmbreeRun> run_embree(const std::vector<EmbreePeer*>& peers, const oracle::Oracle& orc,
                                  const RayBatch& batch, const BenchRow& best, int warmup, int rounds,
                                  std::size_t oracle_cap = 300) {
  std::vector<std::vector<kernel::Hit>> hits;
  std::vector<PeerTimes> times = time_embree(peers, batch.rays, hits, best.query, warmup, rounds);
  std::vector<EmbreeRun> out(peers.size());
  for (std::size_t k = 0; k < peers.size(); ++k) {
    EmbreeRun& r = out[k];
    r.times = times[k];
    r.mrays = batch.rays.size() / r.times.median * 1e-6;
    r.agreement = agree(best.hits, hits[k], best.query);
    r.oracle = arbitrate(orc, batch.rays, best.hits, hits[k], r.agreement.differing, best.query, oracle_cap);
  }
  return out;
}

// The curve scenes' Embree shapes, the main table's (strand ends) among them: how much
// the end spheres change the answers and cost Embree. Timed in turn round by round, for
// kEndRounds x the repetitions (an Embree trace of the quick batch takes milliseconds,
// where one burst of the shared machine's load swung a median of three by 2x).
struct EndVariant {
  CurveEnds ends;
  const char* name;
};
constexpr EndVariant kEndVariants[] = {{CurveEnds::Open, "open (no spheres)"},
                                       {CurveEnds::StrandEnds, "strand ends (main table)"},
                                       {CurveEnds::EveryEnd, "every curve end"}};
constexpr int kEndRounds = 5;
// The oracle takes about 0.2 s a ray on the bear's 144k curves, and open ends differ on
// hundreds of rays per set: quick runs arbitrate fewer of them.
constexpr std::size_t kEndOracleCapQuick = 50;

} // namespace

SuiteResult run_peers(SuiteContext& ctx) {
  auto t0 = std::chrono::steady_clock::now();
  const bool quick = ctx.config.quick;
  SuiteResult res;
  res.name = "peers";
  res.title = "Peers: masq vs Embree 3 and the driver's traversal";
  const std::string embree_why = EmbreePeer::unavailable_reason();
  BenchOptions opt = ctx.bench_options(quick ? 128 : 320, quick ? 96 : 240);
  opt.keep_per_ray = true;
  // masq's tracers: every backend x method on the default builder's structures and on
  // sah4's, whose full four-primitive leaves suit the cpu's four-lane capsule test (as
  // Embree prices its leaves per block of its SIMD width); the fastest is masq's best.
  opt.builders = {Builder::Sah, Builder::Sah4};
  // ... and on AABB and oriented wide nodes (o4: Embree's hair BVH also rotates nodes).
  opt.node_formats = {NodeFormat::W4, NodeFormat::O4};
  Table t;
  t.title = "Mrays/s on the same rays; agreement with masq's best = rays hit by one and missed by the other / common "
            "hits on another primitive (not a tie in t)";
  t.header = {"scene", "rays", "masq best", "Mrays/s (lanes)", "Mrays/s (alone)", "Embree 3 (alone)",
              "masq/Embree", "Embree agreement",
              "oracle: masq / Embree right", "driver best", "driver/masq", "driver agreement"};
  t.left_columns = 3;
  Table ends;
  ends.title = "curve ends: Embree's round Bezier curves open, and closed by sphere points of the curve's radius at "
               "the strand ends (the shape of masq's curves; the table above) or at every curve end";
  ends.header = {"scene", "rays", "Embree curve ends", "end spheres", "Embree build ms", "Embree MiB",
                 "Embree Mrays/s (alone)", "vs open", "Embree agreement", "oracle: masq / Embree right"};
  ends.left_columns = 3;
  Table build;
  build.title = "build time and memory";
  build.header = {"scene", "masq ref build ms", "masq ref MiB", "masq masq build ms", "masq masq MiB", "Embree build ms",
                  "Embree MiB"};
  build.left_columns = 1;
  res.data["scenes"] = nlohmann::json::array();
  for (const PeerScene& ps : {PeerScene{"bear fur (TressFX 3), capsules", "hair/tressfx3_bear.tfx"},
                              PeerScene{"bear fur (TressFX 3), curves", "hair/tressfx3_bear.tfx", true},
                              PeerScene{"default bundle (N=1000 r=0.002 tilt 45 + ground)", ""}}) {
    Scene scene;
    try {
      scene = load_peer_scene(ctx.config, ps);
    } catch (const std::exception& e) {
      t.add({ps.label, "-", "unavailable: " + std::string(e.what())});
      continue;
    }
    opt.progress = [&](const std::string& line) { ctx.say("peers " + ps.label + ": " + line); };
    // Cubic curves: both curve intersectors take turns in the lanes, so masq's best is
    // the faster of them (the row names roving when it wins); the quick variant runs
    // roving alone (both doubled its curve scene's time: 556 s against 249 s in all).
    BenchOptions scene_opt = opt;
    if (ps.curves)
      scene_opt.curve_isects = quick ? std::vector<CurveIsect>{CurveIsect::Roving}
                                     : std::vector<CurveIsect>{CurveIsect::Phantom, CurveIsect::Roving};
    BenchRun run = run_bench_kept(scene, scene_opt, ctx.pool);
    const std::vector<RayBatch>& batches = run.batches;
    const std::vector<BenchRow>& rows = run.rows;
    std::vector<PeerTimes> masq_alone(batches.size());
    std::vector<std::string> alone_error(batches.size());
    for (std::size_t b = 0; b < batches.size(); ++b)
      if (const BenchRow* best = fastest_row(rows, batches[b].set, false)) {
        ctx.say("peers " + ps.label + ": masq's fastest alone, " + ray_set_name(batches[b].set));
        try {
          masq_alone[b] = time_masq_alone(ctx.pool, run.built_for(*best), *best, batches[b].rays, opt);
        } catch (const std::exception& e) {
          alone_error[b] = e.what();
        }
      }
    std::unique_ptr<EmbreePeer> embree;
    std::string embree_error = embree_why;
    if (embree_error.empty()) {
      try {
        ctx.say("peers " + ps.label + ": Embree build");
        embree = std::make_unique<EmbreePeer>(2);
        embree->set_scene(scene, ctx.config.mode == Mode::Robust);
      } catch (const std::exception& e) {
        embree_error = e.what();
        embree.reset();
      }
    }
    // Curve scenes: Embree's other curve ends (kEndVariants), each a scene of its own.
    std::vector<std::unique_ptr<EmbreePeer>> variants; // null: the main peer
    bool has_curves = std::any_of(scene.geometries.begin(), scene.geometries.end(),
                                  [](const Geometry& g) { return scene_prim_row(g.type).shape == PrimShape::Bezier; });
    if (embree && has_curves) {
      try {
        for (const EndVariant& v : kEndVariants) {
          if (v.ends == CurveEnds::StrandEnds) {
            variants.emplace_back(); // the main peer
            continue;
          }
          ctx.say(std::string("peers ") + ps.label + ": Embree build, curve ends " + v.name);
          variants.push_back(std::make_unique<EmbreePeer>(2));
          variants.back()->set_scene(scene, ctx.config.mode == Mode::Robust, v.ends);
        }
      } catch (const std::exception& e) {
        ends.add({ps.label, "-", "unavailable: " + std::string(e.what())});
        variants.clear();
      }
    }
    nlohmann::json sj = {{"scene", ps.label}, {"primitives", scene.primitive_count()}};
    if (embree) sj["embree_end_spheres"] = embree->end_spheres();
    const oracle::Oracle orc(scene); // arbitrates where masq and a peer disagree
    for (const BenchRow& r : rows) sj["results"].push_back(bench_row_json(r));
    for (std::size_t b = 0; b < batches.size(); ++b) {
      const RayBatch& batch = batches[b];
      const BenchRow* best = fastest_row(rows, batch.set, false);
      const BenchRow* best_rq = fastest_row(rows, batch.set, true);
      std::vector<std::string> line = {ps.label, std::string(ray_set_name(batch.set)) +
                                                     (batch.set == RaySet::Shadow && opt.shadow_any_hit ? " (any)" : "")};
      if (!best) {
        line.push_back("no masq backend ran");
        t.add(line);
        continue;
      }
      line.push_back(fmt::format("{} {}{}", best->backend, method_label(*best),
                                 best->nodes == NodeFormat::W4 ? "" : std::string(" ") + node_format_name(best->nodes)));
      line.push_back(fmt::format("{:.3f}", best->mrays_per_s()));
      nlohmann::json pj = {{"rays", ray_set_name(batch.set)}, {"masq_best", bench_row_json(*best)}};
      if (!alone_error[b].empty()) {
        line.insert(line.end(), {"unavailable: " + alone_error[b], "-", "-", "-", "-"});
      } else if (embree) {
        ctx.say("peers " + ps.label + ": Embree " + ray_set_name(batch.set) + ", then the oracle on the differing rays");
        EmbreeRun er = run_embree({embree.get()}, orc, batch, *best, opt.warmup, opt.repetitions).front();
        const PeerTimes& mt = masq_alone[b];
        double masq_mrays = batch.rays.size() / mt.median * 1e-6;
        line.push_back(fmt::format("{:.3f}", masq_mrays));
        line.push_back(fmt::format("{:.3f}", er.mrays));
        line.push_back(fmt::format("{:.2f}x", masq_mrays / er.mrays));
        line.push_back(er.agreement.text());
        line.push_back(er.oracle.text());
        pj["masq_alone"] = {{"mrays_per_s", masq_mrays},
                            {"trace_seconds", {{"median", mt.median}, {"min", mt.min}, {"max", mt.max}}}};
        pj["embree"] = er.json();
        // The same rays through each of Embree's curve ends, in turn.
        std::vector<EmbreePeer*> peers;
        for (const std::unique_ptr<EmbreePeer>& v : variants) peers.push_back(v ? v.get() : embree.get());
        if (!peers.empty())
          ctx.say(std::string("peers ") + ps.label + ": Embree " + ray_set_name(batch.set) + ", curve ends in turn");
        std::vector<EmbreeRun> vr =
            run_embree(peers, orc, batch, *best, opt.warmup, kEndRounds * opt.repetitions,
                       quick ? kEndOracleCapQuick : std::size_t(300));
        for (std::size_t k = 0; k < vr.size(); ++k) {
          const EmbreePeer& peer = *peers[k];
          ends.add({ps.label, line[1], kEndVariants[k].name, std::to_string(peer.end_spheres()),
                    fmt::format("{:.1f}", peer.timing().build_seconds * 1e3),
                    fmt::format("{:.2f}", peer.bytes() / 1048576.0), fmt::format("{:.3f}", vr[k].mrays), fmt::format("{:.2f}x", vr[k].mrays / vr[0].mrays),
                    vr[k].agreement.text(), vr[k].oracle.text()});
          nlohmann::json vj = vr[k].json();
          vj["ends"] = kEndVariants[k].name;
          vj["end_spheres"] = peer.end_spheres();
          vj["build_seconds"] = peer.timing().build_seconds;
          vj["bytes"] = peer.bytes();
          pj["embree_curve_ends"].push_back(vj);
        }
      } else {
        line.push_back(fmt::format("{:.3f}", batch.rays.size() / masq_alone[b].median * 1e-6));
        line.insert(line.end(), {"unavailable", "-", "-", "-"});
        pj["embree"] = {{"unavailable", embree_error}};
      }
      if (best_rq) {
        Agreement g = agree(best->hits, best_rq->hits, best->query);
        line.push_back(fmt::format("{} {} {:.3f}", best_rq->backend, method_name(best_rq->method),
                                   best_rq->mrays_per_s()));
        line.push_back(fmt::format("{:.2f}x", best_rq->mrays_per_s() / best->mrays_per_s()));
        line.push_back(g.text());
        pj["driver_best"] = bench_row_json(*best_rq);
        pj["driver_hit_miss_disagree"] = g.hit_miss;
      } else {
        line.insert(line.end(), {"unavailable", "-", "-"});
      }
      t.add(line);
      sj["peers"].push_back(pj);
    }
    const BenchRow* rr = find_row(rows, opt.backends.front(), Method::Ref, RaySet::Primary, Builder::Sah);
    const BenchRow* rm = find_row(rows, opt.backends.front(), Method::Masq, RaySet::Primary, Builder::Sah);
    auto ms = [](const BenchRow* r) { return r ? fmt::format("{:.1f}", (r->build_s + r->scene_s) * 1e3) : std::string("n/a"); };
    auto accel = [](const BenchRow* r) {
      return r ? fmt::format("{:.2f}", (r->accel_bytes + r->prim_bytes) / 1048576.0) : std::string("n/a");
    };
    build.add({ps.label, ms(rr), accel(rr), ms(rm), accel(rm),
               embree ? fmt::format("{:.1f}", embree->timing().build_seconds * 1e3) : "n/a",
               embree ? fmt::format("{:.2f}", embree->bytes() / 1048576.0) : "n/a"});
    res.data["scenes"].push_back(sj);
  }
  t.notes = {embree_why.empty() ? "Embree: " + EmbreePeer::version() + ", 2 threads, rtcIntersect1 per ray (rtcOccluded1 for shadow rays, as masq traces them: any hit, early exit); capsules as "
                                  "round linear curves, cubic curves as round Bezier curves closed by sphere points, the "
                                  "ground plane as triangles"
                                : "Embree: " + embree_why,
             "oracle: of the differing rays (at most 300, evenly spread), how many masq and Embree answer as the "
             "long-double oracle does",
             "masq best: the fastest of masq's own tracers (cpu, vulkan, opencl x ref, masq, cluster, auto, each on "
             "the default sah builder's structures and on sah4's: docs/builders.md, in node formats w4 and o4: docs/kernels.md) in the lanes, where the methods of a backend take turns round by round; alone: that tracer's structure "
             "uploaded again and its warm-up and timed traces run in a row, as Embree's then are (in the lanes each "
             "trace follows another method's, with cold caches); masq/Embree: both alone",
             "driver: the driver's BVH with masq's intersectors (rayquery, rtpipeline), best of their methods and two "
             "builders",
             "curves: table1's phantom x1 cubics (the strands as round cones chained into Catmull-Rom curves, one "
             "Bezier piece per segment), traced by masq with the run's curve intersector; Embree gets the same fp32 "
             "Bezier control points and radius. Embree 3's round Bezier curves sweep a circle and are open at both "
             "ends (man RTC_GEOMETRY_TYPE_CURVE(3), Round Curves), masq's are the union of balls along the curve; "
             "sphere points of the curve's radius at every strand end (and at a joint whose next curve is thinner) "
             "give Embree masq's shape, and a hit on one counts as the curve it closes. The curve ends table "
             "measures Embree without them and with one at every curve end"};
  ends.notes = {fmt::format("the three Embree scenes traced in turn round by round, median of {} rounds after {} "
                            "warm-up (so the strand ends' rate differs from the table above's); vs open: Embree's rate "
                            "over its rate on open curves (the cost of the spheres); agreement and oracle as in the "
                            "table above, against the same masq best, the oracle on at most {} of the differing rays",
                            kEndRounds * opt.repetitions, opt.warmup, quick ? kEndOracleCapQuick : 300)};
  build.notes = {"masq: host build + upload (first backend), nodes + instances + primitives; Embree: rtcCommitScene, "
                 "memory from Embree's device memory monitor"};
  res.tables = {t, build};
  if (!ends.rows.empty()) res.tables.push_back(ends);
  res.method = fmt::format("{}x{} camera rays and the shadow and diffuse rays derived from their hits; every tracer gets "
                           "the same rays; median of {} timed traces after {} warm-up; Embree timed by wall clock, after "
                           "masq's fastest tracer of every ray set was timed alone the same way.",
                           opt.width, opt.height, opt.repetitions, opt.warmup);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

} // namespace masq
