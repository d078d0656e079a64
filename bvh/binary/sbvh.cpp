#include "bvh/binary/sbvh.h"
#include "masq/error.h"
#include <algorithm>
#include <cmath>
#include <deque>
#include <string>

namespace masq {

namespace {

struct Ref {
  Aabb box;
  int item;
};

struct Job {
  int node;
  int depth;
  std::vector<Ref> refs;
};

struct ObjectSplit {
  int axis = -1;
  int bin = 0;
  double cost = INFINITY; // A_l n_l + A_r n_r
  Aabb left, right;
};

struct SpatialSplit {
  int axis = -1;
  int bin = 0;             // bins [0, bin] go left: plane at the upper end of `bin`
  double cost = INFINITY;
  Aabb left, right;
  int n_left = 0, n_right = 0;
};

int centroid_bin(const Aabb& b, int axis, double lo, double ext, int nb) {
  return std::clamp(int(nb * (b.center()[axis] - lo) / ext), 0, nb - 1);
}

// The best plane between bins k and k+1 by A_l n_l + A_r n_r: bins [0, k] go left.
// left_count[k] counts what starts in bin k (goes left once the plane is above it),
// right_count[k] what ends in it; for object splits both are the bin's count.
struct BinSweep {
  int bin = -1;
  double cost = INFINITY;
  Aabb left, right;
  int n_left = 0, n_right = 0;
};

BinSweep sweep_bins(const std::vector<Aabb>& bin_box, const std::vector<int>& left_count,
                    const std::vector<int>& right_count) {
  const int nb = int(bin_box.size());
  std::vector<Aabb> right(static_cast<std::size_t>(nb));
  std::vector<int> n_right(static_cast<std::size_t>(nb), 0);
  Aabb acc;
  int n = 0;
  for (int k = nb - 1; k > 0; --k) {
    acc.grow(bin_box[std::size_t(k)]);
    n += right_count[std::size_t(k)];
    right[std::size_t(k)] = acc;
    n_right[std::size_t(k)] = n;
  }
  BinSweep best;
  acc = Aabb{};
  n = 0;
  for (int k = 0; k < nb - 1; ++k) {
    acc.grow(bin_box[std::size_t(k)]);
    n += left_count[std::size_t(k)];
    int nr = n_right[std::size_t(k) + 1];
    if (n == 0 || nr == 0 || acc.empty() || right[std::size_t(k) + 1].empty()) continue;
    double cost = acc.area() * n + right[std::size_t(k) + 1].area() * nr;
    if (cost < best.cost) best = {k, cost, acc, right[std::size_t(k) + 1], n, nr};
  }
  return best;
}

ObjectSplit best_object_split(const std::vector<Ref>& refs, const Aabb& cbox, int nb) {
  ObjectSplit best;
  for (int axis = 0; axis < 3; ++axis) {
    double lo = cbox.lo[axis], ext = cbox.hi[axis] - lo;
    if (!(ext > 0.0)) continue;
    std::vector<Aabb> bin_box(static_cast<std::size_t>(nb));
    std::vector<int> bin_count(static_cast<std::size_t>(nb), 0);
    for (const Ref& r : refs) {
      int k = centroid_bin(r.box, axis, lo, ext, nb);
      bin_box[std::size_t(k)].grow(r.box);
      ++bin_count[std::size_t(k)];
    }
    BinSweep sw = sweep_bins(bin_box, bin_count, bin_count);
    if (sw.bin >= 0 && sw.cost < best.cost) best = {axis, sw.bin, sw.cost, sw.left, sw.right};
  }
  return best;
}

// The plane between spatial bins k-1 and k of a node box (k = 0..nb): the same
// expression for the sweep and for the partition, so both see the same planes.
double plane_at(const Aabb& box, int axis, int k, int nb) {
  if (k <= 0) return box.lo[axis];
  if (k >= nb) return box.hi[axis];
  return box.lo[axis] + (box.hi[axis] - box.lo[axis]) * k / nb;
}

int spatial_bin(double x, const Aabb& box, int axis, int nb) {
  double ext = box.hi[axis] - box.lo[axis];
  int k = std::clamp(int(nb * (x - box.lo[axis]) / ext), 0, nb - 1);
  // Settle rounding against the planes themselves.
  while (k > 0 && x < plane_at(box, axis, k, nb)) --k;
  while (k < nb - 1 && x >= plane_at(box, axis, k + 1, nb)) ++k;
  return k;
}

Aabb clip_ref(const PrimClipper& clip, const Ref& r, int axis, double lo, double hi) {
  Aabb c = Aabb::intersect(clip(r.item, axis, lo, hi), r.box);
  return c.empty() ? Aabb{} : c;
}

SpatialSplit best_spatial_split(const std::vector<Ref>& refs, const Aabb& box, int nb, const PrimClipper& clip) {
  SpatialSplit best;
  for (int axis = 0; axis < 3; ++axis) {
    if (!(box.hi[axis] - box.lo[axis] > 0.0)) continue;
    std::vector<Aabb> bin_box(static_cast<std::size_t>(nb));
    std::vector<int> entry(static_cast<std::size_t>(nb), 0), exit(static_cast<std::size_t>(nb), 0);
    for (const Ref& r : refs) {
      int b0 = spatial_bin(r.box.lo[axis], box, axis, nb);
      int b1 = spatial_bin(r.box.hi[axis], box, axis, nb);
      ++entry[std::size_t(b0)];
      ++exit[std::size_t(b1)];
      if (b0 == b1) {
        bin_box[std::size_t(b0)].grow(r.box);
        continue;
      }
      for (int b = b0; b <= b1; ++b) {
        Aabb c = clip_ref(clip, r, axis, plane_at(box, axis, b, nb), plane_at(box, axis, b + 1, nb));
        if (!c.empty()) bin_box[std::size_t(b)].grow(c);
      }
    }
    BinSweep sw = sweep_bins(bin_box, entry, exit);
    if (sw.bin >= 0 && sw.cost < best.cost)
      best = {axis, sw.bin, sw.cost, sw.left, sw.right, sw.n_left, sw.n_right};
  }
  return best;
}

struct SbvhBuilder {
  std::span<const Aabb> boxes;
  const PrimClipper& clip;
  const SahOptions& sah;
  const SbvhOptions& opt;
  SbvhStats stats;
  std::size_t max_refs = 0;
  std::size_t refs_now = 0; // references alive: the items plus the pieces made so far
  double root_area = 0;
  BinaryBvh bvh;

