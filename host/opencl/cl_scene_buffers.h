// The scene arrays of kernels/scene_array_table.h on an OpenCL device: uploaded once per
// scene, then passed as the first kernel arguments, in table order, to the trace and bv
// kernels alike (MASQ_CL_SCENE_PARAMS in kernels/kernel_data.h).
#pragma once
#include "host/opencl/cl_runtime.h"
#include "host/scene_arrays.h"
#include <array>
#include <cstddef>

namespace masq::opencl {

struct SceneBuffers {
  // Every row: its upload when the family's kernels read it (a 16-byte stand-in when it
  // is empty: OpenCL rejects zero-sized buffers), else the runtime's shared stand-in.
  std::array<cl::Buffer, kSceneArrayCount> rows;
  std::size_t bytes = 0; // the uploads, stand-ins for empty read arrays included
};

// Uploads the rows `family` reads (without waiting for the copies). Throws masq::Error
// "<backend>: scene array '<name>' needs N bytes, more than the device's largest
// allocation (...)" for a row over CL_DEVICE_MAX_MEM_ALLOC_SIZE.
SceneBuffers upload_scene_arrays(const Runtime& rt, const char* backend, const SceneArrayData& data,
                                 KernelFamily family, const cl::Buffer& stand_in);

// A 16-byte buffer the kernels never read, for the rows of another family.
cl::Buffer stand_in_buffer(const Runtime& rt);

// Sets the rows as arguments 0 .. kSceneArrayCount-1 of `kernel`; returns the index of
// the kernel's first own argument.
cl_uint set_scene_args(cl::Kernel& kernel, const SceneBuffers& buffers);

} // namespace masq::opencl
