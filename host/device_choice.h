// Which device the GPU backends open: the ranking of device types, the selectors
// (MASQ_VK_DEVICE, MASQ_RQ_DEVICE, MASQ_CL_DEVICE, `--device`) and the one-line error of a
// selector that matches nothing. Pure: no driver calls. host/vulkan/vk_devices.cpp and
// host/opencl/cl_devices.cpp describe each driver's devices as DeviceInfo and choose
// through these functions, so the choice is tested with devices given as data
// (tests/test_device_choice.cpp).
#pragma once
#include "masq/knobs.h"
#include "masq/names.h"
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace masq {

// Device types, best first: the row order is the rank. Vulkan reports discrete,
// integrated, virtual, cpu and other; OpenCL reports GPU (split into discrete and
// integrated by CL_DEVICE_HOST_UNIFIED_MEMORY), accelerator, CPU and custom (other).
// Ties keep the driver's enumeration order.
enum class DeviceType { Discrete, Integrated, Virtual, Accelerator, Cpu, Other };
inline constexpr NameRow<DeviceType> device_type_rows[] = {
    {DeviceType::Discrete, "discrete GPU", "its own memory"},
    {DeviceType::Integrated, "integrated GPU", "shares the host's memory"},
    {DeviceType::Virtual, "virtual GPU", "a GPU passed through a hypervisor"},
    {DeviceType::Accelerator, "accelerator", "OpenCL CL_DEVICE_TYPE_ACCELERATOR"},
    {DeviceType::Cpu, "cpu", "runs on the host's cores (lavapipe, PoCL)"},
    {DeviceType::Other, "other", "any other type"},
};
inline constexpr NameTable device_type_table{"device type", device_type_rows};

// The device APIs a selector can name, each with its environment variable. rayquery and
// rtpipeline follow vulkan's device unless their own variable (or --device rayquery=...,
// rtpipeline=...) names one.
enum class DeviceApi { Vulkan, RayQuery, RtPipeline, OpenCl };
struct DeviceApiRow {
  DeviceApi value;
  const char* name;
  const char* help;
  Knob knob; // the selector's environment variable
};
inline constexpr DeviceApiRow device_api_rows[] = {
    {DeviceApi::Vulkan, "vulkan", "the vulkan backend, and rayquery and rtpipeline unless told otherwise",
     Knob::VkDevice},
    {DeviceApi::RayQuery, "rayquery", "the rayquery backend (default: the vulkan backend's device)", Knob::RqDevice},
    {DeviceApi::RtPipeline, "rtpipeline", "the rtpipeline backend (default: the vulkan backend's device)",
     Knob::RtDevice},
    {DeviceApi::OpenCl, "opencl", "the opencl backend", Knob::ClDevice},
};
inline constexpr NameTable device_api_table{"device API", device_api_rows};

// One device as a driver describes it.
struct DeviceInfo {
  int index = 0;    // position in the API's enumeration: what `masq info` shows, what an index selector names
  std::string name; // as the driver reports it
  DeviceType type = DeviceType::Other;
  std::string unusable;     // why masq's kernels cannot run on it ("" : they can), e.g. "is older than Vulkan 1.2"
  std::string no_ray_query;    // Vulkan: why ray query cannot run on it ("" : it can); OpenCL: unused
  std::string no_ray_pipeline; // Vulkan: why the ray-tracing pipeline cannot run on it ("" : it can)
  // Shown by `masq info` only:
  std::uint64_t memory_bytes = 0;  // Vulkan: the largest device-local heap; OpenCL: CL_DEVICE_GLOBAL_MEM_SIZE
  std::uint32_t subgroup_size = 0; // 0: the device does not report one
  std::string subgroup_source;     // where subgroup_size comes from, or what the device reports instead
  std::string driver;              // driver name and version
};

// A selector: a decimal index of the API's enumeration, or a case-insensitive substring
// of the device name. Empty: none given, the best-ranked usable device is taken.
struct DeviceSelector {
  std::string value;
  std::string source; // "MASQ_VK_DEVICE", "--device": named in errors
  bool empty() const { return value.empty(); }
};

// The rank of a type: 0 is best (device_type_table's row order).
int device_rank(DeviceType type);
// Positions into `devices`, best rank first, ties in enumeration order.
std::vector<std::size_t> ranked_devices(std::span<const DeviceInfo> devices);
// Does `selector` (non-empty) name this device: its index, or a substring of its name
// ignoring case.
bool selector_matches(const DeviceInfo& device, std::string_view selector);
// "0 'llvmpipe (LLVM 15.0.6, 256 bits)' (cpu), 1 '...' (discrete GPU)", or "none".
std::string device_list_text(std::span<const DeviceInfo> devices);

// What a backend needs of its device: the compute kernels, or besides them the driver's
// traversal through ray query or through the ray-tracing pipeline.
enum class DeviceNeed { Compute, RayQuery, RayPipeline };

// The chosen device: its position in the list, or -1 and one line saying why none serves
// ("device 'X' is older than Vulkan 1.2"; the caller throws BackendUnavailable with it).
struct DeviceChoice {
  int position = -1;
  std::string why;
};

// The best-ranked device that `selector` names (every device when it is empty) and that
// serves `need`. A non-empty selector that names no device throws masq::Error naming the
// selector, `api_label` ("Vulkan") and the devices there are: an explicit choice that
// cannot be honoured is an error, never a silent fallback to another device.
DeviceChoice choose_device(std::span<const DeviceInfo> devices, const DeviceSelector& selector,
                           std::string_view api_label, DeviceNeed need);

// The device of a backend the driver traverses for (rayquery: need RayQuery, api
// RayQuery; rtpipeline: RayPipeline, RtPipeline). With its own selector: the best device
// that names and that serves `need`. Without: the vulkan backend's device (chosen by
// `vulkan` for compute), and none (the reason naming the device) when that device cannot
// serve `need`: the driver's traversal and masq's kernels are compared on one device,
// never on a GPU and a CPU.
DeviceChoice choose_traversal_device(std::span<const DeviceInfo> devices, const DeviceSelector& vulkan,
                                     const DeviceSelector& own, DeviceNeed need, DeviceApi api);

// The selector in force for `api`: set_device_selector's, else the API's environment
// variable, else none.
DeviceSelector device_selector(DeviceApi api);
// Overrides the environment for this process (the CLI's --device, a Context naming its
// device); "" clears it. A backend opened after the change opens the device it names;
// backends already open keep theirs.
void set_device_selector(DeviceApi api, std::string value, std::string source);

// The CLI's --device value: "SEL" (vulkan and opencl, rayquery following vulkan) or
// "api=SEL[,api=SEL...]" with api a name of device_api_table. A comma not followed by
// "api=" belongs to the selector. Throws masq::Error naming the value on a bad one.
std::vector<std::pair<DeviceApi, std::string>> parse_device_option(std::string_view value);

} // namespace masq
