// The binned SAH's builds: one tree (serial, or split into tasks on the build's
// threads) or several trees that differ in the traversal cost alone; each node's step
// (bounds, bins, plane, partition) is bvh/binary/binned_sah_node.h's.
#include "bvh/binary/binned_sah.h"
#include "bvh/binary/binned_sah_node.h"
#include "bvh/binary/parallel.h"
#include <memory>

namespace masq {

namespace {

using namespace sah_node;

// A node with at least this many primitives builds its two children as separate tasks;
// below it a subtree is built by one thread in the serial order.
constexpr int kSubtreeTask = 4096;

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
