#include "bench/bench_runner.h"
#include "bvh/build_accel.h"
#include "scenes/camera.h"
#include "scenes/error.h"
#include <algorithm>
#include <tuple>
#include <fmt/format.h>

namespace masq {

namespace {

void say(const BenchOptions& opt, const std::string& line) {
  if (opt.progress) opt.progress(line);
}

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

// The scene is already uploaded: counters first (stats variant), then warm-up and timed
// traces of the counter-free variant.
void measure_one(BenchRow& row, Backend& be, std::span<const kernel::Ray> rays, const BenchOptions& opt) {
  const std::string tag = fmt::format("{} {} {}", row.backend, method_name(row.method), ray_set_name(row.ray_set));
  std::vector<kernel::Hit> hits(rays.size());
  std::vector<kernel::RayStats> stats(rays.size());
  say(opt, tag + ": counters");
  be.trace(rays, hits, stats, row.query);
  fill_counters(row, stats, hits);
  if (opt.keep_per_ray) {
    row.hits = hits;
    row.stats = std::move(stats);
  }
  std::vector<double> times;
  for (int i = 0; i < opt.warmup + opt.repetitions; ++i) {
    be.trace(rays, hits, {}, row.query);
    if (i == 0) row.compile_s = be.timing().compile_seconds;
    if (i >= opt.warmup) times.push_back(be.timing().trace_seconds);
    say(opt, fmt::format("{}: trace {}/{}", tag, i + 1, opt.warmup + opt.repetitions));
  }
  std::sort(times.begin(), times.end());
  row.median_s = times[times.size() / 2];
  row.min_s = times.front();
  row.max_s = times.back();
  row.device_bytes = be.device_bytes();
}

std::vector<kernel::Hit> primary_hits(const std::map<Method, PackedScene>& built, std::span<const kernel::Ray> rays,
                                      const BenchOptions& opt, BackendPool& pool) {
  const PackedScene& ps = built.count(Method::Ref) ? built.at(Method::Ref) : built.begin()->second;
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

} // namespace

std::map<Method, PackedScene> build_methods(const Scene& scene, const BenchOptions& opt) {
  std::map<Method, PackedScene> built;
  for (Method m : opt.methods) {
    say(opt, std::string("building ") + method_name(m) + " (" + builder_name(opt.accel.builder.kind) + ", " +
                 node_format_name(opt.accel.nodes) + ")");
    built[m] = build_accel(scene, m, opt.accel);
  }
  return built;
}

std::vector<RayBatch> make_ray_batches(const Scene& scene, const std::map<Method, PackedScene>& built,
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

std::vector<BenchRow> measure(const std::map<Method, PackedScene>& built, std::size_t primitives,
                              const std::vector<RayBatch>& batches, const BenchOptions& opt, BackendPool& pool) {
  std::vector<BenchRow> rows;
  for (const std::string& name : opt.backends) {
    Backend* be = pool.get(name);
    for (Method m : opt.methods) {
      const PackedScene& ps = built.at(m);
      std::string failed; // upload failure: every set of this backend and method
      bool uploaded = false;
      for (const RayBatch& batch : batches) {
        BenchRow row;
        row.backend = name;
        row.method = m;
        row.builder = ps.builder;
        row.nodes = ps.features.nodes;
        row.ray_set = batch.set;
        row.query = batch.set == RaySet::Shadow && opt.shadow_any_hit ? Query::Any : Query::Closest;
        row.rays = double(batch.rays.size());
        row.primitives = primitives;
        row.build = ps.stats;
        row.build_s = ps.stats.build_seconds;
        row.accel_bytes = ps.acceleration_bytes();
        row.prim_bytes = ps.primitive_bytes();
        if (!be) {
          row.unavailable = pool.why(name);
        } else if (batch.rays.empty()) {
          row.unavailable = "no rays in this set (no primary hits)";
        } else {
          try {
            if (!uploaded && failed.empty()) {
              say(opt, fmt::format("{} {}: upload", name, method_name(m)));
              be->set_scene(ps);
              uploaded = true;
            }
            if (!failed.empty()) throw Error(failed);
            row.device = be->device_name();
            row.scene_s = be->timing().scene_seconds;
            measure_one(row, *be, batch.rays, opt);
          } catch (const std::exception& e) {
            row.unavailable = e.what();
            if (!uploaded) failed = e.what();
          }
        }
        rows.push_back(std::move(row));
      }
    }
  }
  return rows;
}

std::vector<BenchRow> run_bench(const Scene& scene, const BenchOptions& opt, BackendPool& pool) {
  if (opt.builders.empty()) throw Error("bench: no builder to run");
  if (opt.node_formats.empty()) throw Error("bench: no node format to run");
  // Every builder's and node format's scenes first, then per backend each of them in
  // turn: the rows compared for one backend are measured close together in time, which
  // matters on a shared machine. The rays come from the first one's scenes.
  std::vector<std::map<Method, PackedScene>> built;
  std::vector<BenchOptions> per_build;
  for (Builder b : opt.builders)
    for (NodeFormat f : opt.node_formats) {
      BenchOptions one = opt;
      one.accel.builder.kind = b;
      one.accel.nodes = f;
      built.push_back(build_methods(scene, one));
      per_build.push_back(std::move(one));
    }
  std::vector<RayBatch> batches = make_ray_batches(scene, built.front(), per_build.front(), pool);
  std::vector<BenchRow> rows;
  for (const std::string& backend : opt.backends)
    for (Method m : opt.methods)
      for (std::size_t k = 0; k < built.size(); ++k) {
        BenchOptions one = per_build[k];
        one.backends = {backend};
        one.methods = {m};
        for (BenchRow& r : measure(built[k], scene.primitive_count(), batches, one, pool)) rows.push_back(std::move(r));
      }
  auto index = [](const auto& list, const auto& x) {
    return std::size_t(std::find(list.begin(), list.end(), x) - list.begin());
  };
  std::stable_sort(rows.begin(), rows.end(), [&](const BenchRow& a, const BenchRow& b) {
    auto key = [&](const BenchRow& r) {
      return std::tuple(index(opt.backends, r.backend), index(opt.methods, r.method), index(opt.builders, r.builder),
                        index(opt.node_formats, r.nodes), index(opt.ray_sets, r.ray_set));
    };
    return key(a) < key(b);
  });
  return rows;
}

std::vector<BenchRow> run_bench(const Scene& scene, const BenchOptions& opt) {
  BackendPool pool;
  return run_bench(scene, opt, pool);
}

} // namespace masq
