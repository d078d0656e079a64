// Conservative 8-bit quantisation of child boxes for the q8 node format
// (kernels/layout.h QuantNode8, after Ylitie, Karras and Laine 2017).
// A node's frame is a float origin and, per axis, a power-of-two step 2^(e-127); plane q
// decodes as origin + q * step in fp32. Since q has 8 bits and step is a power of two,
// q * step is exact, so the decode has one rounding (of the sum) whether or not the
// compiler contracts it to an fma. Every quantised plane is checked against that decode,
// and against the same value flushed to zero (devices that flush subnormals), so the
// decoded box always contains the true one.
#pragma once
#include "bvh/bounds/aabb.h"
#include "kernels/layout.h"
#include <array>
#include <cstdint>

namespace masq {

struct QuantFrame {
  std::array<float, 3> origin{};
  std::array<int, 3> biased_exp{}; // e + 127, 1..254: step 2^(biased - 127) is a normal float
};

// The frame of a node whose children lie in `box` (finite, non-empty): origin rounded
// down, the smallest step whose plane 255 decodes at or above box.hi.
QuantFrame quant_frame(const Aabb& box);

// The kernel's decode: origin + float(q) * 2^(biased_exp - 127) in fp32.
float quant_decode(float origin, int biased_exp, unsigned q);

struct QuantBox {
  std::array<std::uint8_t, 3> lo{}, hi{};
};

// Planes of `child` (inside the frame's box): lo rounded down, hi up, verified.
QuantBox quantize_box(const QuantFrame& f, const Aabb& child);

// Packs one node. slots: meta byte per slot (0 empty, MASQ_Q8_INNER, 1..127 leaf count).
kernel::QuantNode8 pack_quant_node(const QuantFrame& f, const std::array<QuantBox, 8>& boxes,
                                   const std::array<std::uint8_t, 8>& meta, std::int32_t child_base,
                                   std::int32_t ref_base);

} // namespace masq
