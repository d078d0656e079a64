#include "host/opencl/cl_local_size.h"
#include <algorithm>
#include <vector>

namespace masq::opencl {

namespace {

constexpr std::size_t kPreferredGroup = 64; // as the Vulkan pipelines (host/vulkan/vk_shader_limits.cpp)

} // namespace

WorkGroup fit_work_group(bool cpu_device, std::size_t want, std::size_t preferred_multiple, std::size_t kernel_max,
                         std::size_t device_max_x) {
  want = std::max<std::size_t>(want, 1);
  if (cpu_device) return {0, want};
  const std::size_t m = std::max<std::size_t>(preferred_multiple, 1);
  const std::size_t limit = std::max<std::size_t>(1, std::min(kernel_max, device_max_x));
  std::size_t local = (want + m - 1) / m * m;
  if (local > limit) local = limit >= m ? limit / m * m : limit;
  return {local, local};
}

WorkGroup kernel_work_group(const Runtime& rt, const cl::Kernel& k) {
  cl_int err = CL_SUCCESS;
  const auto type = rt.device.getInfo<CL_DEVICE_TYPE>(&err);
  check(err, "clGetDeviceInfo(CL_DEVICE_TYPE)");
  const std::size_t multiple = k.getWorkGroupInfo<CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE>(rt.device, &err);
  check(err, "clGetKernelWorkGroupInfo(CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE)");
  const std::size_t kernel_max = k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(rt.device, &err);
  check(err, "clGetKernelWorkGroupInfo(CL_KERNEL_WORK_GROUP_SIZE)");
  const std::vector<std::size_t> item_sizes = rt.device.getInfo<CL_DEVICE_MAX_WORK_ITEM_SIZES>(&err);
  check(err, "clGetDeviceInfo(CL_DEVICE_MAX_WORK_ITEM_SIZES)");
  const std::size_t device_max_x = item_sizes.empty() ? kernel_max : item_sizes[0];
  return fit_work_group((type & CL_DEVICE_TYPE_CPU) != 0, kPreferredGroup, multiple, kernel_max, device_max_x);
}

} // namespace masq::opencl
