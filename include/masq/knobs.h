/// @file masq/knobs.h
/// The environment variables masq reads (its knobs), in one table: name, type, default,
/// meaning and who reads it. Every reader goes through the accessors below (knobs/knobs.cpp
/// alone reads the environment), so a bad value is one masq::Error naming
/// the variable, its value and what is expected; `masq info --env` prints the table with
/// the current values, and docs/knobs.md is generated from it (`masq info --env
/// --markdown`; ctest `knob_docs` fails when the two differ).
///
/// A knob is read at each use unless its row says otherwise, so a test (or a program)
/// that sets one between scenes sees it take effect at the next use.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace masq {

/// One enumerator per row of knob_rows, in the same order.
enum class Knob {
  Data,
  CpuThreads,
  HugePages,
  StepCheck,
  StackForm,
  Diagnose,
  MaxRaysPerDispatch,
  VkDevice,
  RqDevice,
  RtDevice,
  ClDevice,
  VkAddressing,
  VkFloatControls,
  VkSpecialize,
  VkLocalSize,
  VkValidation,
  VkPipelineStats,
  VkForceStaging,
  VkWaitSeconds,
  CacheDir,
  VkMaxBindingBytes,
  VkMaxAllocationBytes,
  VkMaxAllocations,
  VkStagingBytes,
  RqMaxInstances,
  RqMaxPrimitives,
  RtMaxGroupStride,
  ClMaxAllocBytes,
  VkFaultDeviceLost,
  VkFaultTimeout,
  VkHideExtensions,
  TestBackends,
  AllowMissingBackends,
  DataDir,
};

/// What a knob's value may be.
enum class KnobType {
  Integer, ///< decimal digits only, within the row's [min, max]
  Choice,  ///< one of the row's `choices` ("on|off"); unset or empty: the default
  Flag,    ///< 0 or 1 (a Choice of "0|1" whose default is 0)
  Path,    ///< any text: a directory
  List,    ///< any text: names separated by commas
  Device,  ///< a device selector: an index or a name substring (docs/devices.md)
};

/// One knob. `default_text` and `meaning` are what `masq info --env` and docs/knobs.md
/// show; `readers` the files that read it.
struct KnobRow {
  Knob knob;
  const char* name;
  KnobType type;
  const char* choices; ///< Choice and Flag: the accepted values, '|'-separated; else nullptr
  std::uint64_t min;   ///< Integer: the smallest value accepted
  std::uint64_t max;   ///< Integer: the largest value accepted
  const char* default_text;
  const char* meaning; ///< one or two sentences, no trailing period
  const char* readers;
};

inline constexpr std::uint64_t kNoKnobMax = std::numeric_limits<std::uint64_t>::max();