  // Stich et al.'s spatial partition with reference unsplitting: a straddling
  // reference goes whole to one side when that is cheaper than the two pieces (or when
  // the budget is spent).
  void partition_spatial(std::vector<Ref>& refs, const Aabb& box, const SpatialSplit& s, std::vector<Ref>& left,
                         std::vector<Ref>& right) {
    int axis = s.axis;
    double plane = plane_at(box, axis, s.bin + 1, sah.bins);
    Aabb bl = s.left, br = s.right;
    double nl = s.n_left, nr = s.n_right;
    for (Ref& r : refs) {
      if (r.box.hi[axis] <= plane) {
        left.push_back(r);
      } else if (r.box.lo[axis] >= plane) {
        right.push_back(r);
      } else {
        Aabb cl = clip_ref(clip, r, axis, box.lo[axis], plane);
        Aabb cr = clip_ref(clip, r, axis, plane, box.hi[axis]);
        if (cl.empty()) {
          right.push_back({cr.empty() ? r.box : cr, r.item});
          continue;
        }
        if (cr.empty()) {
          left.push_back({cl, r.item});
          continue;
        }
        Aabb ul = bl, ur = br;
        ul.grow(r.box);
        ur.grow(r.box);
        double c_split = bl.area() * nl + br.area() * nr;
        double c_left = ul.area() * nl + br.area() * (nr - 1);  // whole to the left
        double c_right = bl.area() * (nl - 1) + ur.area() * nr; // whole to the right
        bool can_split = refs_now < max_refs;
        if (can_split && c_split <= c_left && c_split <= c_right) {
          left.push_back({cl, r.item});
          right.push_back({cr, r.item});
          ++refs_now;
        } else if (c_left <= c_right) {
          left.push_back(r);
          bl = ul;
          nr -= 1;
        } else {
          right.push_back(r);
          br = ur;
          nl -= 1;
        }
      }
    }
  }

  void partition_object(std::vector<Ref>& refs, const Aabb& cbox, const ObjectSplit& s, std::vector<Ref>& left,
                        std::vector<Ref>& right) {
    double lo = cbox.lo[s.axis], ext = cbox.hi[s.axis] - lo;
    for (Ref& r : refs) (centroid_bin(r.box, s.axis, lo, ext, sah.bins) <= s.bin ? left : right).push_back(r);
  }

  void make_leaf(int node, const std::vector<Ref>& refs) {
    bvh.nodes[std::size_t(node)].first = int(bvh.order.size());
    bvh.nodes[std::size_t(node)].count = int(refs.size());
    for (const Ref& r : refs) bvh.order.push_back(r.item);
  }

