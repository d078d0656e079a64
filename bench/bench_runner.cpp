#include "bench/bench_runner.h"
#include "bench/process_clock.h"
#include "bvh/twolevel/build_accel.h"
#include "scenes/camera.h"
#include "masq/error.h"
#include <algorithm>
#include <cstdint>
#include <tuple>
#include <fmt/format.h>

namespace masq {

namespace {

void fill_counters(BenchRow& row, const std::vector<kernel::RayStats>& stats, const std::vector<kernel::Hit>& hits) {
  double t = 0, b = 0, x = 0, c = 0, h = 0;
  for (const kernel::RayStats& s : stats) {
    t += s.tlas_nodes;
    b += s.blas_nodes;
    x += s.transforms;
    c += s.isect_calls;
  }
  for (const kernel::Hit& hit : hits) h += hit.prim >= 0;
  double n = double(std::max<std::size_t>(1, stats.size()));
  row.tlas_nodes = t / n;
  row.blas_nodes = b / n;
  row.transforms = x / n;
  row.isect_calls = c / n;
  row.hit_fraction = h / n;
}

std::vector<kernel::Hit> primary_hits(const BuiltMethods& built, std::span<const kernel::Ray> rays,
                                      const BenchOptions& opt, BackendPool& pool) {
  const PackedScene& ps = built.scenes.count(Method::Ref) ? built.scenes.at(Method::Ref) : built.scenes.begin()->second;
  std::string why;
  for (const std::string& name : opt.backends) {
    Backend* be = pool.get(name);
    if (!be) continue;
    try {
      be->set_scene(ps);
      std::vector<kernel::Hit> hits(rays.size());
      be->trace(rays, hits, {});
      return hits;
    } catch (const std::exception& e) {
      why += std::string(why.empty() ? "" : "; ") + e.what();
    }
  }
  throw Error("bench: no backend could trace the primary rays for the secondary ray sets" +
              (why.empty() ? std::string() : ": " + why));
}

// One method of one build (builder x node format) on one backend: its own backend slot
// keeps its structure uploaded between the rounds of timed traces.
struct Lane {
  Method method = Method::Ref;
  const BuiltMethods* built = nullptr;
  const BenchOptions* opt = nullptr; // this build's options (builder, node format)
  Backend* be = nullptr;
  const PackedScene* uploaded = nullptr;
  std::string upload_failed; // an upload failure fails every set of the lane
  PackedScene auto_kept;     // auto by pilot: the kept candidate for the current set
  std::size_t auto_kept_index = SIZE_MAX; // which of the candidates auto_kept is
  // auto by pilot: per batch, the pilot's outcome, or why it failed.
  std::vector<PilotResult> pilots;
  std::vector<std::string> pilot_errors;
};

// Backend slots past the lanes' for the pilot's candidates (bench/backend_pool.h): lane
// l's candidate i is in kFirstPilotSlot + 8 l + i.
constexpr int kFirstPilotSlot = 1000;

Query batch_query(const RayBatch& batch, const BenchOptions& opt) {
  return batch.set == RaySet::Shadow && opt.shadow_any_hit ? Query::Any : Query::Closest;
}

void describe_structure(BenchRow& row, const PackedScene& ps) {
  row.build = ps.stats;
  row.build_s = ps.stats.build_seconds;
  row.accel_bytes = ps.acceleration_bytes();
  row.prim_bytes = ps.primitive_bytes();
  row.tlas_stack = kernel_stack_size(ps.features.tlas_stack.entries, ps.features.tlas_stack.tree);
  row.blas_stack = kernel_stack_size(ps.features.blas_stack.entries, ps.features.blas_stack.tree);
}

// The row of a lane and batch, describing the method's own structure (auto by pilot:
// prepare_lane describes the kept candidate instead).
BenchRow lane_row(const Lane& lane, const std::string& backend, const RayBatch& batch, std::size_t primitives) {
  const PackedScene& ps = lane.built->scenes.at(lane.method);
  BenchRow row;
  row.backend = backend;
  row.method = lane.method;
  row.builder = ps.builder;
  row.nodes = ps.features.nodes;
  row.curve_isect = ps.features.curve_isect;
  row.blas_occlusion = ps.features.blas_starts_last ? BlasOcclusion::StartsLast : BlasOcclusion::Nearest;
  row.ray_set = batch.set;
  row.query = batch_query(batch, *lane.opt);
  row.rays = double(batch.rays.size());
  row.primitives = primitives;
  describe_structure(row, ps);
  return row;
}


bool runs_pilot(const Lane& lane) {
  return lane.method == Method::Auto && lane.opt->auto_by == AutoBy::Pilot && !lane.built->auto_candidates.built.empty();
}

// auto by pilot: every batch's pilot before any lane uploads, each candidate in its own
// slot (or, when those cannot be opened, one after the other in the lane's own); the
// slots are closed afterwards, so that only the lanes' structures stay on the device.
void run_pilots(Lane& lane, int lane_index, const std::string& name, const std::vector<RayBatch>& batches,
                BackendPool& pool) {
  const AutoCandidates& cands = lane.built->auto_candidates;
  std::vector<int> slot_ids;
  std::vector<Backend*> slots;
  for (std::size_t i = 0; i < cands.built.size(); ++i) {
    slot_ids.push_back(kFirstPilotSlot + 8 * lane_index + int(i));
    slots.push_back(pool.get(name, slot_ids.back()));
  }
  if (std::find(slots.begin(), slots.end(), nullptr) != slots.end()) slots = {lane.be};
  lane.pilots.assign(batches.size(), {});
  lane.pilot_errors.assign(batches.size(), {});
  bool held = false; // the slots hold the candidates since an earlier batch's pilot
  for (std::size_t b = 0; b < batches.size(); ++b) {
    if (batches[b].rays.empty()) continue;
    lane.opt->say(fmt::format("{} auto {}: pilot of auto's candidates", name, ray_set_name(batches[b].set)));
    PilotOptions popt = lane.opt->pilot;
    popt.slots_hold_candidates = held;
    try {
      lane.pilots[b] = run_pilot(slots, cands, batches[b].rays, batch_query(batches[b], *lane.opt), popt);
      held = slots.size() > 1;
    } catch (const std::exception& e) {
      lane.pilot_errors[b] = std::string("auto pilot: ") + e.what();
      held = false;
    }
  }
  for (int id : slot_ids) pool.close(name, id);
}

// The structure the lane traces batch b: auto by pilot's kept candidate for it.
const PackedScene& lane_structure(Lane& lane, BenchRow& row, std::size_t b) {
  if (!runs_pilot(lane)) return lane.built->scenes.at(lane.method);
  if (!lane.pilot_errors[b].empty()) throw Error(lane.pilot_errors[b]);
  const AutoCandidates& cands = lane.built->auto_candidates;
  const PilotResult& pilot = lane.pilots[b];
  if (pilot.kept != lane.auto_kept_index) { // else it is uploaded already
    lane.uploaded = nullptr;
    lane.auto_kept = cands.built[pilot.kept];
    mark_as_auto(lane.auto_kept, cands);
    lane.auto_kept_index = pilot.kept;
  }
  for (std::size_t i = 0; i < cands.built.size(); ++i)
    row.pilot_seconds[std::size_t(cands.built[i].method)] = pilot.seconds[i];
  // A mix that is ref's structure was not traced: it has ref's time.
  if (cands.mix_is_ref) row.pilot_seconds[std::size_t(Method::Auto)] = row.pilot_seconds[std::size_t(Method::Ref)];
  row.pilot_rays = pilot.rays;
  row.pilot_mix_is_ref = cands.mix_is_ref;
  row.pilot_s = pilot.wall_seconds;
  return lane.auto_kept;
}

// Uploads (when needed) and runs the counters: the stats variant once per set.
void prepare_lane(Lane& lane, BenchRow& row, const RayBatch& batch, std::size_t b, const std::string& tag) {
  const PackedScene& ps = lane_structure(lane, row, b);
  if (&ps != &lane.built->scenes.at(lane.method)) describe_structure(row, ps);
  if (lane.uploaded != &ps) {
    lane.opt->say(tag + ": upload");
    try {
      lane.be->set_scene(ps);
    } catch (const std::exception& e) {
      lane.upload_failed = e.what();
      throw;
    }
    lane.uploaded = &ps;
  }
  row.device = lane.be->device_name();
  row.fill_rays = lane.be->fill_rays();
  row.scene_s = lane.be->timing().scene_seconds;
  std::vector<kernel::Hit> hits(batch.rays.size());
  std::vector<kernel::RayStats> stats(batch.rays.size());
  lane.opt->say(tag + ": counters");
  lane.be->trace(batch.rays, hits, stats, row.query);
  fill_counters(row, stats, hits);
  if (lane.opt->keep_per_ray) {
    row.hits = std::move(hits);
    row.stats = std::move(stats);
  }
}

// Warm-up and timed traces of the counter-free variants, the lanes taking turns.
void time_lanes(std::vector<Lane>& lanes, std::vector<BenchRow>& rows, const RayBatch& batch, const BenchOptions& opt) {
  std::vector<std::vector<TraceTiming>> times(lanes.size());
  std::vector<std::vector<double>> cpu_times(lanes.size());
  std::vector<kernel::Hit> hits(batch.rays.size());
  const int rounds = opt.warmup + opt.repetitions;
  const int passes = traces_per_sample(batch.rays.size(), opt.sample_rays);
  for (int round = 0; round < rounds; ++round) {
    opt.say(fmt::format("{} {}: trace round {}/{}", rows.empty() ? "" : rows[0].backend, ray_set_name(batch.set),
                         round + 1, rounds));
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      BenchRow& row = rows[i];
      if (!row.unavailable.empty()) continue;
      try {
        TraceTiming sum;
        const double cpu0 = process_cpu_seconds();
        for (int pass = 0; pass < passes; ++pass) {
          lanes[i].be->trace(batch.rays, hits, {}, row.query);
          const TraceTiming& t = lanes[i].be->timing();
          if (round == 0 && pass == 0) row.compile_s = t.compile_seconds;
          sum.trace_seconds += t.trace_seconds / passes;
          sum.wall_seconds += t.wall_seconds / passes;
          sum.upload_seconds += t.upload_seconds / passes;
          sum.readback_seconds += t.readback_seconds / passes;
        }
        if (round >= opt.warmup) {
          times[i].push_back(sum);
          cpu_times[i].push_back((process_cpu_seconds() - cpu0) / passes);
        }
      } catch (const std::exception& e) {
        row.unavailable = e.what();
      }
    }
  }
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    BenchRow& row = rows[i];
    if (!row.unavailable.empty() || times[i].empty()) continue;
    auto sorted = [&](double TraceTiming::*field) {
      std::vector<double> v;
      for (const TraceTiming& t : times[i]) v.push_back(t.*field);
      std::sort(v.begin(), v.end());
      return v;
    };
    const std::vector<double> device = sorted(&TraceTiming::trace_seconds);
    row.median_s = device[device.size() / 2];
    row.min_s = device.front();
    row.max_s = device.back();
    row.wall_s = sorted(&TraceTiming::wall_seconds)[device.size() / 2];
    row.upload_s = sorted(&TraceTiming::upload_seconds)[device.size() / 2];
    row.readback_s = sorted(&TraceTiming::readback_seconds)[device.size() / 2];
    std::sort(cpu_times[i].begin(), cpu_times[i].end());
    row.cpu_s = cpu_times[i][cpu_times[i].size() / 2];
    row.device_bytes = lanes[i].be->device_bytes();
  }
}

