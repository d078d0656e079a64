#include "host/opencl/cl_runtime.h"

#include "host/backend.h"
#include "host/opencl/cl_devices.h"
#include "masq/error.h"

#include <chrono>
#include <sstream>
#include <vector>

namespace masq::opencl {

std::string cl_error_name(cl_int code) {
  switch (code) {
#define MASQ_CL_CODE(c) \
  case c:               \
    return #c;
    MASQ_CL_CODE(CL_SUCCESS)
    MASQ_CL_CODE(CL_DEVICE_NOT_FOUND)
    MASQ_CL_CODE(CL_DEVICE_NOT_AVAILABLE)
    MASQ_CL_CODE(CL_COMPILER_NOT_AVAILABLE)
    MASQ_CL_CODE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    MASQ_CL_CODE(CL_OUT_OF_RESOURCES)
    MASQ_CL_CODE(CL_OUT_OF_HOST_MEMORY)
    MASQ_CL_CODE(CL_PROFILING_INFO_NOT_AVAILABLE)
    MASQ_CL_CODE(CL_BUILD_PROGRAM_FAILURE)
    MASQ_CL_CODE(CL_MAP_FAILURE)
    MASQ_CL_CODE(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
    MASQ_CL_CODE(CL_INVALID_VALUE)
    MASQ_CL_CODE(CL_INVALID_DEVICE_TYPE)
    MASQ_CL_CODE(CL_INVALID_PLATFORM)
    MASQ_CL_CODE(CL_INVALID_DEVICE)
    MASQ_CL_CODE(CL_INVALID_CONTEXT)
    MASQ_CL_CODE(CL_INVALID_QUEUE_PROPERTIES)
    MASQ_CL_CODE(CL_INVALID_COMMAND_QUEUE)
    MASQ_CL_CODE(CL_INVALID_MEM_OBJECT)
    MASQ_CL_CODE(CL_INVALID_BINARY)
    MASQ_CL_CODE(CL_INVALID_BUILD_OPTIONS)
    MASQ_CL_CODE(CL_INVALID_PROGRAM)
    MASQ_CL_CODE(CL_INVALID_PROGRAM_EXECUTABLE)
    MASQ_CL_CODE(CL_INVALID_KERNEL_NAME)
    MASQ_CL_CODE(CL_INVALID_KERNEL)
    MASQ_CL_CODE(CL_INVALID_ARG_INDEX)
    MASQ_CL_CODE(CL_INVALID_ARG_VALUE)
    MASQ_CL_CODE(CL_INVALID_ARG_SIZE)
    MASQ_CL_CODE(CL_INVALID_KERNEL_ARGS)
    MASQ_CL_CODE(CL_INVALID_WORK_DIMENSION)
    MASQ_CL_CODE(CL_INVALID_WORK_GROUP_SIZE)
    MASQ_CL_CODE(CL_INVALID_WORK_ITEM_SIZE)
    MASQ_CL_CODE(CL_INVALID_GLOBAL_OFFSET)
    MASQ_CL_CODE(CL_INVALID_EVENT)
    MASQ_CL_CODE(CL_INVALID_OPERATION)
    MASQ_CL_CODE(CL_INVALID_BUFFER_SIZE)
    MASQ_CL_CODE(CL_INVALID_GLOBAL_WORK_SIZE)
    MASQ_CL_CODE(CL_PLATFORM_NOT_FOUND_KHR)
#undef MASQ_CL_CODE
    default:
      return "CL error " + std::to_string(code);
  }
}

void check(cl_int code, std::string_view what) {
  if (code != CL_SUCCESS)
    throw Error("opencl: " + std::string(what) + " failed (" + cl_error_name(code) + ")");
}

std::size_t resident_threads(const Runtime& rt) {
  cl_device_type type = 0;
  cl_uint units = 0;
  std::size_t group = 0;
  if (rt.device.getInfo(CL_DEVICE_TYPE, &type) != CL_SUCCESS ||
      rt.device.getInfo(CL_DEVICE_MAX_COMPUTE_UNITS, &units) != CL_SUCCESS ||
      rt.device.getInfo(CL_DEVICE_MAX_WORK_GROUP_SIZE, &group) != CL_SUCCESS)
    return 0; // the device does not say
  if (type & CL_DEVICE_TYPE_CPU) return std::size_t(units) * 8;
  return std::size_t(units) * group;
}

double event_seconds(const std::vector<cl::Event>& events) {
  cl_ulong total_ns = 0;
  for (const cl::Event& ev : events) {
    cl_ulong t0 = 0, t1 = 0;
    check(ev.getProfilingInfo(CL_PROFILING_COMMAND_START, &t0), "clGetEventProfilingInfo(start)");
    check(ev.getProfilingInfo(CL_PROFILING_COMMAND_END, &t1), "clGetEventProfilingInfo(end)");
    total_ns += t1 - t0;
  }
  return static_cast<double>(total_ns) * 1e-9;
}

namespace {

std::string describe(const cl::Platform& platform, const cl::Device& device) {
  return cl_trimmed(device.getInfo<CL_DEVICE_NAME>()) + " (driver " + cl_trimmed(device.getInfo<CL_DRIVER_VERSION>()) +
         ", " + cl_trimmed(platform.getInfo<CL_PLATFORM_VERSION>()) + ")";
}

// The error lines of a compiler log (else its first lines), joined into one line.
std::string summarize_log(const std::string& log) {
  std::vector<std::string> all, errors;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);) {
    line = cl_trimmed(line);
    if (line.empty()) continue;
    all.push_back(line);
    if (line.find("error") != std::string::npos) errors.push_back(line);
  }
  const auto& pick = errors.empty() ? all : errors;
  std::string out;
  for (std::size_t i = 0; i < pick.size() && i < 6; ++i) out += (i ? " | " : "") + pick[i];
  if (pick.size() > 6) out += " | (" + std::to_string(pick.size() - 6) + " more)";
  return out.empty() ? "(empty build log)" : out;
}

} // namespace