  void run() {
    const int n = int(boxes.size());
    std::vector<Ref> all(boxes.size());
    for (int i = 0; i < n; ++i) all[std::size_t(i)] = {boxes[std::size_t(i)], i};
    bvh.nodes.push_back({});
    refs_now = boxes.size();
    // Breadth first: the reference budget goes to the upper levels, where a split
    // plane cuts the most overlap, rather than to whichever subtree comes first.
    std::deque<Job> jobs;
    jobs.push_back({0, 0, std::move(all)});
    while (!jobs.empty()) {
      Job job = std::move(jobs.front());
      jobs.pop_front();
      std::vector<Ref>& refs = job.refs;
      Aabb box, cbox;
      for (const Ref& r : refs) {
        box.grow(r.box);
        cbox.grow(r.box.center());
      }
      if (job.node == 0) root_area = std::max(box.area(), 1e-300);
      bvh.nodes[std::size_t(job.node)].box = box;
      const int count = int(refs.size());
      if (count <= 1) {
        make_leaf(job.node, refs);
        continue;
      }
      ObjectSplit os = best_object_split(refs, cbox, sah.bins);
      SpatialSplit ss;
      Aabb overlap = Aabb::intersect(os.left, os.right);
      bool try_spatial = refs_now < max_refs && job.depth < opt.max_spatial_depth &&
                         (os.axis < 0 || (!overlap.empty() && overlap.area() > opt.alpha * root_area));
      if (try_spatial) ss = best_spatial_split(refs, box, sah.bins, clip);
      double area = box.area();
      double leaf_cost = sah.intersection_cost * count;
      // SAH in units of this node's area, as build_binned_sah: split when cheaper than a
      // leaf, or when the leaf would be too large.
      auto worth = [&](double c) {
        return std::isfinite(c) && (count > sah.max_leaf_size ||
                                    (area > 0.0 && sah.traversal_cost + sah.intersection_cost * c / area < leaf_cost));
      };
      std::vector<Ref> left, right;
      if (ss.cost < os.cost && worth(ss.cost)) {
        partition_spatial(refs, box, ss, left, right);
        // Both sides may hold every reference (long parallel strands cut in two: each
        // side's box is smaller); one empty side would make no progress.
        if (!left.empty() && !right.empty()) {
          ++stats.spatial_splits;
        } else {
          refs_now -= left.size() + right.size() - refs.size();
          left.clear();
          right.clear();
        }
      }
      if (left.empty() && right.empty() && os.axis >= 0 && worth(os.cost)) {
        partition_object(refs, cbox, os, left, right);
        ++stats.object_splits;
      }
      if (left.empty() || right.empty()) {
        left.clear();
        right.clear();
        if (count <= sah.max_leaf_size) {
          make_leaf(job.node, refs);
          continue;
        }
        // Coincident centroids and no useful plane: split by count.
        left.assign(refs.begin(), refs.begin() + count / 2);
        right.assign(refs.begin() + count / 2, refs.end());
      }
      int l = int(bvh.nodes.size());
      bvh.nodes.push_back({});
      bvh.nodes.push_back({});
      bvh.nodes[std::size_t(job.node)].left = l;
      bvh.nodes[std::size_t(job.node)].right = l + 1;
      refs.clear();
      refs.shrink_to_fit();
      jobs.push_back({l, job.depth + 1, std::move(left)});
      jobs.push_back({l + 1, job.depth + 1, std::move(right)});
    }
    stats.references = bvh.order.size();
  }
};

} // namespace

BinaryBvh build_sbvh(std::span<const Aabb> boxes, const PrimClipper& clip, const SahOptions& sah,
                     const SbvhOptions& opt, SbvhStats* stats) {
  if (!(opt.max_refs >= 1.0)) throw Error("sbvh: reference budget " + std::to_string(opt.max_refs) + " is below 1");
  if (!(opt.alpha >= 0.0)) throw Error("sbvh: alpha " + std::to_string(opt.alpha) + " is negative");
  if (sah.bins < 2) throw Error("sbvh: needs at least 2 bins");
  const std::size_t n = boxes.size();
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      if (!(boxes[i].lo[k] <= boxes[i].hi[k]) || !std::isfinite(boxes[i].lo[k]) || !std::isfinite(boxes[i].hi[k]))
        throw Error("bvh: box " + std::to_string(i) + " of " + std::to_string(n) + " is empty or not finite");
  SbvhBuilder b{boxes, clip, sah, opt, {}};
  if (n == 0) return {};
  b.max_refs = std::size_t(std::floor(opt.max_refs * double(n)));
  b.run();
  if (stats) *stats = b.stats;
  return std::move(b.bvh);
}

} // namespace masq
