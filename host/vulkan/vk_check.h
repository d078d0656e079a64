// Checked Vulkan calls: a failing call throws masq::Error naming the call, the file,
// the line and the VkResult by name.
#pragma once
#include "masq/error.h"
#include <vulkan/vulkan.h>
#include <string>

namespace masq::vk {

const char* result_name(VkResult r);

[[noreturn]] void throw_vk_error(const char* call, VkResult r, const char* file, int line);

} // namespace masq::vk

#define MASQ_VK_CHECK(call)                                                        \
  do {                                                                             \
    VkResult masq_vk_r_ = (call);                                                  \
    if (masq_vk_r_ != VK_SUCCESS) ::masq::vk::throw_vk_error(#call, masq_vk_r_, __FILE__, __LINE__); \
  } while (0)
