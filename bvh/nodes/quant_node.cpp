#include "bvh/nodes/quant_node.h"
#include "masq/error.h"
#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <string>

namespace masq {

// The kernels read the node array as words at these offsets (kernels/node_formats.h).
static_assert(offsetof(kernel::QuantNode8, exps) == 4 * MASQ_Q8_EXPS);
static_assert(offsetof(kernel::QuantNode8, child_base) == 4 * MASQ_Q8_CHILD_BASE);
static_assert(offsetof(kernel::QuantNode8, ref_base) == 4 * MASQ_Q8_REF_BASE);
static_assert(offsetof(kernel::QuantNode8, meta) == 4 * MASQ_Q8_META);
static_assert(offsetof(kernel::QuantNode8, qlo_x) == 4 * MASQ_Q8_QLO_X);
static_assert(offsetof(kernel::QuantNode8, qhi_x) == 4 * MASQ_Q8_QHI_X);
static_assert(offsetof(kernel::QuantNode8, qlo_y) == 4 * MASQ_Q8_QLO_Y);
static_assert(offsetof(kernel::QuantNode8, qhi_y) == 4 * MASQ_Q8_QHI_Y);
static_assert(offsetof(kernel::QuantNode8, qlo_z) == 4 * MASQ_Q8_QLO_Z);
static_assert(offsetof(kernel::QuantNode8, qhi_z) == 4 * MASQ_Q8_QHI_Z);
static_assert(offsetof(kernel::WideNode8, hi_x) == 4 * MASQ_W8_HI_X);
static_assert(offsetof(kernel::WideNode8, lo_y) == 4 * MASQ_W8_LO_Y);
static_assert(offsetof(kernel::WideNode8, hi_y) == 4 * MASQ_W8_HI_Y);
static_assert(offsetof(kernel::WideNode8, lo_z) == 4 * MASQ_W8_LO_Z);
static_assert(offsetof(kernel::WideNode8, hi_z) == 4 * MASQ_W8_HI_Z);
static_assert(offsetof(kernel::WideNode8, child) == 4 * MASQ_W8_CHILD);
static_assert(offsetof(kernel::WideNode8, count) == 4 * MASQ_W8_COUNT);

namespace {

// What a device that flushes subnormal results to zero would compute instead.
float flushed(float x) { return std::fabs(x) < FLT_MIN ? std::copysign(0.0f, x) : x; }

// Both decodes (IEEE and flush-to-zero) lie at or below / at or above v.
bool below(float origin, int e, unsigned q, double v) {
  float d = quant_decode(origin, e, q);
  return double(d) <= v && double(flushed(d)) <= v;
}
bool above(float origin, int e, unsigned q, double v) {
  float d = quant_decode(origin, e, q);
  return double(d) >= v && double(flushed(d)) >= v;
}

} // namespace

float quant_decode(float origin, int biased_exp, unsigned q) {
  float step = std::bit_cast<float>(std::uint32_t(biased_exp) << 23);
  volatile float product = float(q) * step; // exact; volatile keeps the sum a separate rounding
  return origin + product;
}

QuantFrame quant_frame(const Aabb& box) {
  QuantFrame f;
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(box.lo[k]) || !std::isfinite(box.hi[k]) || !(box.lo[k] <= box.hi[k]))
      throw Error("q8 nodes: a node box is empty or not finite on axis " + std::to_string(k));
    float o = round_down(box.lo[k]);
    // A subnormal origin would decode to 0 on a flushing device: go to a normal bound below.
    if (std::fabs(o) < FLT_MIN) o = std::signbit(o) ? -FLT_MIN : 0.0f;
    f.origin[std::size_t(k)] = o;
    double extent = box.hi[k] - double(o);
    int e = 1;
    if (extent > 0) e = std::clamp(int(std::floor(std::log2(extent / 255.0))) + 127 - 1, 1, 254);
    while (e < 254 && !above(o, e, 255, box.hi[k])) ++e;
    if (!above(o, e, 255, box.hi[k]))
      throw Error("q8 nodes: no power-of-two step covers the node box on axis " + std::to_string(k));
    f.biased_exp[std::size_t(k)] = e;
  }
  return f;
}

QuantBox quantize_box(const QuantFrame& f, const Aabb& child) {
  QuantBox b;
  for (int k = 0; k < 3; ++k) {
    const float o = f.origin[std::size_t(k)];
    const int e = f.biased_exp[std::size_t(k)];
    const double step = std::ldexp(1.0, e - 127);
    double lo = std::floor((child.lo[k] - double(o)) / step);
    double hi = std::ceil((child.hi[k] - double(o)) / step);
    unsigned qlo = unsigned(std::clamp(lo, 0.0, 255.0));
    unsigned qhi = unsigned(std::clamp(hi, 0.0, 255.0));
    while (qlo > 0 && !below(o, e, qlo, child.lo[k])) --qlo;
    while (qhi < 255 && !above(o, e, qhi, child.hi[k])) ++qhi;
    if (!below(o, e, qlo, child.lo[k]) || !above(o, e, qhi, child.hi[k]))
      throw Error("q8 nodes: a child box is outside its node's quantisation frame on axis " + std::to_string(k));
    b.lo[std::size_t(k)] = std::uint8_t(qlo);
    b.hi[std::size_t(k)] = std::uint8_t(qhi);
  }
  return b;
}

kernel::QuantNode8 pack_quant_node(const QuantFrame& f, const std::array<QuantBox, 8>& boxes,
                                   const std::array<std::uint8_t, 8>& meta, std::int32_t child_base,
                                   std::int32_t ref_base) {
  kernel::QuantNode8 n{};
  for (int k = 0; k < 3; ++k) {
    n.origin[k] = f.origin[std::size_t(k)];
    n.exps |= std::uint32_t(f.biased_exp[std::size_t(k)]) << (8 * k);
  }
  n.child_base = child_base;
  n.ref_base = ref_base;
  auto put = [](std::uint32_t* words, int slot, std::uint8_t v) { words[slot / 4] |= std::uint32_t(v) << (8 * (slot % 4)); };
  for (int s = 0; s < 8; ++s) {
    put(n.meta, s, meta[std::size_t(s)]);
    put(n.qlo_x, s, boxes[std::size_t(s)].lo[0]);
    put(n.qhi_x, s, boxes[std::size_t(s)].hi[0]);
    put(n.qlo_y, s, boxes[std::size_t(s)].lo[1]);
    put(n.qhi_y, s, boxes[std::size_t(s)].hi[1]);
    put(n.qlo_z, s, boxes[std::size_t(s)].lo[2]);
    put(n.qhi_z, s, boxes[std::size_t(s)].hi[2]);
  }
  return n;
}

} // namespace masq
