#include "host/opencl/cl_scene_buffers.h"
#include "masq/error.h"
#include <algorithm>
#include <string>

namespace masq::opencl {

namespace {
constexpr std::size_t kStandInBytes = 16;

cl::Buffer device_buffer(const Runtime& rt, std::size_t bytes, const std::string& what) {
  cl_int err = CL_SUCCESS;
  cl::Buffer buf(rt.context, CL_MEM_READ_ONLY, std::max(bytes, kStandInBytes), nullptr, &err);
  check(err, "clCreateBuffer(" + what + ", " + std::to_string(std::max(bytes, kStandInBytes)) + " bytes)");
  return buf;
}
} // namespace

cl::Buffer stand_in_buffer(const Runtime& rt) { return device_buffer(rt, kStandInBytes, "unread scene arrays"); }

SceneBuffers upload_scene_arrays(const Runtime& rt, const char* backend, const SceneArrayData& data,
                                 KernelFamily family, const cl::Buffer& stand_in) {
  SceneBuffers out;
  for (std::size_t i = 0; i < kSceneArrayCount; ++i) {
    const SceneArrayInfo& row = kSceneArrays[i];
    if (!row.read_by(family)) {
      out.rows[i] = stand_in;
      continue;
    }
    const ArrayBytes& d = data.rows[i];
    if (d.bytes > rt.max_alloc_bytes())
      throw Error(std::string(backend) + ": scene array '" + std::string(row.name) + "' needs " +
                  std::to_string(d.bytes) +
                  " bytes, more than the device's largest allocation (CL_DEVICE_MAX_MEM_ALLOC_SIZE = " +
                  std::to_string(rt.max_alloc_bytes()) + " bytes)");
    const std::string what = std::string(row.name);
    out.rows[i] = device_buffer(rt, d.bytes, what);
    if (d.bytes > 0)
      check(rt.queue.enqueueWriteBuffer(out.rows[i], CL_FALSE, 0, d.bytes, d.data), "clEnqueueWriteBuffer(" + what + ")");
    out.bytes += std::max(d.bytes, kStandInBytes);
  }
  return out;
}

cl_uint set_scene_args(cl::Kernel& kernel, const SceneBuffers& buffers) {
  cl_uint arg = 0;
  for (std::size_t i = 0; i < kSceneArrayCount; ++i, ++arg)
    check(kernel.setArg(arg, buffers.rows[i]), "clSetKernelArg(" + std::string(kSceneArrays[i].name) + ")");
  return arg;
}

} // namespace masq::opencl
