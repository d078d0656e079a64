// The binned SAH's node step, shared by its builds (bvh/binary/binned_sah.cpp): a range
// of references bounded, binned and given its best bin plane, whether it splits under a
// traversal cost, and its partition. Internal to bvh/binary.
#pragma once
#include "bvh/binary/binned_sah.h"
#include <bit>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace masq::sah_node {

// A range this long is bounded and binned in chunks of this many primitives, the
// chunks possibly at once. The chunks' results are merged in chunk order: vmin/vmax
// below keep the earlier of equal values (+0 and -0 alike), so that merge gives the same
// bits as one pass over the range, whatever the chunking.
constexpr int kChunk = 16384;

struct Split {
  int axis = -1;
  int bin = 0; // primitives in bins [0, bin] go left
  double cost = std::numeric_limits<double>::infinity();
};

// What every node of one build reads: the options. The primitives are references that
// carry their box (Ref below) and are partitioned themselves, so that a node reads its
// range in order; reading the boxes through an index array instead (an earlier build)
// fetched each one from wherever the primitive's index pointed, at every level.
struct Input {
  const SahOptions& opt;
  // log2 of opt.leaf_block when it is a power of two (1 and sah4's 4), else -1: the
  // block count is then a shift, not an integer division at every bin of every node.
  int block_shift = -1;
};

int block_shift_of(int leaf_block);

// The leaf blocks of n primitives: ceil(n / leaf_block).
inline double blocks(int n, const Input& in) {
  const int b = in.opt.leaf_block;
  return double(in.block_shift >= 0 ? (n + b - 1) >> in.block_shift : (n + b - 1) / b);
}

// GCC/Clang vector extensions: one AVX register of eight floats (a box), a half of it
// (a centroid), four 32-bit integers (a centroid's bins) and four doubles (a box's
// extents, for its area).
typedef float F8 __attribute__((vector_size(32)));
typedef float F4 __attribute__((vector_size(16)));
typedef std::int32_t I4 __attribute__((vector_size(16)));
typedef std::int32_t I8 __attribute__((vector_size(32)));
typedef double D4 __attribute__((vector_size(32)));
// max lane by lane, keeping the first of equal values (+0 and -0 alike), whatever the
// instruction's own rule: max(a, b) = a < b ? b : a.
inline F8 vmax(F8 a, F8 b) { return a < b ? b : a; }
inline F4 vmax(F4 a, F4 b) { return a < b ? b : a; }
inline F4 vmin(F4 a, F4 b) { return b < a ? b : a; }
constexpr float kInf = std::numeric_limits<float>::infinity();
// Lanes 3 and 7 of a reference's box carry its id and bins as bits (Ref): zeroed before
// any arithmetic, which their bit patterns (denormal floats) would slow.
inline F8 coordinates_of(F8 v) {
  const I8 keep = {-1, -1, -1, 0, -1, -1, -1, 0};
  return std::bit_cast<F8>(std::bit_cast<I8>(v) & keep);
}
inline F4 lower_half(F8 v) { return __builtin_shufflevector(v, v, 0, 1, 2, 3); }
inline F4 upper_half(F8 v) { return __builtin_shufflevector(v, v, 4, 5, 6, 7); }

// A box in fp32 as one register: lanes 0-2 its lower corner negated, lanes 4-6 its upper
// corner (lanes 3 and 7 spare), so that two boxes unite in one max. Embree's builders
// bin fp32 boxes too. A reference is then 32 bytes (the partitions move it) and a bin
// grows by one max; until the thirty-second round the corners were doubles: 64 bytes,
// two min and two max (docs/builders.md, "The binned SAH in fp32"). Every reference's
// box is its primitive's rounded outward to fp32 (references_of), so every node's box
// still holds its primitives.
struct Box {
  F8 v = {-kInf, -kInf, -kInf, -kInf, -kInf, -kInf, -kInf, -kInf};
  void grow(const Box& b) { v = vmax(v, b.v); }
  Aabb aabb() const {
    return {{-double(v[0]), -double(v[1]), -double(v[2])}, {double(v[4]), double(v[5]), double(v[6])}};
  }
  // Aabb::area of the box in double (references_of takes only boxes with lo <= hi, so a
  // union of references is one).
  double area_of_nonempty() const {
    const F8 c = coordinates_of(v);
    const D4 e = __builtin_convertvector(upper_half(c), D4) + __builtin_convertvector(lower_half(c), D4);
    return 2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
  }
};

// The centroids' bounds, in the doubled units of Ref::centre2.
struct CentroidBox {
  F4 lo = {kInf, kInf, kInf, kInf};
  F4 hi = {-kInf, -kInf, -kInf, -kInf};
  void grow(F4 c) {
    lo = vmin(lo, c);
    hi = vmax(hi, c);
  }
  void grow(const CentroidBox& b) {
    lo = vmin(lo, b.lo);
    hi = vmax(hi, b.hi);
  }
  bool binned(int axis) const { return hi[axis] - lo[axis] > 0.0f; } // a positive extent
};

