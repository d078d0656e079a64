#include "bvh/bv/bv_scene.h"
#include "bvh/twolevel/build_accel.h"
#include "bvh/bv/bv_fit.h"
#include "bvh/bounds/obb.h"
#include "bvh/bv/obb_sweep_bvh.h"
#include "kernels/variants.h"
#include "masq/error.h"
#include <chrono>
#include <cmath>

namespace masq {

int bv_type_kernel_id(BvType t) {
  switch (t) {
    case BvType::Aabb: return MASQ_BV_AABB;
    case BvType::Sphere: return MASQ_BV_SPHERE;
    case BvType::Obb: return MASQ_BV_OBB;
    case BvType::Scb: return MASQ_BV_SCB;
  }
  return -1;
}

std::size_t BvScene::node_count() const { return bv_aabb.size() + bv_sphere.size() + bv_obb.size() + bv_scb.size(); }

std::size_t BvScene::node_bytes() const {
  return bv_aabb.size() * sizeof(kernel::BvNodeAabb) + bv_sphere.size() * sizeof(kernel::BvNodeSphere) +
         bv_obb.size() * sizeof(kernel::BvNodeObb) + bv_scb.size() * sizeof(kernel::BvNodeScb) +
         bv_prims.size() * sizeof(kernel::BvPrimRef);
}

namespace {

// sqrt of a Gershgorin bound on the largest eigenvalue of L^T L: >= sigma_max(L), and
// exact for rotations times a uniform scale.
double sigma_max_bound(const glm::dmat3& l) {
  glm::dmat3 g = glm::transpose(l) * l;
  double best = 0;
  for (int r = 0; r < 3; ++r) best = std::max(best, std::fabs(g[0][r]) + std::fabs(g[1][r]) + std::fabs(g[2][r]));
  return std::sqrt(best) * (1.0 + 1e-14);
}

} // namespace

WorldPrims world_prims(const PackedScene& ps) {
  WorldPrims w;
  // Every (frame, geometry) pair the packing placed: frames are per scene instance and
  // the ref packing made one TLAS instance per scene instance, naming its geometry.
  for (const kernel::Instance& inst : ps.instances) {
    const int si = inst.scene_inst, gi = inst.geom;
    Mat3x4f m;
    std::copy(std::begin(ps.frames[std::size_t(si)].world_to_object), std::end(ps.frames[std::size_t(si)].world_to_object),
              m.begin());
    Affine3 o2w = inverse(from_mat3x4f(m));
    const double scale = sigma_max_bound(o2w.linear);
    const kernel::Geometry& g = ps.geoms[std::size_t(gi)];
    for (int p = 0; p < g.count; ++p) {
      BallHull h = prim_hull(ps, gi, p); // a triangle: its vertices
      for (int k = 0; k < h.count; ++k) {
        h.centre[k] = o2w.apply_point(h.centre[k]);
        h.radius[k] *= scale;
      }
      w.hulls.push_back(h);
      w.refs.push_back({gi, p, si, 0});
    }
  }
  return w;
}

struct BvTopology {
  PackedScene prims;
  FlatTree tree;
  std::vector<BallHull> ordered; // hull of tree.order[i]
  std::vector<kernel::BvPrimRef> refs;
  double seconds = 0;
};

void BvTopologyDeleter::operator()(BvTopology* t) const { delete t; }

double bv_topology_seconds(const BvTopology& topo) { return topo.seconds; }

BvTopologyPtr build_bv_topology(const Scene& scene, const BvOptions& opt) {
  auto t0 = std::chrono::steady_clock::now();
  BvTopologyPtr topo(new BvTopology);
  AccelOptions ao;
  ao.sah = opt.sah;
  topo->prims = build_accel(scene, Method::Ref, ao);
  WorldPrims wp = world_prims(topo->prims);
  topo->prims.nodes.clear();
  topo->prims.refs.clear();
  topo->prims.tlas_root = -1;
  if (wp.hulls.empty()) throw Error("bv: scene '" + scene.name + "' has no primitives");
  BinaryBvh bin;
  if (opt.builder == BvBuilder::ObbSweep) {
    bin = build_obb_sweep(wp.hulls, opt.sah);
  } else {
    std::vector<Aabb> boxes;
    boxes.reserve(wp.hulls.size());
    for (const BallHull& h : wp.hulls) boxes.push_back(hull_box(h));
    bin = build_binned_sah(boxes, opt.sah);
  }
  topo->tree = flatten(bin);
  // The traversal stack (kernels/bv_traverse.h) holds, below a node of level l (the root
  // is level 1), one waiting sibling per level above and the node's two children: at most
  // l + 1 entries for an inner node, which is at most the number of levels.
  topo->prims.features.blas_stack = {topo->tree.depth, "bounding-volume tree"};
  if (topo->tree.depth > MASQ_STACK_MAX)
    throw Error("bv: tree depth " + std::to_string(topo->tree.depth) + " exceeds the kernels' largest stack of " +
                std::to_string(MASQ_STACK_MAX) + " entries");
  topo->ordered.reserve(topo->tree.order.size());
  for (int id : topo->tree.order) {
    topo->ordered.push_back(wp.hulls[std::size_t(id)]);
    topo->refs.push_back(wp.refs[std::size_t(id)]);
  }
  topo->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return topo;
}

BvScene fit_bv_scene(const BvTopology& topo, const BvOptions& opt) {
  auto t0 = std::chrono::steady_clock::now();
  BvScene bs;
  bs.type = opt.type;
  bs.prims = topo.prims;
  bs.bv_prims = topo.refs;
  const FlatTree& t = topo.tree;
  switch (opt.type) {
    case BvType::Aabb: bs.bv_aabb = fit_aabb_nodes(t, topo.ordered); break;
    case BvType::Sphere: bs.bv_sphere = fit_sphere_nodes(t, topo.ordered); break;
    case BvType::Obb: bs.bv_obb = fit_obb_nodes(t, topo.ordered); break;
    case BvType::Scb: bs.bv_scb = fit_scb_nodes(t, topo.ordered, opt.scb_p); break;
  }
  bs.stats.nodes = t.nodes.size();
  for (const FlatTree::Node& n : t.nodes) bs.stats.leaves += n.count > 0;
  bs.stats.depth = t.depth;
  bs.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return bs;
}

BvScene build_bv_scene(const Scene& scene, const BvOptions& opt) {
  BvTopologyPtr topo = build_bv_topology(scene, opt);
  BvScene bs = fit_bv_scene(*topo, opt);
  bs.stats.build_seconds += topo->seconds;
  return bs;
}

} // namespace masq
