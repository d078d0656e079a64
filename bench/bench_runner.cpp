#include "bench/bench_runner.h"
#include "bvh/build_accel.h"
#include "scenes/camera.h"
#include <algorithm>
#include <map>

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
  double n = double(stats.size());
  row.tlas_nodes = t / n;
  row.blas_nodes = b / n;
  row.transforms = x / n;
  row.isect_calls = c / n;
  row.hit_fraction = h / n;
}

} // namespace

std::vector<BenchRow> run_bench(const Scene& scene, const BenchOptions& opt) {
  std::vector<kernel::Ray> rays = make_camera_rays(scene.camera, opt.width, opt.height);
  std::map<Method, PackedScene> built;
  for (Method m : opt.methods) {
    say(opt, std::string("building ") + method_name(m));
    built[m] = build_accel(scene, m, opt.accel);
  }
  std::vector<BenchRow> rows;
  for (const std::string& name : opt.backends) {
    std::unique_ptr<Backend> be;
    std::string why;
    try {
      be = make_backend(name);
    } catch (const std::exception& e) {
      why = e.what();
    }
    for (Method m : opt.methods) {
      BenchRow row;
      row.backend = name;
      row.method = m;
      row.rays = double(rays.size());
      row.primitives = scene.primitive_count();
      const PackedScene& ps = built[m];
      row.build = ps.stats;
      row.build_s = ps.stats.build_seconds;
      row.accel_bytes = ps.acceleration_bytes();
      row.prim_bytes = ps.primitive_bytes();
      if (!be) {
        row.unavailable = why;
        rows.push_back(row);
        continue;
      }
      try {
        say(opt, name + " " + method_name(m) + ": upload");
        row.device = be->device_name();
        be->set_scene(ps);
        row.scene_s = be->timing().scene_seconds;
        std::vector<kernel::Hit> hits(rays.size());
        std::vector<kernel::RayStats> stats(rays.size());
        say(opt, name + " " + method_name(m) + ": counters");
        be->trace(rays, hits, stats);
        fill_counters(row, stats, hits);
        std::vector<double> times;
        for (int i = 0; i < opt.warmup + opt.repetitions; ++i) {
          be->trace(rays, hits, {});
          if (i == 0) row.compile_s = be->timing().compile_seconds;
          if (i >= opt.warmup) times.push_back(be->timing().trace_seconds);
          say(opt, name + " " + method_name(m) + ": trace " + std::to_string(i + 1) + "/" +
                       std::to_string(opt.warmup + opt.repetitions));
        }
        std::sort(times.begin(), times.end());
        row.median_s = times[times.size() / 2];
        row.min_s = times.front();
        row.max_s = times.back();
        row.device_bytes = be->device_bytes();
      } catch (const std::exception& e) {
        row.unavailable = e.what();
      }
      rows.push_back(row);
    }
  }
  return rows;
}

} // namespace masq
