// Device limits as the backends use them: the driver's value, lowered (never raised) by
// an Integer knob (include/masq/knobs.h: MASQ_VK_MAX_BINDING_BYTES, MASQ_RQ_MAX_INSTANCES,
// MASQ_MAX_RAYS_PER_DISPATCH...), so that tests and CI run the large-scene paths (Vulkan
// arrays by address, split TLAS/BLAS) and the over-the-limit errors on small scenes. The
// knobs are read at every use, so a knob set between scenes takes effect at the next
// set_scene; tests set them with ScopedEnv (tests/test_env.h).
#pragma once
#include "masq/knobs.h"
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string_view>

namespace masq {

// min(device, the knob), where an unset knob is no limit. Throws masq::Error
// "<backend>: <NAME>='<value>' is not a positive integer" (include/masq/knobs.h).
inline std::uint64_t lowered_limit(const char* backend, std::uint64_t device, Knob knob) {
  const std::optional<std::uint64_t> n = knob_integer(knob, backend);
  return n ? std::min(device, *n) : device;
}

// The value of a knob that names one of two choices: true for `on`, false for the
// other; unset or empty gives the row's default. Throws masq::Error "<owner>: <NAME>=
// '<value>' is not '<a>' or '<b>'" (owner: the backend, or "" for a knob of every backend).
inline bool choice_knob(const char* owner, Knob knob, std::string_view on) {
  return knob_choice(knob, owner) == on;
}

// Rays in one dispatch unless MASQ_MAX_RAYS_PER_DISPATCH lowers it. A display GPU's
// driver resets a kernel that runs past about 2 s (Windows TDR, Linux/macOS watchdogs).
// masq's slowest traces, the counter variants on dense hair, run near 1 Mrays/s on the
// two llvmpipe cores here and at 10-100x that on a GPU; 2^20 rays is then well under
// a tenth of a second per dispatch on a GPU (about 1 s on this machine's CPU drivers,
// which have no watchdog), while one dispatch still holds far more rays than any GPU
// runs at once (an H100: 132 SMs x 2048 threads = 270K), so chunking costs only a
// submit per 2^20 rays.
inline constexpr std::uint64_t kMaxRaysPerDispatch = std::uint64_t{1} << 20;

inline std::uint64_t max_rays_per_dispatch(const char* backend) {
  return lowered_limit(backend, kMaxRaysPerDispatch, Knob::MaxRaysPerDispatch);
}

} // namespace masq
