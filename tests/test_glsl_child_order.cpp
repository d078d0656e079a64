// The Vulkan kernels order a node's hit children by a sorting network, OpenCL by an
// insertion sort and the cpu by bitmasks in the insertion sort's order
// (kernels/child_order.h). Every backend must visit the same
// nodes in the same order, so the network must give the insertion sort's order: entry
// distance, ties in slot order. tests/kernels/child_order_check.comp runs the GLSL
// order_children on entry distances with many ties; the C++ insertion sort
// (order_children_loop) is the reference.
// Vulkan missing fails the test unless MASQ_ALLOW_MISSING_BACKENDS=1.
#include "host/backend.h"
#include "host/vulkan/vk_pipeline.h"
#include "kernels/child_order.h"
#include "spirv/child_order_check_comp_spv.h"
#include "tests/test_env.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace masq;
using masq::kernel::v_default::ChildOrder;
using masq::kernel::v_default::WideHits;

constexpr int kWidth8 = 8;

TEST(GlslChildOrder, NetworkGivesTheInsertionSortsOrder) {
  std::shared_ptr<vk::Context> ctx;
  try {
    ctx = vk::Context::get("vulkan");
  } catch (const BackendUnavailable& e) {
    if (masq::test::missing_backends_allowed()) GTEST_SKIP() << e.what() << " (MASQ_ALLOW_MISSING_BACKENDS=1)";
    FAIL() << e.what() << " (scripts/setup.sh installs lavapipe; MASQ_ALLOW_MISSING_BACKENDS=1 skips)";
  }
  const float inf = std::numeric_limits<float>::infinity();
  const int cases = 20000;
  // Few distinct distances (and -0 against +0), so ties are common; inf is a missed slot.
  const float values[] = {0.5f, 1.0f, 1.0f, 2.0f, -0.0f, 0.0f, -1.5f, inf};
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pick(0, 7);
  std::vector<float> tnear(std::size_t(cases) * kWidth8);
  for (float& t : tnear) t = values[pick(rng)];

  std::vector<VkDescriptorType> types(2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  vk::KernelLayout layout(*ctx, types, 2 * sizeof(std::int32_t));
  vk::Buffer in_buf(*ctx, tnear.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  in_buf.upload(tnear.data(), tnear.size() * 4);
  vk::Buffer out_buf(*ctx, std::size_t(cases) * (kWidth8 + 1) * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  layout.bind_buffer(0, in_buf);
  layout.bind_buffer(1, out_buf);
  vk::DeviceOwned<VkPipeline> pipeline = layout.create_pipeline(child_order_check_comp_spv, {});

  int ties = 0, visits = 0;
  for (int width : {4, 8}) {
    const std::int32_t push[2] = {cases, width};
    layout.dispatch(pipeline.get(), push, (cases + 63) / 64);
    std::vector<std::int32_t> got(std::size_t(cases) * (kWidth8 + 1));
    out_buf.download(got.data(), got.size() * 4);
    int bad = 0;
    for (int c = 0; c < cases; ++c) {
      WideHits wh{};
      for (int i = 0; i < kWidth8; ++i) wh.tnear[i] = tnear[std::size_t(c) * kWidth8 + i];
      ChildOrder want = masq::kernel::v_default::order_children_loop(wh, width);
      const std::int32_t* g = &got[std::size_t(c) * (kWidth8 + 1)];
      bool same = g[kWidth8] == want.n;
      for (int k = 0; same && k < want.n; ++k) same = g[k] == want.slot[k];
      if (!same && bad++ < 3) {
        std::string t, gs, ws;
        for (int i = 0; i < width; ++i) t += std::to_string(wh.tnear[i]) + " ";
        for (int k = 0; k < g[kWidth8] && k < kWidth8; ++k) gs += std::to_string(g[k]) + " ";
        for (int k = 0; k < want.n; ++k) ws += std::to_string(want.slot[k]) + " ";
        ADD_FAILURE() << "width " << width << " case " << c << " (tnear " << t << "): GLSL visits slots " << gs
                      << "| C++ visits " << ws;
      }
      for (int k = 0; k < want.n; ++k)
        for (int j = 0; j < k; ++j) ties += wh.tnear[want.slot[j]] == wh.tnear[want.slot[k]];
      visits += want.n;
    }
    EXPECT_EQ(bad, 0) << "width " << width << ": the GLSL child order differs from the C++ one";
  }
  EXPECT_GT(ties, visits / 10); // the stable order was tested, not only distinct keys
}

} // namespace
