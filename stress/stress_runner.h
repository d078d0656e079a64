// Runs the stress cells through every backend x mode x method and compares each ray
// with the long-double oracle (oracle/, independent of the kernels).
#pragma once
#include "bvh/packed_scene.h"
#include "stress/stress_cases.h"
#include <array>
#include <functional>
#include <string>
#include <vector>

namespace masq::stress {

struct Metrics {
  std::size_t rays = 0;
  std::size_t ambiguous = 0;  // oracle clearance below the cell's fp32 ambiguity band
  std::size_t compared = 0;   // rays - ambiguous
  std::size_t disagree = 0;   // hit/miss differs, or a different surface (|dt| > r)
  std::size_t self_hits = 0;  // surface-start rays that re-hit their origin (|t d| < r/100)
  // masq: ref hits on the same backend and mode, masq does not; with a node format other
  // than w4, ref too: the w4 ref structure hits, this one does not
  std::size_t false_culls = 0;
  // |dt| * |d| / r and normal error over agreeing, well-conditioned hits (origin
  // perturbations within the band move the hit by less than r / 1000).
  double max_dt = 0, sum_dt = 0;
  std::size_t dt_count = 0;
  double max_normal_deg = 0, sum_normal_deg = 0;
  double trace_seconds = 0;
  std::string example; // the first disagreement, for reproduction
  std::array<std::size_t, kRayKinds> rays_by_kind{}, disagree_by_kind{};
  double rate() const { return compared ? double(disagree) / double(compared) : 0.0; }
  double mean_dt() const { return dt_count ? sum_dt / double(dt_count) : 0.0; }
  double mean_normal_deg() const { return dt_count ? sum_normal_deg / double(dt_count) : 0.0; }
};

struct CellResult {
  CellSpec spec;
  std::string backend;
  Mode mode = Mode::Robust;
  Method method = Method::Masq;
  Metrics m;
};

struct StressOptions {
  SweepOptions sweep;
  std::vector<std::string> backends;            // empty: all
  std::vector<Mode> modes = {Mode::Robust, Mode::Fast};
  // The node format of both methods' structures. o4 rotates every BLAS node (gain +inf:
  // the format's numerical worst case), and the w4 ref is traced as well, as the
  // baseline of ref's false culls.
  NodeFormat nodes = NodeFormat::W4;
  std::function<void(const std::string&)> progress; // may be empty
};

struct StressReport {
  std::vector<CellResult> results;
  std::vector<std::pair<std::string, std::string>> unavailable; // backend, why
  std::vector<std::string> devices;                            // "backend: device"
  double oracle_seconds = 0;
  double total_seconds = 0;
};

StressReport run_stress(const StressOptions& opt);

} // namespace masq::stress
