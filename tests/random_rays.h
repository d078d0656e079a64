// Random test rays: from a sphere of radius 5 towards random points of the
// [-1.5, 1.5]^3 box, with non-unit directions (length 0.3..2.3), so that every kernel
// carries |d| through its intersectors. Deterministic from the generator.
#pragma once
#include "scenes/camera.h"
#include <cmath>
#include <random>
#include <vector>

namespace masq::test {

inline std::vector<kernel::Ray> random_rays(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<kernel::Ray> rays;
  for (int i = 0; i < n; ++i) {
    glm::dvec3 from = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng))) * 5.0;
    glm::dvec3 to = glm::dvec3(u(rng), u(rng), u(rng)) * 1.5;
    double scale = 0.3 + 2.0 * std::abs(u(rng));
    rays.push_back(make_ray(from, (to - from) * (scale / glm::length(to - from))));
  }
  return rays;
}

inline std::vector<kernel::Ray> random_rays(std::uint64_t seed, int n) {
  std::mt19937_64 rng(seed);
  return random_rays(rng, n);
}

} // namespace masq::test
