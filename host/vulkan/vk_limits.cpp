#include "host/vulkan/vk_limits.h"
#include "host/backend.h"
#include <fmt/format.h>
#include <algorithm>
#include <cerrno>
#include <cstdlib>

namespace masq::vk {

std::uint64_t lowered_limit(std::uint64_t device, const char* env, std::uint64_t test_override) {
  std::uint64_t limit = device;
  if (test_override != 0) limit = std::min(limit, test_override);
  const char* v = std::getenv(env);
  if (v == nullptr || *v == '\0') return limit;
  char* end = nullptr;
  errno = 0;
  unsigned long long n = std::strtoull(v, &end, 10);
  if (*end != '\0' || errno != 0 || n == 0 || *v == '-')
    throw Error(fmt::format("vulkan: {}='{}' is not a positive integer", env, v));
  return std::min<std::uint64_t>(limit, n);
}

} // namespace masq::vk
