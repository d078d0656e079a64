// Every device of each GPU API and the one each backend takes (`masq info`), and the
// check a driver makes before a run that the device selectors in force name a device
// (so `MASQ_VK_DEVICE=no-such-gpu masq bench` is an error, not a skipped backend).
// Implemented in host/registry/device_list.cpp, beside the backend table it reads.
#pragma once
#include "host/device_choice.h"
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace masq {

struct ApiDevices {
  std::string api;                 // "Vulkan", "OpenCL"
  std::string selectors;           // its selectors' variables: "MASQ_VK_DEVICE, MASQ_RQ_DEVICE"
  std::vector<DeviceInfo> devices; // in enumeration order
  std::string unavailable;         // no driver: one line saying so (devices empty)
  // Each backend on this API and its device: a position in `devices`, or -1 and why
  // (a selector naming no device included).
  std::vector<std::pair<std::string, DeviceChoice>> picks;
};
std::vector<ApiDevices> list_devices();

// Throws masq::Error (one line naming the selector and the devices there are) when a
// selector in force for the device API of one of `backends` names no device. An API
// without a driver passes: opening its backend reports that.
void check_device_selectors(std::span<const std::string> backends);

} // namespace masq