// Every lane of one backend through every batch. Rows: lane, then set. The lanes' slots
// other than the first are closed at the end (BackendPool::close).
std::vector<BenchRow> measure_backend(const std::string& name, std::vector<Lane>& lanes, std::size_t primitives,
                                      const std::vector<RayBatch>& batches, const BenchOptions& opt, BackendPool& pool) {
  for (std::size_t i = 0; i < lanes.size(); ++i)
    if (lanes[i].be && runs_pilot(lanes[i])) run_pilots(lanes[i], int(i), name, batches, pool);
  std::vector<std::vector<BenchRow>> by_lane(lanes.size());
  for (std::size_t b = 0; b < batches.size(); ++b) {
    const RayBatch& batch = batches[b];
    std::vector<BenchRow> rows;
    for (Lane& lane : lanes) {
      BenchRow row = lane_row(lane, name, batch, primitives);
      const std::string tag = fmt::format("{} {} {}", name, method_name(lane.method), ray_set_name(batch.set));
      if (!lane.be) {
        row.unavailable = pool.why(name);
      } else if (batch.rays.empty()) {
        row.unavailable = "no rays in this set (no primary hits)";
      } else if (!lane.upload_failed.empty()) {
        row.unavailable = lane.upload_failed;
      } else {
        try {
          prepare_lane(lane, row, batch, b, tag);
        } catch (const std::exception& e) {
          row.unavailable = e.what();
        }
      }
      rows.push_back(std::move(row));
    }
    time_lanes(lanes, rows, batch, opt);
    for (std::size_t i = 0; i < lanes.size(); ++i) by_lane[i].push_back(std::move(rows[i]));
  }
  for (std::size_t i = 1; i < lanes.size(); ++i) pool.close(name, int(i));
  std::vector<BenchRow> out;
  for (std::vector<BenchRow>& l : by_lane)
    for (BenchRow& r : l) out.push_back(std::move(r));
  return out;
}