// clang-format off
inline constexpr KnobRow knob_rows[] = {
    {Knob::Data, "MASQ_DATA", KnobType::Path, nullptr, 0, 0, "unset",
     "The directory '${MASQ_DATA}' stands for at the start of a path in a scene description; "
     "masq bench --suite reads its real scenes there unless --data names one (else the build's shared/data)",
     "scenes/loaders/load_description.cpp, cli/cmd_bench.cpp"},
    {Knob::CpuThreads, "MASQ_CPU_THREADS", KnobType::Integer, nullptr, 1, kNoKnobMax,
     "the hardware's thread count", "Threads of the cpu backend and the cpu bv tracer",
     "host/cpu/cpu_backend.cpp, host/cpu/cpu_bv_tracer.cpp"},
    {Knob::HugePages, "MASQ_HUGE_PAGES", KnobType::Choice, "on|off", 0, 0, "on",
     "on: the host's arrays of 2 MiB or more (BVH builds, packed scenes) are mapped on their own and advised "
     "transparent huge pages (scenes/huge_page_vector.h); off: the C++ allocator's ordinary pages. Read once per process",
     "scenes/huge_page_vector.cpp"},
    {Knob::StepCheck, "MASQ_STEP_CHECK", KnobType::Choice, "on|off", 0, 0, "on",
     "The traversal's step budget and full-stack faults (docs/kernels.md, \"Traversal that cannot hang\"); "
     "off compiles the check out",
     "host/scene_variant.cpp"},
    {Knob::StackForm, "MASQ_STACK_FORM", KnobType::Choice, "fixed|sized", 0, 0, "fixed",
     "The traversal stack's dimension: 64 entries, or the scene's need (docs/kernels.md, \"Stack forms\")",
     "host/scene_variant.cpp"},
    {Knob::Diagnose, "MASQ_DIAGNOSE", KnobType::Integer, nullptr, 0, 1000000, "0",
     "How many of the rays a traversal stopped its error lists, each with its fault, level, node and stack depth",
     "host/trace_faults.cpp"},
    {Knob::MaxRaysPerDispatch, "MASQ_MAX_RAYS_PER_DISPATCH", KnobType::Integer, nullptr, 1, kNoKnobMax,
     "1048576 (kMaxRaysPerDispatch)",
     "Lowers the rays in one dispatch on vulkan, rayquery, rtpipeline and opencl and their bv tracers, "
     "so a dispatch stays under a display GPU's watchdog",
     "host/limit_knob.h (host/vulkan/trace_dispatch.cpp, host/opencl/)"},
    {Knob::VkDevice, "MASQ_VK_DEVICE", KnobType::Device, nullptr, 0, 0, "the best-ranked usable device",
     "The device of the vulkan backend, and of rayquery and rtpipeline unless their own selector names one",
     "host/device_choice.cpp"},
    {Knob::RqDevice, "MASQ_RQ_DEVICE", KnobType::Device, nullptr, 0, 0, "the vulkan backend's device",
     "The device of the rayquery backend", "host/device_choice.cpp"},
    {Knob::RtDevice, "MASQ_RT_DEVICE", KnobType::Device, nullptr, 0, 0, "the vulkan backend's device",
     "The device of the rtpipeline backend", "host/device_choice.cpp"},
    {Knob::ClDevice, "MASQ_CL_DEVICE", KnobType::Device, nullptr, 0, 0, "the best-ranked usable device",
     "The device of the opencl backend", "host/device_choice.cpp"},
    {Knob::VkAddressing, "MASQ_VK_ADDRESSING", KnobType::Choice, "addressed|bound", 0, 0, "addressed",
     "How the vulkan backend reads the scene arrays: by buffer device address where the device has it, "
     "or through storage-buffer descriptors (arrays over one binding are still addressed)",
     "host/vulkan/vulkan_compute_backend.cpp"},
    {Knob::VkFloatControls, "MASQ_VK_FLOAT_CONTROLS", KnobType::Choice, "on|off", 0, 0, "on",
     "on: the Vulkan kernels' SPIR-V gets NoContraction, and SignedZeroInfNanPreserve where the device "
     "supports it; off: the SPIR-V as compiled",
     "host/vulkan/vk_shader_limits.cpp"},
    {Knob::VkSpecialize, "MASQ_VK_SPECIALIZE", KnobType::Choice, "host|driver", 0, 0, "host",
     "host: masq applies a Vulkan pipeline's specialization constants to its SPIR-V and drops the code they "
     "disable before the driver compiles it; driver: the SPIR-V as compiled, with the constants passed to the driver "
     "(read when a backend first makes a variant's pipeline)",
     "host/vulkan/spirv_specialize.cpp"},
    {Knob::VkLocalSize, "MASQ_VK_LOCAL_SIZE", KnobType::Integer, nullptr, 1, 1024, "64, fitted to the device's subgroup and limits",
     "The work-group size of the Vulkan kernels (over the device's limits: an error); read once per process", "host/vulkan/vk_shader_limits.cpp"},
    {Knob::VkValidation, "MASQ_VK_VALIDATION", KnobType::Choice, "0|1|sync", 0, 0, "0",
     "1: the Vulkan validation layer and a messenger, an error making the next submission throw; "
     "sync: also its synchronization validation",
     "host/vulkan/vk_context.cpp"},
    {Knob::VkPipelineStats, "MASQ_VK_PIPELINE_STATS", KnobType::Flag, "0|1", 0, 0, "0",
     "1: print the driver's compile statistics of every compute pipeline (registers, local memory) "
     "where the device offers them",
     "host/vulkan/vk_context.cpp"},
    {Knob::VkForceStaging, "MASQ_VK_FORCE_STAGING", KnobType::Flag, "0|1", 0, 0, "0",
     "1: place every Vulkan buffer as on a discrete GPU without resizable BAR (only the staging buffer mapped)",
     "host/vulkan/vk_buffer.cpp"},
    {Knob::VkWaitSeconds, "MASQ_VK_WAIT_SECONDS", KnobType::Integer, nullptr, 1, kNoKnobMax,
     "600 (kDefaultWaitSeconds)",
     "Lowers the seconds one Vulkan submission may run before it is an error and its device is given up",
     "host/vulkan/vk_context.cpp"},
    {Knob::CacheDir, "MASQ_CACHE_DIR", KnobType::Path, nullptr, 0, 0, "$XDG_CACHE_HOME/masq, else $HOME/.cache/masq",
     "Where the Vulkan pipeline cache is kept; set and empty: not kept", "host/vulkan/vk_pipeline_cache.cpp"},
    {Knob::VkMaxBindingBytes, "MASQ_VK_MAX_BINDING_BYTES", KnobType::Integer, nullptr, 1, kNoKnobMax,
     "maxStorageBufferRange",
     "Lowers the bytes of one storage binding (vulkan, rayquery): arrays above it are read by address, "
     "rays traced in chunks that fit it (keep it at 48 or more)",
     "host/vulkan/vk_context.cpp"},
    {Knob::VkMaxAllocationBytes, "MASQ_VK_MAX_ALLOCATION_BYTES", KnobType::Integer, nullptr, 1, kNoKnobMax,
     "maxMemoryAllocationSize, maxBufferSize",
     "Lowers the bytes of one Vulkan buffer (vulkan, rayquery); an array above it is an error naming it",
     "host/vulkan/vk_context.cpp"},
    {Knob::VkMaxAllocations, "MASQ_VK_MAX_ALLOCATIONS", KnobType::Integer, nullptr, 1, kNoKnobMax,
     "maxMemoryAllocationCount",
     "Lowers the device memory allocations a Vulkan device holds at once; one more is an error naming the limit",
     "host/vulkan/vk_context.cpp"},
    {Knob::VkStagingBytes, "MASQ_VK_STAGING_BYTES", KnobType::Integer, nullptr, 1, kNoKnobMax, "67108864 (64 MiB)",
     "Lowers the size of the Vulkan staging buffer (larger copies go in pieces)", "host/vulkan/vk_staging.cpp"},
    {Knob::RqMaxInstances, "MASQ_RQ_MAX_INSTANCES", KnobType::Integer, nullptr, 1, kNoKnobMax, "maxInstanceCount",
     "Lowers the instances of one TLAS (rayquery, rtpipeline): above it the scene is split",
     "host/vulkan/driver_scene.cpp"},
    {Knob::RqMaxPrimitives, "MASQ_RQ_MAX_PRIMITIVES", KnobType::Integer, nullptr, 1, kNoKnobMax, "maxPrimitiveCount",
     "Lowers the primitives of one BLAS (rayquery, rtpipeline): above it the geometry is split",
     "host/vulkan/driver_scene.cpp"},
    {Knob::RtMaxGroupStride, "MASQ_RT_MAX_GROUP_STRIDE", KnobType::Integer, nullptr, 1, kNoKnobMax,
     "maxShaderGroupStride",
     "Lowers the bytes of one binding-table record (rtpipeline); no driver reports a limit masq's records exceed, "
     "so tests set it to reach the error",
     "host/vulkan/rt_pipeline.cpp"},
    {Knob::ClMaxAllocBytes, "MASQ_CL_MAX_ALLOC_BYTES", KnobType::Integer, nullptr, 1, kNoKnobMax,
     "CL_DEVICE_MAX_MEM_ALLOC_SIZE", "Lowers the bytes of one OpenCL buffer", "host/opencl/cl_runtime.h"},
    {Knob::VkFaultDeviceLost, "MASQ_VK_FAULT_DEVICE_LOST", KnobType::Flag, "0|1", 0, 0, "0",
     "Fault injection for tests: 1 makes every finished Vulkan submission report VK_ERROR_DEVICE_LOST",
     "host/vulkan/vk_context.cpp"},
    {Knob::VkFaultTimeout, "MASQ_VK_FAULT_TIMEOUT", KnobType::Flag, "0|1", 0, 0, "0",
     "Fault injection for tests: 1 makes every finished Vulkan submission report a timeout (a hung device)",
     "host/vulkan/vk_context.cpp"},
    {Knob::VkHideExtensions, "MASQ_VK_HIDE_EXTENSIONS", KnobType::List, nullptr, 0, 0, "none",
     "Fault injection for tests: Vulkan device extensions that look absent (ext1,ext2)",
     "host/vulkan/vk_devices.cpp"},
    {Knob::TestBackends, "MASQ_TEST_BACKENDS", KnobType::List, nullptr, 0, 0, "every backend",
     "The backends the tests that cover every backend run (cpu,vulkan)", "tests/test_env.h"},
    {Knob::AllowMissingBackends, "MASQ_ALLOW_MISSING_BACKENDS", KnobType::Flag, "0|1", 0, 0, "0",
     "1: a backend this machine cannot open is skipped by the tests, not a failure", "tests/test_env.h"},
    {Knob::DataDir, "MASQ_DATA_DIR", KnobType::Path, nullptr, 0, 0, "../shared/data beside the checkout",
     "The real scenes of the Python tests (ctest sets it to the build's data directory)",
     "python/tests/conftest.py"},
};
// clang-format on

