// GLSL half of tests/test_glsl_child_order.cpp: the Vulkan kernels' order_children
// (a sorting network) on given entry distances, to compare with the C++ one. A test
// kernel: compiled into test_glsl_child_order by tests/CMakeLists.txt (kernel headers
// through masq_add_spirv's -I kernels), not shipped.
#version 460
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "child_order.h"

layout(std430, binding = 0) readonly buffer TnearBuf { float tnear_in[]; };   // 8 per case
layout(std430, binding = 1) writeonly buffer OrderBuf { int order_out[]; };   // 9 per case: slots, n
layout(push_constant) uniform Params {
  int case_count;
  int width;
};

void main() {
  int c = int(gl_GlobalInvocationID.x);
  if (c >= case_count) return;
  WideHits wh;
  for (int i = 0; i < MASQ_WIDTH8; ++i) {
    wh.tnear[i] = tnear_in[c * MASQ_WIDTH8 + i];
    wh.tfar[i] = 0.0f;
    wh.child[i] = 0;
    wh.count[i] = 0;
  }
  ChildOrder co = order_children(wh, width);
  for (int i = 0; i < MASQ_WIDTH8; ++i) order_out[c * (MASQ_WIDTH8 + 1) + i] = co.slot[i];
  order_out[c * (MASQ_WIDTH8 + 1) + MASQ_WIDTH8] = co.n;
}