// A primitive: its box, with its id's bits in lane 3 and in lane 7 its bin on each axis
// at the node being split (one byte an axis, written by bin_range, read by the partition
// that follows instead of binning again). The centroid is computed where it is needed.
struct Ref {
  Box box;
  // Twice the centroid (lo + hi; lane 3 zero): the binning's units, one subtraction.
  F4 centre2() const {
    const F8 c = coordinates_of(box.v);
    return upper_half(c) - lower_half(c);
  }
  int id() const { return std::bit_cast<std::int32_t>(box.v[3]); }
  int bin(int axis) const { return int(std::bit_cast<std::uint32_t>(box.v[7]) >> (8 * axis)) & 0xFF; }
  void set_bins(std::uint32_t packed) { box.v[7] = std::bit_cast<float>(packed); }
};

// Per axis nb bins: box and primitive count of the centroids that fall in each; and the
// sweep's occupied bins, suffix areas and counts. Kept by a thread from node to node (no
// allocation per node), and empty between nodes: find_split empties the bins it used,
// since clearing all 3 nb of them at each of a build's ~2n nodes cost more than the
// small nodes' binning itself.
struct Bins {
  std::vector<Box> box;
  std::vector<int> count;
  std::vector<int> used;
  std::vector<double> right_area;
  std::vector<int> right_count;
  explicit Bins(int nb)
      : box(3 * std::size_t(nb)), count(3 * std::size_t(nb), 0), used(nb), right_area(nb), right_count(nb) {}
  int count_per_axis() const { return int(used.size()); }
  void merge(const Bins& o) {
    for (std::size_t i = 0; i < box.size(); ++i) {
      box[i].grow(o.box[i]);
      count[i] += o.count[i];
    }
  }
};

// This thread's bins of nb per axis, kept from call to call (empty between nodes, as
// every build leaves them): auto builds thousands of small cluster BLAS, and fresh bins
// are five vectors a call (callgrind: 26,000 of the 345,000 allocations of three cluster
// builds of Ratboy).
Bins& thread_bins(int nb);

// A node's best bin plane and what decides between splitting there and a leaf.
struct NodeChoice {
  Aabb box;
  int count = 0;
  Split s;            // s.axis < 0: no bin plane (one primitive, or coincident centroids)
  double area = 0;    // the node box's
  double leaf_cost = 0;
};

// Whether a range of count primitives is a leaf whatever its best bin plane: it fits a
// leaf, and the leaf's price C_i b(n) is at most the traversal step C_t, below which no
// split's price goes (splits(): C_t plus the children's part, which is never negative).
// Under sah4 (blocks of four, C_t = C_i = 1) that is every range of at most four: half of
// a tree's nodes, whose binning and plane search decided nothing.
inline bool leaf_whatever_plane(const Input& in, int count, double traversal_cost) {
  const SahOptions& opt = in.opt;
  return count <= opt.max_leaf_size && opt.intersection_cost >= 0.0 &&
         opt.intersection_cost * blocks(count, in) <= traversal_cost;
}

// The box of references [first, first + count) of order and their best bin plane (bins:
// this thread's, left empty again).
// plane: false for a range that is a leaf whatever its plane (leaf_whatever_plane), which
// takes its box alone: no centroid box, no bins, no plane (splits() then makes a leaf).
NodeChoice choose_split(const Input& in, HugePageVector<Ref>& order, int first, int count, Bins& bins,
                        bool plane);

// Whether the node splits under traversal cost C_t. SAH in units of this node's area:
// leaf = C_i * b(n), split = C_t + C_i * (A_l b(n_l) + A_r b(n_r)) / A, b(n) the leaf's
// blocks (n itself with the default block of 1). A bin plane is taken when it is cheaper
// or the node is over max_leaf_size; without one, such a node splits by count.
inline bool splits(const Input& in, const NodeChoice& c, double traversal_cost) {
  if (c.count <= 1) return false;
  const SahOptions& opt = in.opt;
  if (c.count > opt.max_leaf_size) return true;
  if (c.s.axis < 0) return false;
  double split_cost = c.area > 0.0 ? traversal_cost + opt.intersection_cost * c.s.cost / c.area : c.leaf_cost;
  return split_cost < c.leaf_cost;
}

// Splits the node's range at its bin plane (or, without one, by count); returns the
// first index that goes right.
int partition_node(HugePageVector<Ref>& order, int first, const NodeChoice& c);

// The checked options, and the boxes as references (ids in order).
HugePageVector<Ref> references_of(std::span<const Aabb> boxes, const SahOptions& opt);

} // namespace masq::sah_node
