// Measures one scene through every backend x method with the same rays: device time
// after warm-up, median and min-max over repetitions, counters per ray, memory.
#pragma once
#include "bvh/build_accel.h"
#include "bvh/packed_scene.h"
#include "host/backend.h"
#include "scenes/scene.h"
#include <functional>
#include <string>
#include <vector>

namespace masq {

struct BenchOptions {
  std::vector<std::string> backends = backend_names();
  std::vector<Method> methods = {Method::Ref, Method::Masq};
  int width = 512;
  int height = 512;
  int warmup = 1;
  int repetitions = 5;
  AccelOptions accel; // mode, curve OBB, phantom iterations
  std::function<void(const std::string&)> progress; // one line per step, may be empty
};

struct BenchRow {
  std::string backend;
  std::string device;
  Method method = Method::Ref;
  std::string unavailable; // non-empty: the backend could not run (why)
  double rays = 0;
  double median_s = 0, min_s = 0, max_s = 0;
  double build_s = 0, scene_s = 0, compile_s = 0;
  // Per ray, from the stats variant (rayquery: node tests and transforms are not observable: -1).
  double tlas_nodes = 0, blas_nodes = 0, transforms = 0, isect_calls = 0;
  double hit_fraction = 0;
  std::size_t accel_bytes = 0, prim_bytes = 0, device_bytes = 0;
  std::size_t primitives = 0;
  BuildStats build;
  double mrays_per_s() const { return median_s > 0 ? rays / median_s * 1e-6 : 0; }
};

std::vector<BenchRow> run_bench(const Scene& scene, const BenchOptions& opt);

} // namespace masq
