// The C++ side of the Python overhead benchmark (python/bench/trace_overhead.py): the same
// scene, accel, rays and timed traces through the public C++ API, so the script can
// compare a trace from Python with the same trace from C++.
// Usage: masq_api_trace FILE BACKEND METHOD WIDTH HEIGHT REPS [reuse|fresh]
// reuse (default): every trace writes one hit vector kept from trace to trace; fresh:
// each trace returns a new vector (Context::trace(accel, rays)), as a Python trace
// without out= returns a new array.
// Prints one line per timed trace: "trace_seconds <wall seconds>".
#include "masq/masq.h"
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  const std::string output = argc == 8 ? argv[7] : "reuse";
  if ((argc != 7 && argc != 8) || (output != "reuse" && output != "fresh")) {
    std::fprintf(stderr, "usage: %s FILE BACKEND METHOD WIDTH HEIGHT REPS [reuse|fresh]\n", argv[0]);
    return 2;
  }
  try {
    using namespace masq::api;
    Scene scene = Scene::load(argv[1]);
    AccelOptions options;
    options.method = masq::api::method_table.parse(argv[3]);
    Accel accel = Accel::build(scene, options);
    Context ctx(argv[2]);
    std::vector<Ray> rays = scene.camera_rays(std::atoi(argv[4]), std::atoi(argv[5]));
    std::vector<Hit> hits(rays.size());
    ctx.trace(accel, rays, hits); // upload and compile, untimed
    for (int rep = 0; rep < std::atoi(argv[6]); ++rep) {
      auto t0 = std::chrono::steady_clock::now();
      if (output == "reuse") ctx.trace(accel, rays, hits);
      else hits = ctx.trace(accel, rays); // the old vector is freed after the trace, as Python's would be
      std::chrono::duration<double> dt = std::chrono::steady_clock::now() - t0;
      std::printf("trace_seconds %.6f\n", dt.count());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "masq_api_trace: %s\n", e.what());
    return 1;
  }
  return 0;
}
