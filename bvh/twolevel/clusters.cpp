#include "bvh/twolevel/clusters.h"
#include "bvh/binary/parallel.h"
#include "bvh/bounds/obb.h"
#include "masq/error.h"
#include "scenes/prim_table.h"
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

namespace masq {

namespace {

glm::dvec3 any_perpendicular(const glm::dvec3& w) {
  glm::dvec3 helper = std::abs(w.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(w, helper));
}

glm::dmat3 frame_along(const glm::dvec3& w) {
  glm::dvec3 u = any_perpendicular(w);
  return glm::dmat3(w, u, glm::cross(w, u));
}

// Hull box in the frame whose axes are the columns of `axes` (about the object origin);
// support_pair gives both sides' bits at the cost of one.
Aabb box_in_frame(const BallHull& h, const glm::dmat3& axes) {
  Aabb b;
  for (int k = 0; k < 3; ++k) {
    const BallHull::Pair side = h.support_pair(axes[k]);
    b.lo[k] = -side.minus;
    b.hi[k] = side.plus;
  }
  return b;
}

} // namespace

std::vector<glm::dvec3> orientation_classes(int count) {
  // A Fibonacci spiral over z in (0, 1]: equal areas of the hemisphere per point.
  std::vector<glm::dvec3> dirs;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    double z = 1.0 - (i + 0.5) / count;
    double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    dirs.push_back({r * std::cos(golden * i), r * std::sin(golden * i), z});
  }
  return dirs;
}

namespace {

// The axis a primitive is oriented along, from its hull (unit; the chord for curves), or
// zero when it has none (both ends at one point).
glm::dvec3 hull_axis(const BallHull& h) {
  glm::dvec3 d = h.centre[h.count - 1] - h.centre[0];
  if (h.count == 4 && glm::length(d) == 0.0) d = h.centre[2] - h.centre[1];
  double l = glm::length(d);
  return l > 0.0 && std::isfinite(l) ? d / l : glm::dvec3(0.0);
}

// A primitive of a class: its centroid in the class's frame (what the k-d split sorts
// by) beside its id, so that the split reads one contiguous array rather than a
// geometry-wide one at scattered ids (perf: those reads, and the hulls read again at
// scattered ids for the centroids, missed the cache in most of make_clusters' time).
struct ClassItem {
  glm::dvec3 centroid;
  std::int32_t prim;
};

void check_cluster_input(const Geometry& g, int classes) {
  if (classes < 1 || classes > 1024)
    throw Error("cluster: classes " + std::to_string(classes) + " outside 1..1024");
  if (!scene_prim_row(g.type).oriented)
    throw Error(std::string("cluster: a ") + prim_type_name(g.type) + " geometry has no orientation to cluster by");
}

std::vector<glm::dmat3> class_frames(const std::vector<glm::dvec3>& dirs) {
  std::vector<glm::dmat3> out(dirs.size());
  for (std::size_t c = 0; c < dirs.size(); ++c) out[c] = frame_along(dirs[c]);
  return out;
}

} // namespace

ClassAssignment assign_classes(const Geometry& g, const std::vector<std::int32_t>& prims, int classes) {
  check_cluster_input(g, classes);
  const std::vector<glm::dvec3> dirs = orientation_classes(classes);
  const std::vector<glm::dmat3> class_axes = class_frames(dirs);
  // The directions' coordinates as three rows, so that a primitive's products with all
  // of them are one loop the compiler runs in vector lanes (glm::dot's operations and
  // order in each lane: the same bits).
  std::vector<double> dir_x(dirs.size()), dir_y(dirs.size()), dir_z(dirs.size());
  for (std::size_t c = 0; c < dirs.size(); ++c) dir_x[c] = dirs[c].x, dir_y[c] = dirs[c].y, dir_z[c] = dirs[c].z;
  // Each primitive's class and centroid in its class's frame on all threads (one look at
  // its hull, in the order of prims).
  ClassAssignment out;
  out.classes = classes;
  out.class_of.resize(prims.size());
  out.centroid.resize(prims.size());
  parallel_chunks(prims.size(), 1024, [&](std::size_t lo, std::size_t hi) {
    std::vector<double> along(dirs.size());
    for (std::size_t i = lo; i < hi; ++i) {
      const std::size_t p = std::size_t(prims[i]);
      const BallHull h = ball_hull(g, p);
      const glm::dvec3 w = hull_axis(h);
      for (std::size_t c = 0; c < dirs.size(); ++c) // antipodal axes are the same orientation
        along[c] = std::abs((w.x * dir_x[c] + w.y * dir_y[c]) + w.z * dir_z[c]);
      // The first direction of the largest (w is finite, so no value is NaN).
      std::size_t best = 0;
      double best_dot = -1.0;
      for (std::size_t c = 0; c < dirs.size(); ++c)
        if (along[c] > best_dot) best_dot = along[c], best = c;
      out.class_of[i] = std::uint32_t(best);
      out.centroid[i] = box_in_frame(h, class_axes[best]).center();
    }
  });
  return out;
}

