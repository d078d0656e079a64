// The rtpipeline backend's ray-tracing pipeline (VK_KHR_ray_tracing_pipeline) and its
// shader binding table: the mechanism the masquerade paper ran on OptiX, where the
// driver's traversal calls the user's intersection program through the binding table.
// The stages are kernels/rtpipeline.* (kernels/rt_shared.h says what each does).
#pragma once
#include "host/kernel_variant.h"
#include "host/vulkan/rayquery_plan.h"
#include "host/vulkan/vk_pipeline.h"
#include "kernels/layout.h"
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace masq::vk {

// THE table of hit groups: one per primitive type, row i for MASQ_PRIM_* value i, with
// the variant switch of that type's intersector. Every procedural group's intersection
// stage is specialised with its own switch alone left as the scene has it, so it carries
// one intersector; the triangle group has no intersection stage (the driver's triangles)
// but an any-hit stage for robust mode.
struct HitGroupRow {
  int prim_type;                     // MASQ_PRIM_*
  std::int32_t KernelVariant::*have; // MASQ_HAVE_* of kernels/variant_table.h
  const char* name;
};
inline constexpr HitGroupRow kHitGroups[] = {
    {MASQ_PRIM_TRIANGLE, &KernelVariant::triangles, "triangle"},
    {MASQ_PRIM_CAPSULE, &KernelVariant::capsules, "capsule"},
    {MASQ_PRIM_ROUND_CONE, &KernelVariant::round_cones, "round cone"},
    {MASQ_PRIM_SPHERE, &KernelVariant::spheres, "sphere"},
    {MASQ_PRIM_CURVE, &KernelVariant::curves, "curve"},
    {MASQ_PRIM_RIBBON, &KernelVariant::ribbons, "ribbon"},
};
static_assert(std::size(kHitGroups) == MASQ_PRIM_TYPE_COUNT, "one hit group per primitive type");

// The stages that see the pipeline's bindings and push constants (its KernelLayout's).
inline constexpr VkShaderStageFlags kRtShaderStages =
    VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_MISS_BIT_KHR | VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR |
    VK_SHADER_STAGE_ANY_HIT_BIT_KHR | VK_SHADER_STAGE_INTERSECTION_BIT_KHR;

// Shader groups of the pipeline: ray generation, miss, then kHitGroups in order.
inline constexpr std::uint32_t kRaygenGroup = 0;
inline constexpr std::uint32_t kMissGroup = 1;
inline constexpr std::uint32_t kFirstHitGroup = 2;

class RtPipeline {
 public:
  // The pipeline of variant `v` (its switches as specialization constants of every
  // stage), scene arrays bound or read by address. Throws masq::Error naming `backend`
  // when the driver rejects it.
  RtPipeline(Context& ctx, KernelLayout& layout, const KernelVariant& v, bool addressed, const char* backend);
  RtPipeline(const RtPipeline&) = delete;
  RtPipeline& operator=(const RtPipeline&) = delete;

  VkPipeline handle() const { return pipeline_.get(); }
  // The opaque handle of shader group g (shaderGroupHandleSize bytes).
  std::span<const std::byte> group_handle(std::uint32_t g) const;

 private:
  Context& ctx_;
  DeviceOwned<VkPipeline> pipeline_;
  std::vector<std::byte> handles_;
};

// The shader binding table of one pipeline over one plan, in one buffer: the ray
// generation record, the miss record, and the hit records (rayquery_plan.h: one per
// BLAS with its primitive type's group, then one per primitive type for masquerade
// instances), each a group handle and the record's data (the BLAS id, -1 for
// masquerade), at the device's handle alignment; each region starts at
// shaderGroupBaseAlignment. Throws masq::Error naming `backend` when the table's stride
// exceeds maxShaderGroupStride or it needs more than one buffer holds.
class BindingTable {
 public:
  BindingTable(Context& ctx, const RtPipeline& pipeline, const RayQueryPlan& plan, const char* backend);
  VkStridedDeviceAddressRegionKHR raygen{}, miss{}, hit{}, callable{};
  std::size_t bytes() const { return buffer_.size(); }

 private:
  Buffer buffer_;
};

} // namespace masq::vk
