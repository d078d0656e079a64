#include "bench/auto_pilot.h"
#include "masq/error.h"
#include <algorithm>
#include <chrono>
#include <string>

namespace masq {

namespace {
// Rays per run of the pilot sample: a few rows of a small image, long enough that a
// work group sees coherent neighbours.
constexpr std::size_t kPilotRun = 256;
} // namespace

std::vector<kernel::Ray> pilot_sample(std::span<const kernel::Ray> rays, std::size_t max_rays) {
  if (rays.size() <= max_rays) return {rays.begin(), rays.end()};
  std::vector<kernel::Ray> out;
  out.reserve(max_rays);
  std::size_t run = std::min(kPilotRun, max_rays);
  std::size_t runs = (max_rays + run - 1) / run;
  for (std::size_t i = 0; i < runs && out.size() < max_rays; ++i) {
    // Run i starts at i/runs of the way through, so the runs cover the whole set.
    std::size_t first = i * (rays.size() - run) / std::max<std::size_t>(1, runs - 1);
    if (runs == 1) first = 0;
    std::size_t n = std::min(run, max_rays - out.size());
    out.insert(out.end(), rays.begin() + std::ptrdiff_t(first), rays.begin() + std::ptrdiff_t(first + n));
  }
  return out;
}

PilotResult run_pilot(std::span<Backend* const> slots, const AutoCandidates& candidates,
                      std::span<const kernel::Ray> rays, Query query, const PilotOptions& opt) {
  const std::size_t n = candidates.built.size();
  if (n == 0) throw Error("auto pilot: no candidate structures");
  if (slots.size() != 1 && slots.size() < n)
    throw Error("auto pilot: " + std::to_string(slots.size()) + " backend slots for " + std::to_string(n) +
                " candidates (give one, or one per candidate)");
  if (std::any_of(slots.begin(), slots.end(), [](Backend* b) { return b == nullptr; }))
    throw Error("auto pilot: a backend slot is missing");
  if (opt.rounds < 1) throw Error("auto pilot: rounds " + std::to_string(opt.rounds) + " must be at least 1");
  if (opt.max_rays < 1) throw Error("auto pilot: max_rays must be at least 1");
  if (!(opt.ref_margin >= 0 && opt.ref_margin < 1))
    throw Error("auto pilot: ref_margin " + std::to_string(opt.ref_margin) + " outside [0, 1)");
  auto t0 = std::chrono::steady_clock::now();
  PilotResult res;
  // A sample too small to fill the device would time launch overhead, not the candidates.
  std::vector<kernel::Ray> sample = pilot_sample(rays, std::max(opt.max_rays, slots[0]->fill_rays()));
  res.rays = sample.size();
  res.seconds.assign(n, 0.0);
  std::vector<kernel::Hit> hits(sample.size());
  // trace i once, warm (the variant's compile and first touches) or timed.
  auto trace = [&](Backend& be, std::size_t i, bool timed) {
    be.trace(sample, hits, {}, query);
    if (!timed) return;
    double s = be.timing().trace_seconds;
    res.seconds[i] = res.seconds[i] > 0 ? std::min(res.seconds[i], s) : s;
  };
  if (slots.size() == 1) {
    for (std::size_t i = 0; i < n; ++i) {
      slots[0]->set_scene(candidates.built[i]);
      for (int r = 0; r <= opt.rounds; ++r) trace(*slots[0], i, r > 0);
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      if (!opt.slots_hold_candidates) slots[i]->set_scene(candidates.built[i]);
      trace(*slots[i], i, false);
    }
    for (int r = 0; r < opt.rounds; ++r)
      for (std::size_t i = 0; i < n; ++i) trace(*slots[i], i, true);
  }
  std::size_t fastest = std::size_t(std::min_element(res.seconds.begin(), res.seconds.end()) - res.seconds.begin());
  res.kept = fastest;
  for (std::size_t i = 0; i < n; ++i)
    if (candidates.built[i].method == Method::Ref && res.seconds[fastest] > res.seconds[i] * (1.0 - opt.ref_margin))
      res.kept = i;
  res.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

PilotResult run_pilot(Backend& be, const AutoCandidates& candidates, std::span<const kernel::Ray> rays, Query query,
                      const PilotOptions& opt) {
  Backend* one[] = {&be};
  return run_pilot(one, candidates, rays, query, opt);
}

} // namespace masq