std::vector<Cluster> make_clusters(const Geometry& g, const std::vector<std::int32_t>& prims,
                                   const ClusterOptions& opt, const ClassAssignment* assigned, ClusterHulls* hulls_out) {
  if (opt.max_size < 2 || opt.max_size > 256)
    throw Error("cluster: max_size " + std::to_string(opt.max_size) + " outside 2..256");
  check_cluster_input(g, opt.classes);
  if (assigned && (assigned->classes != opt.classes || assigned->class_of.size() != prims.size()))
    throw Error("cluster: a class assignment of " + std::to_string(assigned->classes) + " classes and " +
                std::to_string(assigned->class_of.size()) + " primitives for " + std::to_string(opt.classes) +
                " classes and " + std::to_string(prims.size()) + " primitives");
  const std::vector<glm::dvec3> dirs = orientation_classes(opt.classes);
  std::optional<ClassAssignment> made;
  if (!assigned) assigned = &made.emplace(assign_classes(g, prims, opt.classes));
  const std::vector<std::uint32_t>& class_of = assigned->class_of;
  const std::vector<glm::dvec3>& centroid = assigned->centroid;
  // The classes filled in the order of prims (as one pass would fill them).
  std::vector<std::vector<ClassItem>> by_class(dirs.size());
  for (std::size_t i = 0; i < prims.size(); ++i) by_class[class_of[i]].push_back({centroid[i], prims[i]});

  // The classes are split on all threads, each into its own list, joined in class order.
  std::vector<std::vector<Cluster>> of_class(dirs.size());
  std::vector<ClusterHulls> hulls_of_class(hulls_out ? dirs.size() : 0);
  parallel_chunks(dirs.size(), 1, [&](std::size_t c0, std::size_t c1) {
    std::vector<BallHull> hulls; // a cluster's members' (reused from cluster to cluster unless moved to hulls_out)
    for (std::size_t c = c0; c < c1; ++c) {
      std::vector<ClassItem>& items = by_class[c];
      if (items.empty()) continue;
      std::vector<Cluster>& out = of_class[c];
      // Top-down k-d split of the class at the centroids' widest extent (in the class's
      // frame), at a multiple of max_size nearest the middle: every cluster but one per
      // class is full, which keeps the per-cluster instance cost (64 B + a TLAS entry)
      // spread over max_size members. Parts are ranges of items, split in place; the
      // later half of a split is taken first.
      std::vector<std::pair<std::size_t, std::size_t>> parts{{0, items.size()}};
      while (!parts.empty()) {
        const auto [first, last] = parts.back();
        parts.pop_back();
        const auto begin = items.begin() + std::ptrdiff_t(first), end = items.begin() + std::ptrdiff_t(last);
        const std::size_t size = last - first;
        if (int(size) > opt.max_size) {
          Aabb cb;
          for (auto it = begin; it != end; ++it) cb.grow(it->centroid);
          glm::dvec3 ext = cb.hi - cb.lo;
          int split_axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
          std::size_t k = std::size_t(opt.max_size);
          std::size_t mid = std::max<std::size_t>(1, (size / 2 + k / 2) / k) * k;
          // One comparison per axis, the axis fixed at compile time (glm's run-time
          // component index is a switch in every comparison).
          auto split_by = [&](auto key) {
            std::nth_element(begin, begin + std::ptrdiff_t(mid), end,
                             [&](const ClassItem& a, const ClassItem& b) { return key(a) < key(b); });
          };
          if (split_axis == 0) split_by([](const ClassItem& item) { return item.centroid.x; });
          else if (split_axis == 1) split_by([](const ClassItem& item) { return item.centroid.y; });
          else split_by([](const ClassItem& item) { return item.centroid.z; });
          parts.emplace_back(first, first + mid);
          parts.emplace_back(first + mid, last);
          continue;
        }
        Cluster cl;
        cl.members.reserve(size);
        for (auto it = begin; it != end; ++it) cl.members.push_back(it->prim);
        member_hulls(g, cl.members, hulls);
        // Dominant axis: the members' axes summed with their signs aligned to the class.
        glm::dvec3 sum(0.0);
        for (const BallHull& h : hulls) {
          const glm::dvec3 w = hull_axis(h);
          sum += glm::dot(w, dirs[c]) < 0.0 ? -w : w;
        }
        double l = glm::length(sum);
        cl.axes = frame_along(l > 1e-12 ? sum / l : dirs[c]);
        Aabb about_origin;
        for (const BallHull& h : hulls) {
          const Aabb own = box_in_frame(h, cl.axes);
          about_origin.grow(own);
          cl.member_area += own.area();
        }
        glm::dvec3 mid_pt = about_origin.center();
        cl.centre = cl.axes * mid_pt;
        cl.local_box.lo = about_origin.lo - mid_pt;
        cl.local_box.hi = about_origin.hi - mid_pt;
        out.push_back(std::move(cl));
        if (hulls_out) hulls_of_class[c].push_back(std::move(hulls)); // (then a fresh one)
      }
    }
  });
  std::vector<Cluster> out;
  for (std::vector<Cluster>& part : of_class)
    for (Cluster& cl : part) out.push_back(std::move(cl));
  if (hulls_out) {
    hulls_out->clear();
    hulls_out->reserve(out.size());
    for (ClusterHulls& part : hulls_of_class)
      for (std::vector<BallHull>& h : part) hulls_out->push_back(std::move(h));
  }
  return out;
}

bool hulls_match(const ClusterHulls& hulls, const std::vector<Cluster>& clusters) {
  if (hulls.size() != clusters.size()) return false;
  for (std::size_t ci = 0; ci < clusters.size(); ++ci)
    if (hulls[ci].size() != clusters[ci].members.size()) return false;
  return true;
}

void member_hulls(const Geometry& g, std::span<const std::int32_t> members, std::vector<BallHull>& out) {
  out.clear();
  out.reserve(members.size());
  for (std::int32_t p : members) out.push_back(ball_hull(g, std::size_t(p)));
}

Affine3 cluster_object_to_local(const Cluster& c) {
  Affine3 a;
  a.linear = glm::transpose(c.axes);
  a.translation = -(a.linear * c.centre);
  return a;
}

} // namespace masq
