// Traces a 64 x 64 grid of rays at a row of 8 capsules and checks the hit count.
// Usage: consumer [backend]   (default "best")
#include <masq/masq.h>
#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
  using namespace masq::api;
  try {
    Scene scene;
    std::vector<Capsule> capsules;
    for (int i = 0; i < 8; ++i) {
      float x = -0.875f + 0.25f * i; // vertical capsules of radius 0.03
      capsules.push_back({{x, -0.5f, 0}, {x, 0.5f, 0}, 0.03f});
    }
    scene.add_capsules(capsules);
    // Options by name, as a command line or a language binding gives them (masq/names.h).
    Accel accel = Accel::build(scene, {method_table.parse("masq"), mode_table.parse("robust")});

    std::vector<Ray> rays;
    const int n = 64;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        Ray r;
        r.org = {-1.0f + 2.0f * (i + 0.5f) / n, -1.0f + 2.0f * (j + 0.5f) / n, -5.0f};
        r.dir = {0, 0, 1};
        rays.push_back(r);
      }
    Context ctx(argc > 1 ? argv[1] : "best");
    std::vector<Hit> hits = ctx.trace(accel, rays);
    int count = 0;
    for (const Hit& h : hits) count += h.hit();
    // Ray centres sit 1/64 and 3/64 from each capsule axis: the 2 columns at 1/64 hit
    // over the 32 rows with |y| < 0.5 plus one row into each round cap (distance
    // sqrt(2)/64 < 0.03 from the end point), so 8 * 2 * 34 = 544 hits.
    const int expected = 544;
    std::printf("masq %s, method %s, on %s (%s): %d hits of %zu rays (expected %d)\n", version(),
                method_table.name(accel.options().method), ctx.backend().c_str(), ctx.device().c_str(), count,
                rays.size(), expected);
    return count == expected ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
