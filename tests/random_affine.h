// Random instance transforms for the tests: a rotation about a random axis, a
// non-uniform scale in [scale_lo, scale_lo + scale_span] per axis, and a translation in
// [-translate, translate] per axis. Deterministic from the generator.
#pragma once
#include "scenes/scene.h"
#include <cmath>
#include <random>

namespace masq::test {

inline Affine3 random_affine(std::mt19937_64& rng, double translate = 1.5, double scale_lo = 0.4,
                             double scale_span = 1.2) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  glm::dvec3 axis = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
  double angle = 3.0 * u(rng);
  // Rodrigues rotation.
  glm::dmat3 k(0, axis.z, -axis.y, -axis.z, 0, axis.x, axis.y, -axis.x, 0);
  glm::dmat3 rot = glm::dmat3(1.0) + std::sin(angle) * k + (1 - std::cos(angle)) * (k * k);
  glm::dmat3 scale(1.0);
  for (int i = 0; i < 3; ++i) scale[i][i] = scale_lo + scale_span * std::abs(u(rng));
  Affine3 a;
  a.linear = rot * scale;
  a.translation = glm::dvec3(u(rng), u(rng), u(rng)) * translate;
  return a;
}

} // namespace masq::test
