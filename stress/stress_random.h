// The stress suite's random draws: shared by the cell builder (stress_cases.cpp) and the
// per-type rows (stress_prim_rows.cpp), so every cell draws the same numbers in the same
// order wherever the drawing code lives.
#pragma once
#include <glm/glm.hpp>
#include <random>

namespace masq::stress {

using Rng = std::mt19937_64;

inline glm::dvec3 random_unit(Rng& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    glm::dvec3 v(g(rng), g(rng), g(rng));
    double l = glm::length(v);
    if (l > 1e-6) return v / l;
  }
}

inline glm::dvec3 perpendicular_to(const glm::dvec3& w, Rng& rng) {
  for (;;) {
    glm::dvec3 v = random_unit(rng);
    glm::dvec3 p = v - glm::dot(v, w) * w;
    double l = glm::length(p);
    if (l > 1e-3) return p / l;
  }
}

inline double uniform(Rng& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }

} // namespace masq::stress
