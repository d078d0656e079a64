// How many rays fill a device. A trace with fewer rays than the device runs at once
// leaves lanes idle, and its time per ray then measures launch and readback more than
// traversal; a GPU with 100K+ resident threads needs far more rays than a CPU driver
// with a few cores. Each backend reports the threads its device keeps in flight
// (Backend::fill_rays); the auto pilot samples at least fill_rays of them, and the
// bench says in its notes when a ray set has fewer (it keeps the same rays on every
// backend, so it does not enlarge one backend's set).
#pragma once
#include <cstddef>

namespace masq {

// Waves of resident threads one trace should hold: rays finish at different times, so
// the last wave runs partly empty; with 4 waves that tail is at most a quarter of the
// trace.
inline constexpr std::size_t kFillWaves = 4;

// Rays that fill a device keeping `resident_threads` threads in flight (0: unknown).
inline std::size_t fill_rays_for(std::size_t resident_threads) { return kFillWaves * resident_threads; }

} // namespace masq
