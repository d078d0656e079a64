// The binned SAH's node step, shared by its builds (bvh/binary/binned_sah.cpp): a range
// of references bounded, binned and given its best bin plane, whether it splits under a
// traversal cost, and its partition. Internal to bvh/binary.
#pragma once
#include "bvh/binary/binned_sah.h"
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace masq::sah_node {

// A range this long is bounded and binned in chunks of this many primitives, the
// chunks possibly at once. The chunks' results are merged in chunk order: glm::min/max
// keep the earlier of equal values (+0 and -0 alike), so that merge gives the same bits
// as one pass over the range, whatever the chunking.
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

// Four doubles with the GCC/Clang vector extensions (one AVX register where the build
// machine has AVX, else two SSE ones): a box corner's x, y, z and a spare lane, so that
// a box grows by two vector min/max instead of six scalar ones.
typedef double D4 __attribute__((vector_size(32)));
typedef std::int32_t I4 __attribute__((vector_size(16)));
// glm::min and glm::max lane by lane, the same bits: min(a, b) = b < a ? b : a.
inline D4 vmin(D4 a, D4 b) { return b < a ? b : a; }
inline D4 vmax(D4 a, D4 b) { return a < b ? b : a; }
constexpr double kInf = std::numeric_limits<double>::infinity();

// A box as two corners in lanes 0-2 (lane 3 is spare and never read as a coordinate).
struct Box4 {
  D4 lo = {kInf, kInf, kInf, kInf};
  D4 hi = {-kInf, -kInf, -kInf, -kInf};
  void grow(const Box4& b) {
    lo = vmin(lo, b.lo);
    hi = vmax(hi, b.hi);
  }
  void grow(D4 p) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  Aabb aabb() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
  // Aabb::area of a box that is not empty, the same operations (references_of takes
  // only boxes with lo <= hi, so a union of references is one: Aabb::area's emptiness
  // test would always pass).
  double area_of_nonempty() const {
    D4 e = hi - lo;
    return 2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
  }
};

// A primitive: its box, with its id in lo's spare lane (exact: ids are below 2^31) and
// in hi's its bin on each axis at the node being split (one byte an axis, written by
// bin_range, read by the partition that follows instead of dividing again). The
// centroid is computed where it is needed, as Aabb::center computes it (the same bits),
// which keeps a reference at 64 bytes for the partitions that move it.
struct Ref {
  Box4 box;
  D4 center() const { return 0.5 * (box.lo + box.hi); }
  int id() const { return int(box.lo[3]); }
  int bin(int axis) const { return int(std::int64_t(box.hi[3]) >> (8 * axis)) & 0xFF; }
};

// Per axis nb bins: box and primitive count of the centroids that fall in each; and the
// sweep's occupied bins, suffix areas and counts. Kept by a thread from node to node (no
// allocation per node), and empty between nodes: find_split empties the bins it used,
// since clearing all 3 nb of them at each of a build's ~2n nodes cost more than the
// small nodes' binning itself.
struct Bins {
  std::vector<Box4> box;
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
