// masq_addressed_cost: what reading the scene arrays by device address costs on the
// Vulkan backends, against binding them, on one scene that fits either way. Both modes
// run in one process, interleaved round by round (MASQ_VK_MAX_BINDING_BYTES set or unset
// before each set_scene, host/limit_knob.h), and each mode keeps its fastest trace, so
// load from other processes on a shared machine biases neither.
//   masq_addressed_cost [strands=20000] [width=256] [rounds=5] [backend=vulkan]
#include "bvh/twolevel/build_accel.h"
#include "host/backend.h"
#include "scenes/camera.h"
#include "scenes/strand_generators.h"
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace masq;

int main(int argc, char** argv) {
  try {
    HairParams hp;
    hp.strands = argc > 1 ? std::atoi(argv[1]) : 20000;
    hp.type = PrimType::Capsule;
    const int width = argc > 2 ? std::atoi(argv[2]) : 256;
    const int rounds = argc > 3 ? std::atoi(argv[3]) : 5;
    const std::string backend = argc > 4 ? argv[4] : "vulkan";
    Scene scene = make_hair_scene(hp);
    std::vector<kernel::Ray> rays = make_camera_rays(scene.camera, width, width);
    std::vector<kernel::Hit> hits(rays.size()), first(rays.size());
    std::unique_ptr<Backend> be = make_backend(backend);
    std::printf("%s, hair %d strands (capsules), %zu rays, %d interleaved rounds of 3 traces; fastest per mode\n",
                be->device_name().c_str(), hp.strands, rays.size(), rounds);
    std::printf("%-8s %-7s %12s %12s %9s\n", "backend", "method", "bound Mray/s", "addr Mray/s", "addr/bound");
    for (Method m : {Method::Ref, Method::Masq, Method::Cluster}) {
      PackedScene packed = build_accel(scene, m);
      double best[2] = {1e30, 1e30};
      for (int r = 0; r < rounds; ++r)
        for (int addressed = 0; addressed < 2; ++addressed) {
          // 1 MiB: below every array of this scene but the small ones, above a chunk of rays.
          if (addressed) setenv("MASQ_VK_MAX_BINDING_BYTES", "1048576", 1);
          else unsetenv("MASQ_VK_MAX_BINDING_BYTES");
          be->set_scene(packed);
          be->trace(rays, hits, {}); // warm-up (and the JIT on first use)
          for (int k = 0; k < 3; ++k) {
            be->trace(rays, hits, {});
            best[addressed] = std::min(best[addressed], be->timing().trace_seconds);
          }
          if (r == 0 && addressed == 0) first = hits;
          for (std::size_t i = 0; i < hits.size(); ++i)
            if (hits[i].prim != first[i].prim) {
              std::fprintf(stderr, "ray %zu: addressed and bound modes disagree\n", i);
              return 1;
            }
        }
      unsetenv("MASQ_VK_MAX_BINDING_BYTES");
      double n = double(rays.size()) * 1e-6;
      std::printf("%-8s %-7s %12.3f %12.3f %9.3f\n", backend.c_str(), method_name(m), n / best[0], n / best[1],
                  best[0] / best[1]);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "masq_addressed_cost: %s\n", e.what());
    return 1;
  }
}
