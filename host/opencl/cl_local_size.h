// The work-group size of an OpenCL dispatch, from the device and the built kernel.
#pragma once
#include "host/opencl/cl_runtime.h"
#include <cstddef>

namespace masq::opencl {

struct WorkGroup {
  std::size_t local = 0;           // 0: the runtime chooses (cl::NullRange)
  std::size_t global_multiple = 1; // global sizes are padded to this
};

// The shape for `want` work items per group (the kernels' 64, as on Vulkan) and a
// device of this type and these kernel limits: a GPU or accelerator gets `want` rounded
// up to the kernel's CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE (its warp or wavefront),
// lowered to CL_KERNEL_WORK_GROUP_SIZE (what the kernel's registers allow) and
// CL_DEVICE_MAX_WORK_ITEM_SIZES[0]; a CPU device keeps the runtime's own choice (PoCL
// packs a group's items into its vector loops and sizes groups from the global size),
// with the global size padded to `want` so that choice is never a group of one.
WorkGroup fit_work_group(bool cpu_device, std::size_t want, std::size_t preferred_multiple,
                         std::size_t kernel_max, std::size_t device_max_x);

// fit_work_group for kernel `k` on the runtime's device (clGetKernelWorkGroupInfo).
WorkGroup kernel_work_group(const Runtime& rt, const cl::Kernel& k);

// `n` work items padded to the shape's multiple.
inline std::size_t padded_global(const WorkGroup& g, std::size_t n) {
  return (n + g.global_multiple - 1) / g.global_multiple * g.global_multiple;
}

} // namespace masq::opencl