// The lanes of one backend: every method of every build, each in its own slot.
std::vector<Lane> open_lanes(const std::string& name, const std::vector<const BuiltMethods*>& builds,
                             const std::vector<const BenchOptions*>& build_opts, BackendPool& pool) {
  std::vector<Lane> lanes;
  for (std::size_t k = 0; k < builds.size(); ++k)
    for (Method m : build_opts[k]->methods) {
      Lane lane;
      lane.method = m;
      lane.built = builds[k];
      lane.opt = build_opts[k];
      lane.be = pool.get(name, int(lanes.size()));
      lanes.push_back(std::move(lane));
    }
  return lanes;
}

} // namespace

int traces_per_sample(std::size_t rays, std::size_t sample_rays) {
  return rays == 0 || sample_rays <= rays ? 1 : int((sample_rays + rays - 1) / rays);
}

BuiltMethods build_methods(const Scene& scene, const BenchOptions& opt) {
  BuiltMethods built;
  for (Method m : opt.methods) {
    opt.say(std::string("building ") + method_name(m) + " (" + builder_name(opt.accel.builder.kind) + ", " +
                 node_format_name(opt.accel.nodes) + ")");
    if (m == Method::Auto && opt.auto_by == AutoBy::Pilot && opt.accel.auto_select == AutoSelect::WholeStructure) {
      built.auto_candidates = build_auto_candidates(scene, opt.accel);
      PackedScene model = built.auto_candidates.built[model_choice(built.auto_candidates)];
      mark_as_auto(model, built.auto_candidates);
      built.scenes[m] = std::move(model);
    } else {
      built.scenes[m] = build_accel(scene, m, opt.accel);
    }
  }
  return built;
}

