// Independent ground truth: brute force over every primitive of every instance in long
// double. Shares no code with kernels/: each primitive type by the methods in
// oracle_prims.h (textbook quadratics for spheres and capsules, the tangent cone for
// round cones, the swept-sphere union for curves, Moller-Trumbore for triangles, all
// with the common self-intersection window), transforms inverted in long double from
// the scene's own double matrices.
#pragma once
#include "kernels/layout.h"
#include "scenes/scene.h"
#include <glm/glm.hpp>
#include <limits>
#include <vector>

namespace masq::oracle {

struct OracleHit {
  long double t = 0;           // valid when prim >= 0
  int prim = -1;
  int geom = -1;
  int inst = -1;
  glm::dvec3 normal{0.0};      // world space, unit
  long double second_t = 0;    // nearest hit of any OTHER primitive (inf if none)
  // Smallest relative clearance of any primitive the ray passes near, before the nearest
  // hit: |distance - r| / r for round primitives, |smallest barycentric| for triangles
  // (PrimResult::clearance, taken where the ray's closest approach is not beyond the hit). Small
  // values mark rays where fp32 may legitimately flip hit and miss.
  long double clearance = 0;
};

struct OracleOptions {
  // OracleHit::clearance is exact below this value; a primitive the ray passes farther
  // from is not solved at all (its clearance could only be larger), so a clearance
  // at or above it is a lower bound, or inf. Brute force solves every primitive for every
  // ray: a cutoff skips most of them (the curve's solve costs ~50 us a pair), and a
  // caller that reads clearance only as "below some small threshold" loses nothing.
  // inf (the default): every primitive solved, every clearance exact.
  long double exact_clearance_below = std::numeric_limits<long double>::infinity();
};

class Oracle {
 public:
  explicit Oracle(const Scene& scene, OracleOptions options = {});
  OracleHit trace(const kernel::Ray& ray) const;
  std::vector<OracleHit> trace_all(const std::vector<kernel::Ray>& rays) const; // on oneTBB's threads

 private:
  struct InstanceLd {
    long double w2o[3][4]; // world -> object
    int geometry;
  };
  const Scene& scene_;
  OracleOptions options_;
  std::vector<InstanceLd> inst_;
};

} // namespace masq::oracle
