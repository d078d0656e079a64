// The Vulkan backends' timing of their compile, upload and trace steps (what BenchRow's
// seconds report), on the monotonic clock.
#pragma once
#include <chrono>

namespace masq::vk {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

} // namespace masq::vk