std::vector<RayBatch> make_ray_batches(const Scene& scene, const BuiltMethods& built,
                                       const BenchOptions& opt, BackendPool& pool) {
  std::vector<kernel::Ray> primary = make_camera_rays(scene.camera, opt.width, opt.height);
  std::vector<kernel::Hit> hits;
  std::vector<RayBatch> batches;
  for (RaySet set : opt.ray_sets) {
    if (set == RaySet::Primary) {
      batches.push_back({set, primary});
      continue;
    }
    if (hits.empty()) hits = primary_hits(built, primary, opt, pool);
    batches.push_back({set, make_secondary_rays(set, scene, primary, hits)});
  }
  return batches;
}

const BuiltMethods& BenchRun::built_for(const BenchRow& row) const {
  for (std::size_t k = 0; k < built.size(); ++k)
    if (options[k].accel.builder.kind == row.builder && options[k].accel.nodes == row.nodes &&
        options[k].accel.curve_isect == row.curve_isect)
      return built[k];
  throw Error(fmt::format("bench: no structure built with builder {}, node format {} and curve intersector {}",
                          builder_name(row.builder), node_format_name(row.nodes), curve_isect_name(row.curve_isect)));
}

BenchRun run_bench_kept(const Scene& scene, const BenchOptions& opt, BackendPool& pool) {
  if (opt.builders.empty()) throw Error("bench: no builder to run");
  if (opt.node_formats.empty()) throw Error("bench: no node format to run");
  if (opt.curve_isects.empty()) throw Error("bench: no curve intersector to run");
  // Every builder's and node format's scenes first, then per backend all of them.
  BenchRun run;
  std::vector<BuiltMethods>& built = run.built;
  std::vector<BenchOptions>& per_build = run.options;
  built.reserve(opt.builders.size() * opt.node_formats.size() * opt.curve_isects.size());
  per_build.reserve(built.capacity());
  for (Builder b : opt.builders)
    for (NodeFormat f : opt.node_formats)
      for (CurveIsect ci : opt.curve_isects) {
        BenchOptions one = opt;
        one.accel.builder.kind = b;
        one.accel.nodes = f;
        one.accel.curve_isect = ci;
        built.push_back(build_methods(scene, one));
        per_build.push_back(std::move(one));
      }
  run.batches = make_ray_batches(scene, built.front(), per_build.front(), pool);
  const std::vector<RayBatch>& batches = run.batches;
  std::vector<const BuiltMethods*> builds;
  std::vector<const BenchOptions*> build_opts;
  for (std::size_t k = 0; k < built.size(); ++k) {
    builds.push_back(&built[k]);
    build_opts.push_back(&per_build[k]);
  }
  // Per backend, every builder's and node format's methods take turns in the same
  // rounds: the rows compared for one backend are measured together, which matters on
  // a shared machine. The rays come from the first build's scenes.
  std::vector<BenchRow>& rows = run.rows;
  for (const std::string& backend : opt.backends) {
    std::vector<Lane> lanes = open_lanes(backend, builds, build_opts, pool);
    for (BenchRow& r : measure_backend(backend, lanes, scene.primitive_count(), batches, opt, pool))
      rows.push_back(std::move(r));
  }
  auto index = [](const auto& list, const auto& x) {
    return std::size_t(std::find(list.begin(), list.end(), x) - list.begin());
  };
  std::stable_sort(rows.begin(), rows.end(), [&](const BenchRow& a, const BenchRow& b) {
    auto key = [&](const BenchRow& r) {
      return std::tuple(index(opt.backends, r.backend), index(opt.methods, r.method), index(opt.builders, r.builder),
                        index(opt.node_formats, r.nodes), index(opt.curve_isects, r.curve_isect),
                        index(opt.ray_sets, r.ray_set));
    };
    return key(a) < key(b);
  });
  return run;
}

std::vector<BenchRow> run_bench(const Scene& scene, const BenchOptions& opt, BackendPool& pool) {
  return run_bench_kept(scene, opt, pool).rows;
}

std::vector<BenchRow> run_bench(const Scene& scene, const BenchOptions& opt) {
  BackendPool pool;
  return run_bench(scene, opt, pool);
}

} // namespace masq
