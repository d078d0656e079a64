#include "bvh/binary/binned_sah_node.h"
#include "bvh/binary/parallel.h"
#include "bvh/binary/partition_in_chunks.h"
#include "masq/error.h"
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

namespace masq::sah_node {

int block_shift_of(int leaf_block) {
  for (int s = 0; s < 31; ++s)
    if (leaf_block == 1 << s) return s;
  return -1;
}

Bins& thread_bins(int nb) {
  thread_local std::unique_ptr<Bins> bins;
  if (!bins || bins->count_per_axis() != nb) bins = std::make_unique<Bins>(nb);
  return *bins;
}

namespace {

// The centroid bounds' origin and bins per unit, for a primitive's bin on an axis:
// min(nb - 1, int((centre2 - lo) * nb / ext)). An axis that is not binned gets scale 0
// (its bins are never read); a scale beyond fp32 is its largest value (the products it
// gives are clamped to the bins after).
struct BinFrame {
  F4 lo;
  F4 scale;
};
BinFrame bin_frame(const CentroidBox& cbox, int nb) {
  BinFrame f{cbox.lo, F4{}};
  for (int k = 0; k < 3; ++k)
    if (cbox.binned(k))
      f.scale[k] = float(std::min(double(nb) / (double(cbox.hi[k]) - double(cbox.lo[k])),
                                  double(std::numeric_limits<float>::max())));
    else
      f.lo[k] = 0.0f;
  f.lo[3] = 0.0f;
  return f;
}

// Calls body(lo, hi, chunk) on the chunks of [first, first + count), possibly at once;
// the caller merges the chunk results in chunk order.
template <class Body>
void for_chunks(int first, int count, Body body) {
  int chunks = (count + kChunk - 1) / kChunk;
  parallel_chunks(std::size_t(chunks), 1, [&](std::size_t c0, std::size_t c1) {
    for (std::size_t c = c0; c < c1; ++c) {
      int lo = first + int(c) * kChunk;
      body(lo, std::min(first + count, lo + kChunk), int(c));
    }
  });
}

void bounds_of(const HugePageVector<Ref>& order, int first, int count, Box& box, CentroidBox& cbox) {
  auto pass = [&](int lo, int hi, Box& b, CentroidBox& c) {
    for (int i = lo; i < hi; ++i) {
      const Ref& r = order[std::size_t(i)];
      b.grow(r.box);
      c.grow(r.centre2());
    }
  };
  if (count < 2 * kChunk) return pass(first, first + count, box, cbox);
  std::vector<Box> b((count + kChunk - 1) / kChunk);
  std::vector<CentroidBox> c(b.size());
  for_chunks(first, count, [&](int lo, int hi, int k) { pass(lo, hi, b[k], c[k]); });
  for (std::size_t k = 0; k < b.size(); ++k) {
    box.grow(b[k]);
    cbox.grow(c[k]);
  }
}

// Fills bins with the range's primitives, every axis whose centroid extent is positive
// in one pass over them (each bin grows in primitive order, as three passes would). The
// three axes' bin indices are one vector multiply and conversion; they are kept in the
// reference for the partition.
void bin_range(const Input& in, HugePageVector<Ref>& order, int first, int count, const CentroidBox& cbox,
               Bins& bins) {
  const int nb = in.opt.bins;
  int axes[3], n_axes = 0;
  for (int axis = 0; axis < 3; ++axis)
    if (cbox.binned(axis)) axes[n_axes++] = axis;
  const BinFrame f = bin_frame(cbox, nb);
  const F4 nbv = {float(nb), float(nb), float(nb), float(nb)};
  const I4 last_bin = {nb - 1, nb - 1, nb - 1, nb - 1};
  // In runs of kBinRun references: first every reference's bins, then the bins' boxes
  // grown, so that a bin's address does not wait on its own reference's arithmetic.
  constexpr int kBinRun = 16;
  auto pass = [&](int lo_i, int hi_i, Bins& out) {
    I4 k[kBinRun];
    for (int i0 = lo_i; i0 < hi_i; i0 += kBinRun) {
      const int n = std::min(kBinRun, hi_i - i0);
      // Clamped to [0, nb] first, so that every lane converts within range; then each
      // lane's bin at most nb - 1.
      for (int j = 0; j < n; ++j) {
        F4 at = (order[std::size_t(i0 + j)].centre2() - f.lo) * f.scale;
        at = at > 0.0f ? at : F4{}; // (a NaN lane too)
        at = at < nbv ? at : nbv;
        k[j] = __builtin_convertvector(at, I4);
        k[j] = k[j] < last_bin ? k[j] : last_bin;
      }
      if (n_axes == 3) {
        for (int j = 0; j < n; ++j) {
          Ref& r = order[std::size_t(i0 + j)];
          const I4 b = k[j];
          out.box[std::size_t(b[0])].grow(r.box);
          out.box[std::size_t(nb + b[1])].grow(r.box);
          out.box[std::size_t(2 * nb + b[2])].grow(r.box);
          ++out.count[std::size_t(b[0])];
          ++out.count[std::size_t(nb + b[1])];
          ++out.count[std::size_t(2 * nb + b[2])];
          r.set_bins(std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16);
        }
        continue;
      }
      for (int j = 0; j < n; ++j) {
        Ref& r = order[std::size_t(i0 + j)];
        std::uint32_t packed = 0;
        for (int a = 0; a < n_axes; ++a) {
          int axis = axes[a];
          int bin = k[j][axis];
          packed |= std::uint32_t(bin) << (8 * axis);
          std::size_t at = std::size_t(axis * nb + bin);
          out.box[at].grow(r.box);
          ++out.count[at];
        }
        r.set_bins(packed);
      }
    }
  };
  if (count < 2 * kChunk) return pass(first, first + count, bins);
  std::vector<Bins> part((count + kChunk - 1) / kChunk, Bins(nb));
  for_chunks(first, count, [&](int lo, int hi, int k) { pass(lo, hi, part[k]); });
  for (const Bins& p : part) bins.merge(p);
}

// The best bin plane of the binned axes, and the bins emptied again. Only occupied bins
// are visited: a plane after an empty bin has the cost of the plane before it (the same
// two sides) and never wins the strict comparison, so the split is the one a sweep over
// every bin finds, bit for bit (growing by an empty box changes no bit).
Split find_split(const Input& in, Bins& bins, const CentroidBox& cbox) {
  Split best;
  const int nb = in.opt.bins;
  double* right_area = bins.right_area.data();
  int* right_count = bins.right_count.data();
  int* used = bins.used.data();
  for (int axis = 0; axis < 3; ++axis) {
    if (!cbox.binned(axis)) continue;
    Box* bin_box = &bins.box[std::size_t(axis * nb)];
    int* bin_count = &bins.count[std::size_t(axis * nb)];
    int m = 0;
    for (int k = 0; k < nb; ++k) {
      used[m] = k;
      m += bin_count[k] != 0 ? 1 : 0;
    }
    // right_area[j], right_count[j]: the bins used[j..m-1].
    Box acc;
    int n = 0;
    for (int j = m - 1; j > 0; --j) {
      acc.grow(bin_box[used[j]]);
      n += bin_count[used[j]];
      right_area[j] = acc.area_of_nonempty();
      right_count[j] = n;
    }
    acc = Box{};
    n = 0;
    for (int j = 0; j + 1 < m; ++j) {
      acc.grow(bin_box[used[j]]);
      n += bin_count[used[j]];
      double cost = acc.area_of_nonempty() * blocks(n, in) + right_area[j + 1] * blocks(right_count[j + 1], in);
      if (cost < best.cost) best = {axis, used[j], cost};
    }
    for (int j = 0; j < m; ++j) {
      bin_box[used[j]] = Box{};
      bin_count[used[j]] = 0;
    }
  }
  return best;
}

} // namespace

// plane: false for a range that is a leaf whatever its plane (leaf_whatever_plane), which
// takes its box alone: no centroid box, no bins, no plane (splits() then makes a leaf).
NodeChoice choose_split(const Input& in, HugePageVector<Ref>& order, int first, int count, Bins& bins,
                        bool plane) {
  NodeChoice c;
  c.count = count;
  if (!plane) {
    Box box;
    for (int i = first; i < first + count; ++i) box.grow(order[std::size_t(i)].box);
    c.box = box.aabb();
    return c;
  }
  Box box;
  CentroidBox cbox;
  bounds_of(order, first, count, box, cbox);
  c.box = box.aabb();
  if (count <= 1) return c;
  bin_range(in, order, first, count, cbox, bins);
  c.s = find_split(in, bins, cbox);
  c.area = c.box.area();
  c.leaf_cost = in.opt.intersection_cost * blocks(count, in);
  return c;
}

// Splits the node's range at its bin plane (or, without one, by count); returns the
// first index that goes right.
int partition_node(HugePageVector<Ref>& order, int first, const NodeChoice& c) {
  const int count = c.count;
  if (c.s.axis < 0) return first + count / 2; // coincident centroids: no plane separates them
  const int axis = c.s.axis, bin = c.s.bin;
  auto goes_left = [&](const Ref& p) { return p.bin(axis) <= bin; };
  // std::partition's own (unstable) order decides the leaf order: a long range gets the
  // same order from partition_in_chunks.
  if (count < 2 * kChunk) {
    auto begin = order.begin() + first;
    return int(std::partition(begin, begin + count, goes_left) - order.begin());
  }
  return partition_in_chunks(order, first, count, kChunk, goes_left);
}

// The checked options, and the boxes as references (ids in order).
HugePageVector<Ref> references_of(std::span<const Aabb> boxes, const SahOptions& opt) {
  if (opt.leaf_block < 1) throw Error("bvh: SAH leaf block " + std::to_string(opt.leaf_block) + " (must be >= 1)");
  // A reference keeps its bin on each axis in a byte (Ref::bin).
  if (opt.bins < 1 || opt.bins > 256) throw Error("bvh: SAH bins " + std::to_string(opt.bins) + " (must be 1-256)");
  const int n = int(boxes.size());
  // A NaN or empty box would give a NaN centroid and an out-of-range bin below. The
  // corners stay within a quarter of fp32's range, so that a doubled centroid
  // (Ref::centre2) and the centroids' extent are finite.
  constexpr double kMax = double(std::numeric_limits<float>::max()) / 4;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      if (!(boxes[i].lo[k] <= boxes[i].hi[k]) || !(std::abs(boxes[i].lo[k]) <= kMax) ||
          !(std::abs(boxes[i].hi[k]) <= kMax))
        throw Error("bvh: box " + std::to_string(i) + " of " + std::to_string(n) +
                    " is empty, or not finite within a quarter of fp32's range");
  // Each corner rounded outward to fp32 (bvh/bounds/aabb.h), so that the box holds the
  // primitive's.
  HugePageVector<Ref> refs(boxes.size());
  parallel_chunks(boxes.size(), 8192, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      const Aabb& b = boxes[i];
      const F4 down = round_down_lanes(D4{b.lo.x, b.lo.y, b.lo.z, 0.0});
      const F4 up = -round_down_lanes(D4{-b.hi.x, -b.hi.y, -b.hi.z, 0.0}); // round_up, lane by lane
      refs[i].box.v = F8{-down[0], -down[1], -down[2], std::bit_cast<float>(std::int32_t(i)), up[0], up[1], up[2], 0.0f};
    }
  });
  return refs;
}

} // namespace masq::sah_node
