#include "bvh/binary/binned_sah.h"
#include "bvh/binary/parallel.h"
#include "bvh/binary/partition_in_chunks.h"
#include "masq/error.h"
#include <algorithm>
#include <string>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>

namespace masq {

namespace {

// A range this long is bounded and binned in chunks of this many primitives, the
// chunks possibly at once. The chunks' results are merged in chunk order: glm::min/max
// keep the earlier of equal values (+0 and -0 alike), so that merge gives the same bits
// as one pass over the range, whatever the chunking.
constexpr int kChunk = 16384;
// A node with at least this many primitives builds its two children as separate tasks;
// below it a subtree is built by one thread in the serial order.
constexpr int kSubtreeTask = 4096;

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

int block_shift_of(int leaf_block) {
  for (int s = 0; s < 31; ++s)
    if (leaf_block == 1 << s) return s;
  return -1;
}

// The leaf blocks of n primitives: ceil(n / leaf_block).
double blocks(int n, const Input& in) {
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
Bins& thread_bins(int nb) {
  thread_local std::unique_ptr<Bins> bins;
  if (!bins || bins->count_per_axis() != nb) bins = std::make_unique<Bins>(nb);
  return *bins;
}

// The centroid bounds' origin and extent, for a primitive's bin on an axis:
// min(nb - 1, int(nb * (centre - lo) / ext)). The extent is 1 on an axis that is not
// binned (no 0 / 0 in its spare lane).
struct BinFrame {
  D4 lo;
  D4 ext;
};
BinFrame bin_frame(const Box4& cbox) {
  BinFrame f{cbox.lo, cbox.hi - cbox.lo};
  for (int k = 0; k < 4; ++k)
    if (!(k < 3 && f.ext[k] > 0.0)) f.lo[k] = 0.0, f.ext[k] = 1.0;
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

void bounds_of(const HugePageVector<Ref>& order, int first, int count, Box4& box, Box4& cbox) {
  auto pass = [&](int lo, int hi, Box4& b, Box4& c) {
    for (int i = lo; i < hi; ++i) {
      const Ref& r = order[std::size_t(i)];
      b.grow(r.box);
      c.grow(r.center());
    }
  };
  if (count < 2 * kChunk) return pass(first, first + count, box, cbox);
  std::vector<Box4> b((count + kChunk - 1) / kChunk), c(b.size());
  for_chunks(first, count, [&](int lo, int hi, int k) { pass(lo, hi, b[k], c[k]); });
  for (std::size_t k = 0; k < b.size(); ++k) {
    box.grow(b[k]);
    cbox.grow(c[k]);
  }
}

// Fills bins with the range's primitives, every axis whose centroid extent is positive
// in one pass over them (each bin grows in primitive order, as three passes would). The
// three axes' bin indices are one vector division; they are kept in the reference for
// the partition.
void bin_range(const Input& in, HugePageVector<Ref>& order, int first, int count, const Box4& cbox, Bins& bins) {
  const int nb = in.opt.bins;
  int axes[3], n_axes = 0;
  for (int axis = 0; axis < 3; ++axis)
    if (cbox.hi[axis] - cbox.lo[axis] > 0.0) axes[n_axes++] = axis;
  const BinFrame f = bin_frame(cbox);
  const D4 nbv = {double(nb), double(nb), double(nb), double(nb)};
  const I4 last_bin = {nb - 1, nb - 1, nb - 1, nb - 1};
  // In runs of kBinRun references: first every reference's bins (independent divisions,
  // which overlap), then the bins' boxes grown. One reference at a time, each bin's
  // address waited on the division's latency chain (perf: a fifth of the binning on the
  // first box update).
  constexpr int kBinRun = 16;
  auto pass = [&](int lo_i, int hi_i, Bins& out) {
    I4 k[kBinRun];
    for (int i0 = lo_i; i0 < hi_i; i0 += kBinRun) {
      const int n = std::min(kBinRun, hi_i - i0);
      // Clamped to [0, nb] first, which changes no binned axis's value (its centroids lie
      // in the frame), so that every lane converts within range, all four in one
      // instruction (AVX has none from double to 64-bit integers).
      for (int j = 0; j < n; ++j)
        k[j] = __builtin_convertvector(
            vmin(vmax(nbv * (order[std::size_t(i0 + j)].center() - f.lo) / f.ext, D4{}), nbv), I4);
      // Each lane's bin at most nb - 1 (std::min(nb - 1, k)), all three in one vector
      // min; a node whose three axes are all binned (nearly every one) has its three
      // updates unrolled.
      for (int j = 0; j < n; ++j) k[j] = k[j] < last_bin ? k[j] : last_bin;
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
          r.box.hi[3] = double(std::int64_t(b[0]) | std::int64_t(b[1]) << 8 | std::int64_t(b[2]) << 16);
        }
        continue;
      }
      for (int j = 0; j < n; ++j) {
        Ref& r = order[std::size_t(i0 + j)];
        std::int64_t packed = 0;
        for (int a = 0; a < n_axes; ++a) {
          int axis = axes[a];
          int bin = k[j][axis];
          packed |= std::int64_t(bin) << (8 * axis);
          std::size_t at = std::size_t(axis * nb + bin);
          out.box[at].grow(r.box);
          ++out.count[at];
        }
        r.box.hi[3] = double(packed);
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
Split find_split(const Input& in, Bins& bins, const Box4& cbox) {
  Split best;
  const int nb = in.opt.bins;
  double* right_area = bins.right_area.data();
  int* right_count = bins.right_count.data();
  int* used = bins.used.data();
  for (int axis = 0; axis < 3; ++axis) {
    if (!(cbox.hi[axis] - cbox.lo[axis] > 0.0)) continue;
    Box4* bin_box = &bins.box[std::size_t(axis * nb)];
    int* bin_count = &bins.count[std::size_t(axis * nb)];
    int m = 0;
    for (int k = 0; k < nb; ++k) {
      used[m] = k;
      m += bin_count[k] != 0 ? 1 : 0;
    }
    // right_area[j], right_count[j]: the bins used[j..m-1].
    Box4 acc;
    int n = 0;
    for (int j = m - 1; j > 0; --j) {
      acc.grow(bin_box[used[j]]);
      n += bin_count[used[j]];
      right_area[j] = acc.area_of_nonempty();
      right_count[j] = n;
    }
    acc = Box4{};
    n = 0;
    for (int j = 0; j + 1 < m; ++j) {
      acc.grow(bin_box[used[j]]);
      n += bin_count[used[j]];
      double cost = acc.area_of_nonempty() * blocks(n, in) + right_area[j + 1] * blocks(right_count[j + 1], in);
      if (cost < best.cost) best = {axis, used[j], cost};
    }
    for (int j = 0; j < m; ++j) {
      bin_box[used[j]] = Box4{};
      bin_count[used[j]] = 0;
    }
  }
  return best;
}

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
bool leaf_whatever_plane(const Input& in, int count, double traversal_cost) {
  const SahOptions& opt = in.opt;
  return count <= opt.max_leaf_size && opt.intersection_cost >= 0.0 &&
         opt.intersection_cost * blocks(count, in) <= traversal_cost;
}

// plane: false for a range that is a leaf whatever its plane (leaf_whatever_plane), which
// takes its box alone: no centroid box, no bins, no plane (splits() then makes a leaf).
NodeChoice choose_split(const Input& in, HugePageVector<Ref>& order, int first, int count, Bins& bins,
                        bool plane) {
  NodeChoice c;
  c.count = count;
  if (!plane) {
    Box4 box;
    for (int i = first; i < first + count; ++i) box.grow(order[std::size_t(i)].box);
    c.box = box.aabb();
    return c;
  }
  Box4 box, cbox;
  bounds_of(order, first, count, box, cbox);
  c.box = box.aabb();
  if (count <= 1) return c;
  bin_range(in, order, first, count, cbox, bins);
  c.s = find_split(in, bins, cbox);
  c.area = c.box.area();
  c.leaf_cost = in.opt.intersection_cost * blocks(count, in);
  return c;
}

// Whether the node splits under traversal cost C_t. SAH in units of this node's area:
// leaf = C_i * b(n), split = C_t + C_i * (A_l b(n_l) + A_r b(n_r)) / A, b(n) the leaf's
// blocks (n itself with the default block of 1). A bin plane is taken when it is cheaper
// or the node is over max_leaf_size; without one, such a node splits by count.
bool splits(const Input& in, const NodeChoice& c, double traversal_cost) {
  if (c.count <= 1) return false;
  const SahOptions& opt = in.opt;
  if (c.count > opt.max_leaf_size) return true;
  if (c.s.axis < 0) return false;
  double split_cost = c.area > 0.0 ? traversal_cost + opt.intersection_cost * c.s.cost / c.area : c.leaf_cost;
  return split_cost < c.leaf_cost;
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

// One node's decision: its box, and where its range splits (mid < 0: a leaf).
struct NodeSplit {
  Aabb box;
  int mid = -1;
};

NodeSplit split_node(const Input& in, HugePageVector<Ref>& order, int first, int count, Bins& bins) {
  NodeChoice c =
      choose_split(in, order, first, count, bins, !leaf_whatever_plane(in, count, in.opt.traversal_cost));
  NodeSplit out;
  out.box = c.box;
  if (splits(in, c, in.opt.traversal_cost)) out.mid = partition_node(order, first, c);
  return out;
}

// Room for the binary nodes of every subtree of one build, written once and never
// value-initialised: a subtree over references [first, first + count) has at most
// 2 count - 1 nodes and writes them from slot 2 first on, so subtrees built at once never
// share a slot. One array of 2n slots (huge pages, kept from build to build:
// scenes/huge_page_vector.h) in place of a fresh vector per subtree task, whose pages
// were faulted in and zeroed by the kernel at every build (perf: two fifths of a bear
// build's page faults).
class NodeScratch {
 public:
  explicit NodeScratch(std::size_t slots) : slots_(slots), data_(alloc_.allocate(slots)) {}
  ~NodeScratch() { alloc_.deallocate(data_, slots_); }
  NodeScratch(const NodeScratch&) = delete;
  NodeScratch& operator=(const NodeScratch&) = delete;
  // The slots of the subtree over references from first on.
  BinaryNode* subtree(int first) const { return data_ + 2 * std::size_t(first); }

 private:
  HugePageAllocator<BinaryNode> alloc_;
  std::size_t slots_;
  BinaryNode* data_;
};

// The serial build of one subtree into out (room for 2 count - 1 nodes); returns how many
// it wrote. out[0] is its root, the rest in the order the serial builder allocates them
// (both children of a node at once, when the node is split; the right subtree is
// finished before the left one is started).
std::size_t build_serial(const Input& in, HugePageVector<Ref>& order, int first, int count, BinaryNode* out) {
  struct Job {
    int node, first, count;
  };
  std::size_t size = 1;
  out[0] = BinaryNode{};
  std::vector<Job> jobs{{0, first, count}};
  Bins bins(in.opt.bins);
  while (!jobs.empty()) {
    Job job = jobs.back();
    jobs.pop_back();
    NodeSplit s = split_node(in, order, job.first, job.count, bins);
    BinaryNode& node = out[job.node];
    node.box = s.box;
    if (s.mid < 0) {
      node.first = job.first;
      node.count = job.count;
      continue;
    }
    const int left = int(size);
    out[size++] = BinaryNode{};
    out[size++] = BinaryNode{};
    node.left = left;
    node.right = left + 1;
    jobs.push_back({left, job.first, s.mid - job.first});
    jobs.push_back({left + 1, s.mid, job.first + job.count - s.mid});
  }
  return size;
}

// A subtree built by tasks: either serial (its nodes as build_serial writes them, in the
// build's scratch) or a split root (root) whose children were built as separate tasks.
struct Subtree {
  const BinaryNode* serial = nullptr; // serial_size nodes, or nullptr for a split root
  std::size_t serial_size = 0;
  BinaryNode root;
  std::unique_ptr<Subtree> left, right;
  std::size_t size = 0; // nodes in the whole subtree
};

Subtree build_tasks(const Input& in, HugePageVector<Ref>& order, int first, int count, const NodeScratch& scratch) {
  Subtree t;
  if (count < kSubtreeTask) {
    BinaryNode* out = scratch.subtree(first);
    t.serial = out;
    t.serial_size = t.size = build_serial(in, order, first, count, out);
    return t;
  }
  Bins bins(in.opt.bins);
  NodeSplit s = split_node(in, order, first, count, bins);
  t.root.box = s.box;
  t.size = 1;
  if (s.mid < 0) {
    t.root.first = first;
    t.root.count = count;
    return t;
  }
  t.left = std::make_unique<Subtree>();
  t.right = std::make_unique<Subtree>();
  parallel_pair([&] { *t.left = build_tasks(in, order, first, s.mid - first, scratch); },
                [&] { *t.right = build_tasks(in, order, s.mid, first + count - s.mid, scratch); });
  t.size += t.left->size + t.right->size;
  return t;
}

// Writes subtree t with its root at out[at] and the nodes below it from out[below] on,
// numbered as the serial builder numbers them: a split root's children at below and
// below + 1, then the right child's subtree, then the left child's.
void place(const Subtree& t, HugePageVector<BinaryNode>& out, std::size_t at, std::size_t below) {
  if (t.serial) {
    auto moved = [&](BinaryNode n) {
      if (!n.is_leaf()) {
        n.left = int(below) + n.left - 1;
        n.right = int(below) + n.right - 1;
      }
      return n;
    };
    out[at] = moved(t.serial[0]);
    for (std::size_t i = 1; i < t.serial_size; ++i) out[below + i - 1] = moved(t.serial[i]);
    return;
  }
  out[at] = t.root;
  if (!t.left) return; // a leaf root
  out[at].left = int(below);
  out[at].right = int(below + 1);
  std::size_t right_below = below + 2, left_below = right_below + t.right->size - 1;
  parallel_pair([&] { place(*t.right, out, below + 1, right_below); },
                [&] { place(*t.left, out, below, left_below); });
}

// The checked options, and the boxes as references (ids in order).
HugePageVector<Ref> references_of(std::span<const Aabb> boxes, const SahOptions& opt) {
  if (opt.leaf_block < 1) throw Error("bvh: SAH leaf block " + std::to_string(opt.leaf_block) + " (must be >= 1)");
  // A reference keeps its bin on each axis in a byte (Ref::bin).
  if (opt.bins < 1 || opt.bins > 256) throw Error("bvh: SAH bins " + std::to_string(opt.bins) + " (must be 1-256)");
  const int n = int(boxes.size());
  // A NaN or empty box would give a NaN centroid and an out-of-range bin below.
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      if (!(boxes[i].lo[k] <= boxes[i].hi[k]) || !std::isfinite(boxes[i].lo[k]) || !std::isfinite(boxes[i].hi[k]))
        throw Error("bvh: box " + std::to_string(i) + " of " + std::to_string(n) + " is empty or not finite");
  HugePageVector<Ref> refs(boxes.size());
  parallel_chunks(boxes.size(), 8192, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      const Aabb& b = boxes[i];
      refs[i].box.lo = D4{b.lo.x, b.lo.y, b.lo.z, double(i)};
      refs[i].box.hi = D4{b.hi.x, b.hi.y, b.hi.z, 0.0};
    }
  });
  return refs;
}

} // namespace

BinaryBvh build_binned_sah(std::span<const Aabb> boxes, const SahOptions& opt) {
  HugePageVector<Ref> refs = references_of(boxes, opt);
  BinaryBvh bvh;
  const int n = int(boxes.size());
  if (n == 0) return bvh;
  const Input in{opt, block_shift_of(opt.leaf_block)};
  NodeScratch scratch(2 * std::size_t(n));
  if (build_concurrency() == 1 || n < kSubtreeTask) {
    BinaryNode* nodes = scratch.subtree(0);
    const std::size_t size = build_serial(in, refs, 0, n, nodes);
    bvh.nodes.assign(nodes, nodes + size);
  } else {
    Subtree root = build_tasks(in, refs, 0, n, scratch);
    bvh.nodes.resize(root.size);
    place(root, bvh.nodes, 0, 1);
  }
  bvh.order.resize(refs.size());
  parallel_chunks(refs.size(), 8192, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) bvh.order[i] = refs[i].id();
  });
  return bvh;
}

std::vector<BinaryBvh> build_binned_sah_costs(std::span<const Aabb> boxes, const SahOptions& opt,
                                              std::span<const double> traversal_costs) {
  HugePageVector<Ref> refs = references_of(boxes, opt);
  const std::size_t trees = traversal_costs.size();
  std::vector<BinaryBvh> out(trees);
  const int n = int(boxes.size());
  if (n == 0) return out;
  const Input in{opt, block_shift_of(opt.leaf_block)};
  for (BinaryBvh& t : out) {
    t.nodes.reserve(2 * std::size_t(n) - 1); // a binary tree over n references has at most 2n - 1 nodes
    t.nodes.resize(1);
    t.order.resize(boxes.size());
  }
  // build_serial's walk, once for every tree: a job's node in each tree, or -1 in a tree
  // that made a leaf above it. A tree's nodes are allocated in the order of its own
  // serial build (its nodes are visited in the same relative order), and a tree that
  // makes a leaf of a range takes the range's order then, as its own build leaves it.
  // A job's node per tree lives in `job_nodes` from job.nodes on (trees entries), not in
  // a vector of its own: a cluster BLAS is a few dozen jobs, and auto builds thousands
  // of them (some 280,000 allocations a build of the bear's 32-member shape).
  struct Job {
    int first, count;
    std::size_t nodes; // index of its first entry in job_nodes
  };
  std::vector<int> job_nodes(trees, 0);
  job_nodes.reserve((2 * std::size_t(n) - 1) * trees);
  std::vector<Job> jobs{{0, n, 0}};
  jobs.reserve(std::size_t(n)); // (the stack holds at most one job per reference)
  Bins& bins = thread_bins(opt.bins);
  std::vector<char> split(trees, 0);
  while (!jobs.empty()) {
    const Job job = jobs.back();
    jobs.pop_back();
    auto job_node = [&](std::size_t t) { return job_nodes[job.nodes + t]; };
    // A range that every tree still walking it keeps as a leaf needs its box alone.
    bool leaf_in_all = true;
    for (std::size_t t = 0; t < trees && leaf_in_all; ++t) {
      if (job_node(t) < 0) continue;
      leaf_in_all = leaf_whatever_plane(in, job.count, traversal_costs[t]);
    }
    const NodeChoice c = choose_split(in, refs, job.first, job.count, bins, !leaf_in_all);
    bool any = false;
    for (std::size_t t = 0; t < trees; ++t) {
      split[t] = 0;
      if (job_node(t) < 0) continue;
      BinaryNode& node = out[t].nodes[std::size_t(job_node(t))];
      node.box = c.box;
      split[t] = splits(in, c, traversal_costs[t]) ? 1 : 0;
      any = any || split[t] != 0;
      if (split[t]) continue;
      node.first = job.first;
      node.count = job.count;
      for (int i = job.first; i < job.first + job.count; ++i) out[t].order[std::size_t(i)] = refs[std::size_t(i)].id();
    }
    if (!any) continue;
    const int mid = partition_node(refs, job.first, c);
    const Job left{job.first, mid - job.first, job_nodes.size()};
    const Job right{mid, job.first + job.count - mid, job_nodes.size() + trees};
    job_nodes.resize(job_nodes.size() + 2 * trees, -1);
    for (std::size_t t = 0; t < trees; ++t) {
      if (!split[t]) continue;
      HugePageVector<BinaryNode>& nodes = out[t].nodes;
      const int l = int(nodes.size());
      nodes.push_back({});
      nodes.push_back({});
      nodes[std::size_t(job_node(t))].left = l;
      nodes[std::size_t(job_node(t))].right = l + 1;
      job_nodes[left.nodes + t] = l;
      job_nodes[right.nodes + t] = l + 1;
    }
    jobs.push_back(left);
    jobs.push_back(right);
  }
  return out;
}

} // namespace masq
