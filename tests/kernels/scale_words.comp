// GLSL half of SyncBarriers in tests/test_vk_memory_placement.cpp: a shader that reads
// one buffer and writes another, between a staged upload and a staged readback recorded
// in one command buffer. A test kernel, not shipped.
#version 460
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer InBuf { uint words_in[]; };
layout(std430, binding = 1) writeonly buffer OutBuf { uint words_out[]; };
layout(push_constant) uniform Params {
  uint count;
};

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < count) words_out[i] = words_in[i] * 3u + 1u;
}
