#include "bvh/build/binned_sah.h"
#include "masq/error.h"
#include <algorithm>
#include <string>
#include <array>
#include <cmath>

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

struct Split {
  int axis = -1;
  int bin = 0; // primitives in bins [0, bin] go left
  double cost = std::numeric_limits<double>::infinity();
};

struct Job {
  int node;
  int first;
  int count;
};

double blocks(int n, const SahOptions& opt) { return double((n + opt.leaf_block - 1) / opt.leaf_block); }

Split find_split(const std::vector<Aabb>& boxes, const std::vector<int>& order, int first, int count,
                 const Aabb& cbox, const SahOptions& opt) {
  Split best;
  const int nb = opt.bins;
  for (int axis = 0; axis < 3; ++axis) {
    double lo = cbox.lo[axis], ext = cbox.hi[axis] - lo;
    if (!(ext > 0.0)) continue;
    std::vector<Aabb> bin_box(nb);
    std::vector<int> bin_count(nb, 0);
    for (int i = first; i < first + count; ++i) {
      const Aabb& b = boxes[order[i]];
      int k = std::min(nb - 1, int(nb * (b.center()[axis] - lo) / ext));
      bin_box[k].grow(b);
      ++bin_count[k];
    }
    std::vector<double> right_area(nb, 0.0);
    std::vector<int> right_count(nb, 0);
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
  bvh.order.resize(n);
  for (int i = 0; i < n; ++i) bvh.order[i] = i;
  bvh.nodes.reserve(2 * std::size_t(n));
  bvh.nodes.push_back({});
  std::vector<Job> jobs{{0, 0, n}};
  while (!jobs.empty()) {
    Job job = jobs.back();
    jobs.pop_back();
    Aabb box, cbox;
    for (int i = job.first; i < job.first + job.count; ++i) {
      box.grow(boxes[bvh.order[i]]);
      cbox.grow(boxes[bvh.order[i]].center());
    }
    bvh.nodes[job.node].box = box;
    auto make_leaf = [&] {
      bvh.nodes[job.node].first = job.first;
      bvh.nodes[job.node].count = job.count;
    };
    if (job.count <= 1) {
      make_leaf();
      continue;
    }
    Split s = find_split(boxes, bvh.order, job.first, job.count, cbox, opt);
    // SAH in units of this node's area: leaf = C_i * b(n), split = C_t + C_i * (A_l b(n_l) + A_r b(n_r)) / A,
    // b(n) the leaf's blocks (n itself with the default block of 1).
    double area = box.area();
    double leaf_cost = opt.intersection_cost * blocks(job.count, opt);
    double split_cost = area > 0.0 ? opt.traversal_cost + opt.intersection_cost * s.cost / area : leaf_cost;
    int mid;
    if (s.axis >= 0 && (split_cost < leaf_cost || job.count > opt.max_leaf_size)) {
      double lo = cbox.lo[s.axis], ext = cbox.hi[s.axis] - lo;
      auto begin = bvh.order.begin() + job.first;
      auto it = std::partition(begin, begin + job.count, [&](int p) {
        int k = std::min(opt.bins - 1, int(opt.bins * (boxes[p].center()[s.axis] - lo) / ext));
        return k <= s.bin;
      });
      mid = int(it - bvh.order.begin());
    } else if (job.count > opt.max_leaf_size) {
      // Coincident centroids: no plane separates them, split by count.
      mid = job.first + job.count / 2;
    } else {
      make_leaf();
      continue;
    }
    int left = int(bvh.nodes.size());
    bvh.nodes.push_back({});
    bvh.nodes.push_back({});
    bvh.nodes[job.node].left = left;
    bvh.nodes[job.node].right = left + 1;
    jobs.push_back({left, job.first, mid - job.first});
    jobs.push_back({left + 1, mid, job.first + job.count - mid});
  }
  return bvh;
}

} // namespace masq