inline constexpr bool knob_rows_in_order() {
  for (std::size_t i = 0; i < std::size(knob_rows); ++i)
    if (static_cast<std::size_t>(knob_rows[i].knob) != i) return false;
  return true;
}
static_assert(knob_rows_in_order(), "knob_rows: one row per Knob, in the enum's order");
static_assert(std::size(knob_rows) == static_cast<std::size_t>(Knob::DataDir) + 1,
              "knob_rows: one row per Knob (the last enumerator is DataDir)");

constexpr const KnobRow& knob_row(Knob k) { return knob_rows[static_cast<std::size_t>(k)]; }
constexpr const char* knob_name(Knob k) { return knob_row(k).name; }

/// The variable's text; nullopt when unset (set and empty is "").
std::optional<std::string> knob_text(Knob k);

/// An Integer knob's value; nullopt when unset or empty. Throws masq::Error
/// "<owner>: <NAME>='<value>' is not <what is expected>" (no "<owner>: " when owner is
/// empty) for any other text.
std::optional<std::uint64_t> knob_integer(Knob k, std::string_view owner = {});

/// A Choice or Flag knob's value: one of the row's choices, or its default when unset or
/// empty. Throws as knob_integer for any other text.
std::string_view knob_choice(Knob k, std::string_view owner = {});

/// A Flag knob: true for 1, false for 0, unset or empty (throws as knob_choice).
bool knob_flag(Knob k, std::string_view owner = {});

/// What the row accepts, as errors say it: "a positive integer", "an integer from 0 to
/// 1000000", "'on' or 'off'", "a path".
std::string knob_expected(const KnobRow& row);

/// "" when the variable is unset or valid, else the error its readers would throw.
std::string knob_problem(Knob k);

/// The environment variables masq reads but does not own (HOME, XDG_CACHE_HOME: where a
/// knob's default lies); nullopt when unset.
std::optional<std::string> system_env(const char* name);

} // namespace masq
