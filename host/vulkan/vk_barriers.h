// The memory barriers between masq's transfers, dispatches and acceleration-structure
// builds, in one place: Staging records the copy ones, KernelLayout::dispatch the
// dispatch one, the acceleration-structure batches (accel_batch.cpp) the build one.
// tests/test_vk_memory_placement.cpp records a staged upload, a dispatch and a staged
// readback in one command buffer with them under synchronization validation (which sees
// hazards inside a command buffer, not across waited submissions).
#pragma once
#include "host/vulkan/vk_context.h"

namespace masq::vk {

// Before a copy: earlier shader, acceleration-structure-build and transfer writes are
// visible to it, and earlier reads of its destination have finished.
void barrier_before_copy(const Context& ctx, VkCommandBuffer cmd);
// After a copy into device memory: its writes are visible to compute shaders (storage and
// uniform reads), acceleration-structure builds (inputs are read as SHADER_READ in the
// build stage; ray-query contexts only) and later copies.
void barrier_after_upload(const Context& ctx, VkCommandBuffer cmd);
// After a copy into the staging buffer: its writes are visible to the host; later writes
// to the source (the next dispatch's hits) wait for its reads.
void barrier_after_readback(const Context& ctx, VkCommandBuffer cmd);
// After a dispatch: its shader writes are visible to the host (mapped results), to copies
// (staged readback; the next chunk's ray upload waits for its reads) and to the next
// dispatch, which writes the same hits.
void barrier_after_dispatch(VkCommandBuffer cmd);
// After a vkCmdTraceRaysKHR (rtpipeline): its shader writes are visible to the host, to
// copies and to the next trace (the next TLAS part reads the hits of the last).
void barrier_after_trace_rays(VkCommandBuffer cmd);
// After a vkCmdFillBuffer of counters the ray-tracing shaders then add to.
void barrier_after_fill(VkCommandBuffer cmd);
// After acceleration-structure builds or copies: their writes are visible to what reads
// the structures next (a compacted-size query or compacting copy, a TLAS build over a
// BLAS, ray queries in compute shaders, traceRayEXT in ray-tracing shaders).
void barrier_after_accel_build(const Context& ctx, VkCommandBuffer cmd);

} // namespace masq::vk
