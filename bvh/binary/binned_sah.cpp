#include "bvh/binary/binned_sah.h"
#include "bvh/binary/parallel.h"
#include "bvh/binary/partition_in_chunks.h"
#include "masq/error.h"
#include <algorithm>
#include <string>
#include <array>
#include <cmath>
#include <memory>

namespace masq {

float round_down(double x) {
  float f = static_cast<float>(x);
  return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float round_up(double x) {
  float f = static_cast<float>(x);
  return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

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

double blocks(int n, const SahOptions& opt) { return double((n + opt.leaf_block - 1) / opt.leaf_block); }

// What every node of one build reads: the options. The primitives are references that
// carry their box and centroid (computed once, as Aabb::center computes them) and are
// partitioned themselves, so that a node reads its range in order; reading the boxes
// through an index array instead (the build before) fetched each one from wherever
// the primitive's index pointed, at every level.
struct Input {
  const SahOptions& opt;
};
struct Ref {
  Aabb box;
  glm::dvec3 center;
  int id;
};

// Per axis nb bins: box and primitive count of the centroids that fall in each; and the
// sweep's suffix areas and counts. Kept by a thread from node to node (no allocation
// per node).
struct Bins {
  std::vector<Aabb> box;
  std::vector<int> count;
  std::vector<double> right_area;
  std::vector<int> right_count;
  explicit Bins(int nb) : box(3 * std::size_t(nb)), count(3 * std::size_t(nb), 0), right_area(nb), right_count(nb) {}
  void clear() {
    std::fill(box.begin(), box.end(), Aabb{});
    std::fill(count.begin(), count.end(), 0);
  }
  void merge(const Bins& o) {
    for (std::size_t i = 0; i < box.size(); ++i) {
      box[i].grow(o.box[i]);
      count[i] += o.count[i];
    }
  }
};

int bin_of(const glm::dvec3& center, int axis, double lo, double ext, int nb) {
  return std::min(nb - 1, int(nb * (center[axis] - lo) / ext));
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

void bounds_of(const std::vector<Ref>& order, int first, int count, Aabb& box, Aabb& cbox) {
  auto pass = [&](int lo, int hi, Aabb& b, Aabb& c) {
    for (int i = lo; i < hi; ++i) {
      b.grow(order[std::size_t(i)].box);
      c.grow(order[std::size_t(i)].center);
    }
  };
  if (count < 2 * kChunk) return pass(first, first + count, box, cbox);
  std::vector<Aabb> b((count + kChunk - 1) / kChunk), c(b.size());
  for_chunks(first, count, [&](int lo, int hi, int k) { pass(lo, hi, b[k], c[k]); });
  for (std::size_t k = 0; k < b.size(); ++k) {
    box.grow(b[k]);
    cbox.grow(c[k]);
  }
}

// Fills bins with the range's primitives, every axis whose centroid extent is positive
// in one pass over them (each bin grows in primitive order, as three passes would).
void bin_range(const Input& in, const std::vector<Ref>& order, int first, int count, const Aabb& cbox, Bins& bins) {
  const int nb = in.opt.bins;
  int axes[3], n_axes = 0;
  for (int axis = 0; axis < 3; ++axis)
    if (cbox.hi[axis] - cbox.lo[axis] > 0.0) axes[n_axes++] = axis;
  auto pass = [&](int lo_i, int hi_i, Bins& out) {
    for (int i = lo_i; i < hi_i; ++i) {
      const Aabb& b = order[std::size_t(i)].box;
      const glm::dvec3& c = order[std::size_t(i)].center;
      for (int a = 0; a < n_axes; ++a) {
        int axis = axes[a];
        std::size_t k = std::size_t(axis * nb + bin_of(c, axis, cbox.lo[axis], cbox.hi[axis] - cbox.lo[axis], nb));
        out.box[k].grow(b);
        ++out.count[k];
      }
    }
  };
  bins.clear();
  if (count < 2 * kChunk) return pass(first, first + count, bins);
  std::vector<Bins> part((count + kChunk - 1) / kChunk, Bins(nb));
  for_chunks(first, count, [&](int lo, int hi, int k) { pass(lo, hi, part[k]); });
  for (const Bins& p : part) bins.merge(p);
}

Split find_split(Bins& bins, const Aabb& cbox, const SahOptions& opt) {
  Split best;
  const int nb = opt.bins;
  std::vector<double>& right_area = bins.right_area;
  std::vector<int>& right_count = bins.right_count;
  for (int axis = 0; axis < 3; ++axis) {
    if (!(cbox.hi[axis] - cbox.lo[axis] > 0.0)) continue;
    const Aabb* bin_box = &bins.box[std::size_t(axis * nb)];
    const int* bin_count = &bins.count[std::size_t(axis * nb)];
    Aabb acc;
    int n = 0;
    for (int k = nb - 1; k > 0; --k) {
      acc.grow(bin_box[k]);
      n += bin_count[k];
      right_area[k] = acc.area();
      right_count[k] = n;
    }
    acc = Aabb{};
    n = 0;
    for (int k = 0; k < nb - 1; ++k) {
      acc.grow(bin_box[k]);
      n += bin_count[k];
      if (n == 0 || right_count[k + 1] == 0) continue;
      double cost = acc.area() * blocks(n, opt) + right_area[k + 1] * blocks(right_count[k + 1], opt);
      if (cost < best.cost) best = {axis, k, cost};
    }
  }
  return best;
}

// One node's decision: its box, and where its range splits (mid < 0: a leaf).
struct NodeSplit {
  Aabb box;
  int mid = -1;
};

NodeSplit split_node(const Input& in, std::vector<Ref>& order, int first, int count, Bins& bins) {
  const SahOptions& opt = in.opt;
  NodeSplit out;
  Aabb cbox;
  bounds_of(order, first, count, out.box, cbox);
  if (count <= 1) return out;
  bin_range(in, order, first, count, cbox, bins);
  Split s = find_split(bins, cbox, opt);
  // SAH in units of this node's area: leaf = C_i * b(n), split = C_t + C_i * (A_l b(n_l) + A_r b(n_r)) / A,
  // b(n) the leaf's blocks (n itself with the default block of 1).
  double area = out.box.area();
  double leaf_cost = opt.intersection_cost * blocks(count, opt);
  double split_cost = area > 0.0 ? opt.traversal_cost + opt.intersection_cost * s.cost / area : leaf_cost;
  if (s.axis >= 0 && (split_cost < leaf_cost || count > opt.max_leaf_size)) {
    double lo = cbox.lo[s.axis], ext = cbox.hi[s.axis] - lo;
    auto goes_left = [&](const Ref& p) { return bin_of(p.center, s.axis, lo, ext, opt.bins) <= s.bin; };
    // std::partition's own (unstable) order decides the leaf order: a long range gets the
    // same order from partition_in_chunks.
    if (count < 2 * kChunk) {
      auto begin = order.begin() + first;
      out.mid = int(std::partition(begin, begin + count, goes_left) - order.begin());
    } else {
      out.mid = partition_in_chunks(order, first, count, kChunk, goes_left);
    }
  } else if (count > opt.max_leaf_size) {
    out.mid = first + count / 2; // coincident centroids: no plane separates them, split by count
  }
  return out;
}

// The serial build of one subtree: nodes[0] is its root, the rest in the order the
// serial builder allocates them (both children of a node at once, when the node is
// split; the right subtree is finished before the left one is started).
std::vector<BinaryNode> build_serial(const Input& in, std::vector<Ref>& order, int first, int count) {
  struct Job {
    int node, first, count;
  };
  std::vector<BinaryNode> nodes(1);
  nodes.reserve(2 * std::size_t(count));
  std::vector<Job> jobs{{0, first, count}};
  Bins bins(in.opt.bins);
  while (!jobs.empty()) {
    Job job = jobs.back();
    jobs.pop_back();
    NodeSplit s = split_node(in, order, job.first, job.count, bins);
    nodes[job.node].box = s.box;
    if (s.mid < 0) {
      nodes[job.node].first = job.first;
      nodes[job.node].count = job.count;
      continue;
    }
    int left = int(nodes.size());
    nodes.push_back({});
    nodes.push_back({});
    nodes[job.node].left = left;
    nodes[job.node].right = left + 1;
    jobs.push_back({left, job.first, s.mid - job.first});
    jobs.push_back({left + 1, s.mid, job.first + job.count - s.mid});
  }
  return nodes;
}

// A subtree built by tasks: either serial (nodes as build_serial gives them) or a split
// root (nodes = {root}) whose children were built as separate tasks.
struct Subtree {
  std::vector<BinaryNode> nodes;
  std::unique_ptr<Subtree> left, right;
  std::size_t size = 0; // nodes in the whole subtree
};

Subtree build_tasks(const Input& in, std::vector<Ref>& order, int first, int count) {
  Subtree t;
  if (count < kSubtreeTask) {
    t.nodes = build_serial(in, order, first, count);
    t.size = t.nodes.size();
    return t;
  }
  Bins bins(in.opt.bins);
  NodeSplit s = split_node(in, order, first, count, bins);
  t.nodes.resize(1);
  t.nodes[0].box = s.box;
  t.size = 1;
  if (s.mid < 0) {
    t.nodes[0].first = first;
    t.nodes[0].count = count;
    return t;
  }
  t.left = std::make_unique<Subtree>();
  t.right = std::make_unique<Subtree>();
  parallel_pair([&] { *t.left = build_tasks(in, order, first, s.mid - first); },
                [&] { *t.right = build_tasks(in, order, s.mid, first + count - s.mid); });
  t.size += t.left->size + t.right->size;
  return t;
}

// Writes subtree t with its root at out[at] and the nodes below it from out[below] on,
// numbered as the serial builder numbers them: a split root's children at below and
// below + 1, then the right child's subtree, then the left child's.
void place(const Subtree& t, std::vector<BinaryNode>& out, std::size_t at, std::size_t below) {
  if (!t.left) {
    auto moved = [&](BinaryNode n) {
      if (!n.is_leaf()) {
        n.left = int(below) + n.left - 1;
        n.right = int(below) + n.right - 1;
      }
      return n;
    };
    out[at] = moved(t.nodes[0]);
    for (std::size_t i = 1; i < t.nodes.size(); ++i) out[below + i - 1] = moved(t.nodes[i]);
    return;
  }
  out[at] = t.nodes[0];
  out[at].left = int(below);
  out[at].right = int(below + 1);
  std::size_t right_below = below + 2, left_below = right_below + t.right->size - 1;
  parallel_pair([&] { place(*t.right, out, below + 1, right_below); },
                [&] { place(*t.left, out, below, left_below); });
}

} // namespace

BinaryBvh build_binned_sah(const std::vector<Aabb>& boxes, const SahOptions& opt) {
  if (opt.leaf_block < 1) throw Error("bvh: SAH leaf block " + std::to_string(opt.leaf_block) + " (must be >= 1)");
  BinaryBvh bvh;
  const int n = int(boxes.size());
  if (n == 0) return bvh;
  // A NaN or empty box would give a NaN centroid and an out-of-range bin below.
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      if (!(boxes[i].lo[k] <= boxes[i].hi[k]) || !std::isfinite(boxes[i].lo[k]) || !std::isfinite(boxes[i].hi[k]))
        throw Error("bvh: box " + std::to_string(i) + " of " + std::to_string(n) + " is empty or not finite");
  std::vector<Ref> refs(boxes.size());
  const Input in{opt};
  parallel_chunks(boxes.size(), 8192, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) refs[i] = {boxes[i], boxes[i].center(), int(i)};
  });
  if (build_concurrency() == 1 || n < kSubtreeTask) {
    bvh.nodes = build_serial(in, refs, 0, n);
  } else {
    Subtree root = build_tasks(in, refs, 0, n);
    bvh.nodes.resize(root.size);
    place(root, bvh.nodes, 0, 1);
  }
  bvh.order.resize(refs.size());
  parallel_chunks(refs.size(), 8192, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) bvh.order[i] = refs[i].id;
  });
  return bvh;
}

} // namespace masq
