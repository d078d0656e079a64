#include "host/opencl/cl_devices.h"
#include "host/backend.h"
#include <CL/cl_ext.h>
#include <algorithm>
#include <cstdio>

namespace masq::opencl {

std::string cl_trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\0' || s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

namespace {

DeviceType device_type(const cl::Device& d) {
  const cl_device_type t = d.getInfo<CL_DEVICE_TYPE>();
  if (t & CL_DEVICE_TYPE_GPU) {
    // OpenCL has no discrete/integrated type; a GPU sharing the host's memory is integrated
    // (CL_DEVICE_HOST_UNIFIED_MEMORY: deprecated in 2.0, still answered by every driver).
    cl_bool unified = CL_FALSE;
    clGetDeviceInfo(d(), CL_DEVICE_HOST_UNIFIED_MEMORY, sizeof unified, &unified, nullptr);
    return unified ? DeviceType::Integrated : DeviceType::Discrete;
  }
  if (t & CL_DEVICE_TYPE_ACCELERATOR) return DeviceType::Accelerator;
  if (t & CL_DEVICE_TYPE_CPU) return DeviceType::Cpu;
  return DeviceType::Other;
}

// "OpenCL 1.2 pocl ..." -> 12; 0 when unreadable.
int version_number(const std::string& v) {
  int major = 0, minor = 0;
  if (std::sscanf(v.c_str(), "OpenCL %d.%d", &major, &minor) != 2) return 0;
  return major * 10 + minor;
}

// OpenCL core has no subgroup size before 2.1, and then only per kernel; the vendors'
// device queries give the hardware's SIMD width. Without one, what the device reports
// instead is named.
void subgroup(const cl::Device& d, DeviceInfo& info) {
  const std::string ext = d.getInfo<CL_DEVICE_EXTENSIONS>();
  auto has = [&](const char* name) { return (" " + ext + " ").find(std::string(" ") + name + " ") != std::string::npos; };
  cl_uint width = 0;
  if (has("cl_nv_device_attribute_query") &&
      clGetDeviceInfo(d(), CL_DEVICE_WARP_SIZE_NV, sizeof width, &width, nullptr) == CL_SUCCESS && width) {
    info.subgroup_size = width;
    info.subgroup_source = "CL_DEVICE_WARP_SIZE_NV";
    return;
  }
  if (has("cl_amd_device_attribute_query") &&
      clGetDeviceInfo(d(), CL_DEVICE_WAVEFRONT_WIDTH_AMD, sizeof width, &width, nullptr) == CL_SUCCESS && width) {
    info.subgroup_size = width;
    info.subgroup_source = "CL_DEVICE_WAVEFRONT_WIDTH_AMD";
    return;
  }
  std::size_t bytes = 0;
  if (has("cl_intel_required_subgroup_size") &&
      clGetDeviceInfo(d(), CL_DEVICE_SUB_GROUP_SIZES_INTEL, 0, nullptr, &bytes) == CL_SUCCESS && bytes) {
    std::vector<std::size_t> sizes(bytes / sizeof(std::size_t));
    clGetDeviceInfo(d(), CL_DEVICE_SUB_GROUP_SIZES_INTEL, bytes, sizes.data(), nullptr);
    info.subgroup_size = static_cast<std::uint32_t>(*std::max_element(sizes.begin(), sizes.end()));
    info.subgroup_source = "largest of CL_DEVICE_SUB_GROUP_SIZES_INTEL";
    return;
  }
  info.subgroup_source = "not reported; CL_DEVICE_MAX_WORK_GROUP_SIZE " +
                         std::to_string(d.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>()) + " over CL_DEVICE_MAX_COMPUTE_UNITS " +
                         std::to_string(d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>());
}

DeviceInfo describe(const cl::Platform& p, const cl::Device& d, int index) {
  DeviceInfo info;
  info.index = index;
  info.name = cl_trimmed(d.getInfo<CL_DEVICE_NAME>());
  info.type = device_type(d);
  const std::string version = cl_trimmed(d.getInfo<CL_DEVICE_VERSION>());
  if (!d.getInfo<CL_DEVICE_AVAILABLE>()) info.unusable = "is not available (CL_DEVICE_AVAILABLE)";
  else if (!d.getInfo<CL_DEVICE_COMPILER_AVAILABLE>()) info.unusable = "has no compiler (CL_DEVICE_COMPILER_AVAILABLE)";
  else if (version_number(version) < 12) info.unusable = "reports '" + version + "', masq needs OpenCL 1.2";
  info.no_ray_query = "is an OpenCL device";
  info.memory_bytes = d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
  subgroup(d, info);
  info.driver = cl_trimmed(d.getInfo<CL_DRIVER_VERSION>()) + ", " + cl_trimmed(p.getInfo<CL_PLATFORM_VERSION>());
  return info;
}

std::vector<DeviceInfo> infos(const std::vector<ClDevice>& devices) {
  std::vector<DeviceInfo> out;
  for (const ClDevice& d : devices) out.push_back(d.info);
  return out;
}

} // namespace

DeviceChoice choose_opencl_device(const std::vector<DeviceInfo>& devices) {
  return choose_device(devices, device_selector(DeviceApi::OpenCl), "OpenCL", DeviceNeed::Compute);
}

std::vector<ClDevice> cl_devices() {
  std::vector<cl::Platform> platforms;
  cl_int err = cl::Platform::get(&platforms);
  if (err != CL_SUCCESS || platforms.empty())
    throw BackendUnavailable("opencl: no OpenCL platform (clGetPlatformIDs: " +
                             cl_error_name(err == CL_SUCCESS ? CL_PLATFORM_NOT_FOUND_KHR : err) + ")");
  std::vector<ClDevice> out;
  cl_int last = CL_DEVICE_NOT_FOUND;
  for (const cl::Platform& p : platforms) {
    std::vector<cl::Device> devices;
    cl_int e = p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    if (e != CL_SUCCESS) {
      last = e;
      continue;
    }
    for (const cl::Device& d : devices) out.push_back({p, d, describe(p, d, static_cast<int>(out.size()))});
  }
  if (out.empty())
    throw BackendUnavailable("opencl: no OpenCL device on " + std::to_string(platforms.size()) +
                             " platform(s) (clGetDeviceIDs: " + cl_error_name(last) + ")");
  return out;
}

const ClDevice& choose_cl_device(const std::vector<ClDevice>& devices) {
  DeviceChoice c = choose_opencl_device(infos(devices));
  if (c.position < 0) throw BackendUnavailable("opencl: " + c.why);
  return devices[static_cast<std::size_t>(c.position)];
}

std::vector<DeviceInfo> cl_device_infos() { return infos(cl_devices()); }

} // namespace masq::opencl
