// The devices of every GPU API for `masq info`, and the selector check before a run:
// which backend uses which API comes from the backend table's device_api column.
#include "host/device_list.h"
#include "host/backend.h"
#include "host/opencl/cl_devices.h"
#include "host/vulkan/vk_devices.h"

namespace masq {

namespace {

// The driver APIs: vulkan, rayquery and rtpipeline choose among the Vulkan devices, opencl among
// the OpenCL ones.
struct DriverApi {
  const char* label;
  std::vector<DeviceInfo> (*infos)();
  bool opencl;
  bool serves(DeviceApi a) const { return (a == DeviceApi::OpenCl) == opencl; }
};
const DriverApi kDriverApis[] = {{"Vulkan", vk::vulkan_device_infos, false}, {"OpenCL", opencl::cl_device_infos, true}};

DeviceChoice pick(DeviceApi api, const std::vector<DeviceInfo>& devices) {
  switch (api) {
    case DeviceApi::Vulkan: return vk::choose_vulkan_device(devices, DeviceNeed::Compute);
    case DeviceApi::RayQuery: return vk::choose_vulkan_device(devices, DeviceNeed::RayQuery);
    case DeviceApi::RtPipeline: return vk::choose_vulkan_device(devices, DeviceNeed::RayPipeline);
    case DeviceApi::OpenCl: return opencl::choose_opencl_device(devices);
  }
  return {};
}

} // namespace

std::vector<ApiDevices> list_devices() {
  std::vector<ApiDevices> out;
  for (const DriverApi& d : kDriverApis) {
    ApiDevices a;
    a.api = d.label;
    for (const DeviceApiRow& row : device_api_table.rows())
      if (d.serves(row.value)) a.selectors += std::string(a.selectors.empty() ? "" : ", ") + knob_name(row.knob);
    try {
      a.devices = d.infos();
    } catch (const BackendUnavailable& e) {
      a.unavailable = e.what();
    }
    for (const BackendRow& r : backend_table.rows()) {
      if (!r.device_api || !d.serves(device_api_table.parse(r.device_api)) || !a.unavailable.empty()) continue;
      DeviceChoice c;
      try {
        c = pick(device_api_table.parse(r.device_api), a.devices);
      } catch (const Error& e) {
        c = {-1, e.what()}; // the listing is what a user reads to fix the selector
      }
      a.picks.emplace_back(r.name, c);
    }
    out.push_back(std::move(a));
  }
  return out;
}

void check_device_selectors(std::span<const std::string> backends) {
  for (const DriverApi& d : kDriverApis) {
    std::vector<DeviceInfo> devices;
    bool listed = false;
    for (const std::string& b : backends) {
      const BackendRow* r = backend_table.find(b);
      if (!r || !r->device_api) continue;
      const DeviceApi api = device_api_table.parse(r->device_api);
      if (!d.serves(api)) continue;
      if (!listed) {
        try {
          devices = d.infos();
        } catch (const BackendUnavailable&) {
          break; // no driver: opening the backend says so
        }
        listed = true;
      }
      pick(api, devices); // throws for a selector naming none
    }
  }
}

} // namespace masq