Runtime open_runtime() {
  // The best-ranked device of every platform (GPU > accelerator > CPU), or the one
  // MASQ_CL_DEVICE / --device names (host/opencl/cl_devices.h).
  const std::vector<ClDevice> devices = cl_devices();
  const ClDevice& chosen = choose_cl_device(devices);
  Runtime rt;
  rt.platform = chosen.platform;
  rt.device = chosen.device;
  cl_int err = CL_SUCCESS;
  rt.context = cl::Context(rt.device, nullptr, nullptr, nullptr, &err);
  if (err != CL_SUCCESS) throw BackendUnavailable("opencl: clCreateContext failed (" + cl_error_name(err) + ")");
  rt.queue = cl::CommandQueue(rt.context, rt.device, CL_QUEUE_PROFILING_ENABLE, &err);
  if (err != CL_SUCCESS)
    throw BackendUnavailable("opencl: clCreateCommandQueue failed (" + cl_error_name(err) + ")");
  rt.description = describe(rt.platform, rt.device);
  rt.max_alloc = static_cast<std::size_t>(rt.device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>());
  rt.correctly_rounded_divide_sqrt =
      (rt.device.getInfo<CL_DEVICE_SINGLE_FP_CONFIG>() & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) != 0;
  return rt;
}

std::string base_build_options(const Runtime& rt) {
  return rt.correctly_rounded_divide_sqrt ? "-cl-std=CL1.2 -cl-fp32-correctly-rounded-divide-sqrt" : "-cl-std=CL1.2";
}

std::string variant_build_options(const KernelVariant& v) {
  std::string out;
  const auto values = switch_values(v);
  for (std::size_t i = 0; i < kVariantSwitchCount; ++i)
    out += " -D " + std::string(kVariantSwitches[i].name) + "=" + std::to_string(values[i]);
  return out;
}

BuiltProgram build_program(const Runtime& rt, const std::string& source, const std::string& options,
                           std::string_view label) {
  cl_int err = CL_SUCCESS;
  BuiltProgram out;
  out.program = cl::Program(rt.context, source, false, &err);
  check(err, "clCreateProgramWithSource (" + std::string(label) + ")");
  auto start = std::chrono::steady_clock::now();
  err = out.program.build(std::vector<cl::Device>{rt.device}, options.c_str());
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (err != CL_SUCCESS) {
    std::string log = out.program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(rt.device);
    throw Error("opencl: building " + std::string(label) + " with \"" + options + "\" failed (" +
                cl_error_name(err) + "): " + summarize_log(log));
  }
  return out;
}

} // namespace masq::opencl
