// OpenCL plumbing shared by the opencl backend and its tests: device choice, checked
// calls, program builds with readable errors. Not part of the public Backend API.
#pragma once
#ifndef CL_HPP_TARGET_OPENCL_VERSION
#define CL_HPP_TARGET_OPENCL_VERSION 120
#endif
#ifndef CL_HPP_MINIMUM_OPENCL_VERSION
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#endif
#include "host/kernel_variant.h"
#include "host/limit_knob.h"
#include <CL/opencl.hpp>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace masq::opencl {

// "CL_OUT_OF_RESOURCES", ..., or "CL error <n>" for codes without a name here.
std::string cl_error_name(cl_int code);
// A string the OpenCL runtime returned, without its trailing NULs, newlines and blanks.
std::string cl_trimmed(std::string s);

// Throws masq::Error "opencl: <what> failed (<CL_NAME>)" unless code is CL_SUCCESS.
void check(cl_int code, std::string_view what);

struct Runtime {
  cl::Platform platform;
  cl::Device device;
  cl::Context context;
  cl::CommandQueue queue;    // in order, profiling enabled
  std::string description;   // device name, driver version, platform version
  std::size_t max_alloc = 0; // CL_DEVICE_MAX_MEM_ALLOC_SIZE
  // CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT in CL_DEVICE_SINGLE_FP_CONFIG: the device can
  // build with -cl-fp32-correctly-rounded-divide-sqrt.
  bool correctly_rounded_divide_sqrt = false;
  // max_alloc lowered by MASQ_CL_MAX_ALLOC_BYTES (host/limit_knob.h), for tests of the
  // over-the-limit error on small scenes.
  std::size_t max_alloc_bytes() const {
    return static_cast<std::size_t>(lowered_limit("opencl", max_alloc, Knob::ClMaxAllocBytes));
  }
};

// Opens the device host/opencl/cl_devices.h chooses. Throws BackendUnavailable (one line,
// naming the failing call) when there is none, masq::Error for a selector naming none.
Runtime open_runtime();

// The work-items the runtime's device keeps in flight, for Backend::fill_rays
// (host/device_fill.h). OpenCL reports compute units but not the threads resident on
// one: a GPU or accelerator counts CL_DEVICE_MAX_WORK_GROUP_SIZE per unit (a lower
// bound: an NVIDIA SM keeps 2048, an AMD CU up to 2560), a CPU 8 per unit (one AVX
// vector of work-items per hardware thread, as PoCL vectorises them).
std::size_t resident_threads(const Runtime& rt);

// The device time of finished commands of a queue with profiling: the sum of each
// event's end - start. Throws masq::Error naming the failing call.
double event_seconds(const std::vector<cl::Event>& events);

struct BuiltProgram {
  cl::Program program;
  double seconds = 0; // clBuildProgram wall time
};

// Builds OpenCL C source for the runtime's device. On failure throws masq::Error naming
// `label`, the options and the first error lines of the build log.
BuiltProgram build_program(const Runtime& rt, const std::string& source, const std::string& options,
                           std::string_view label);

// The options every masq program is built with: OpenCL C 1.2; never relaxed math (the
// intersectors' error bounds assume IEEE single precision); and correctly rounded
// division and square root where the device offers them (OpenCL C allows 2.5 and 3 ulp
// otherwise), so that they round as on the cpu (docs/robustness.md, "Float semantics").
std::string base_build_options(const Runtime& rt);

// The -D switches of one kernel variant for clBuildProgram: every row of
// kernels/variant_table.h. Shared by the trace and bv programs.
std::string variant_build_options(const KernelVariant& v);

} // namespace masq::opencl
