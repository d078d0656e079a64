// The OpenCL devices as masq sees them: every device of every platform described as a
// DeviceInfo (host/device_choice.h), the opencl backend's choice among them (best-ranked,
// or the one MASQ_CL_DEVICE / --device names) and the listing `masq info` prints.
#pragma once
#include "host/device_choice.h"
#include "host/opencl/cl_runtime.h"
#include <vector>

namespace masq::opencl {

struct ClDevice {
  cl::Platform platform;
  cl::Device device;
  DeviceInfo info; // info.index: position over all platforms, in ICD order
};

// Every device of every platform. Throws BackendUnavailable "opencl: ..." when there is no
// platform, or no device on any.
std::vector<ClDevice> cl_devices();

// The device the opencl backend opens (device_selector(DeviceApi::OpenCl)). Throws
// masq::Error for a selector that names no device, BackendUnavailable when none serves.
const ClDevice& choose_cl_device(const std::vector<ClDevice>& devices);

// The opencl backend's choice among `devices` (device_selector(DeviceApi::OpenCl)).
// Throws masq::Error for a selector naming none.
DeviceChoice choose_opencl_device(const std::vector<DeviceInfo>& devices);

// For `masq info`: every device's description (throws as cl_devices).
std::vector<DeviceInfo> cl_device_infos();

} // namespace masq::opencl
