#include "bvh/twolevel/build_accel.h"
#include "bvh/binary/builder.h"
#include "bvh/binary/parallel.h"
#include "bvh/bounds/clip_bounds.h"
#include "bvh/twolevel/cluster_blas.h"
#include "bvh/twolevel/masq_fits.h"
#include "bvh/twolevel/entry_order.h"
#include "bvh/nodes/compact_instance.h"
#include "bvh/bounds/obb.h"
#include "bvh/bounds/prim_bounds.h"
#include "bvh/twolevel/structure_cost.h"
#include "bvh/nodes/wide_bvh.h"
#include "scenes/prim_table.h"
#include "masq/error.h"
#include <algorithm>
#include <chrono>
#include <cstring>
#include <map>
#include <optional>
#include <span>
#include <utility>

namespace masq {

namespace {

Aabb triangle_box(const Geometry& g, const glm::uvec3& t) {
  Aabb b;
  for (int k = 0; k < 3; ++k) b.grow(glm::dvec3(g.vertices[t[k]]));
  return b;
}

Aabb transform_box(const Aabb& b, const Affine3& xf) {
  Aabb out;
  for (int i = 0; i < 8; ++i)
    out.grow(xf.apply_point({i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z}));
  return out;
}

kernel::Instance make_instance(const Mat3x4f& world_to_object, int blas_root, int geom, int prim, int scene_inst) {
  kernel::Instance k{};
  std::memcpy(k.world_to_object, world_to_object.data(), sizeof(k.world_to_object));
  k.blas_root = blas_root;
  k.geom = geom;
  k.prim = prim;
  k.scene_inst = scene_inst;
  return k;
}

void pack_primitives(const Scene& scene, PackedScene& ps) {
  for (const Geometry& g : scene.geometries) {
    const ScenePrimRow& row = scene_prim_row(g.type);
    kernel::Geometry kg{};
    kg.type = row.kernel_type;
    kg.count = int(g.primitive_count());
    kg.first = row.pack(g, ps);
    ps.geoms.push_back(kg);
  }
}

// The binary BLAS of geometry g over the primitives ids (item i is ids[i]); `references`
// gets its leaf reference count. Nothing for an empty ids.
void build_geometry_blas(const Geometry& g, const std::vector<std::int32_t>& ids, const AccelOptions& opt,
                         BinaryBvh& bvh, std::size_t& references) {
  if (ids.empty()) return;
  HugePageVector<Aabb> boxes(ids.size());
  parallel_chunks(ids.size(), 4096, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      std::size_t p = std::size_t(ids[i]);
      boxes[i] = scene_prim_row(g.type).mesh ? triangle_box(g, g.triangles[p]) : hull_box(ball_hull(g, p));
    }
  });
  // Spatial splits clip the primitive itself (object space), item i being ids[i].
  PrimClipper clip = [&](int item, int axis, double lo, double hi) {
    return clip_primitive(g, std::size_t(ids[std::size_t(item)]), axis, lo, hi);
  };
  SahOptions blas_sah = opt.sah;
  if (builder_prices_isect(opt.builder.kind)) blas_sah.intersection_cost *= blas_isect_price(scene_prim_row(g.type).kernel_type);
  bvh = build_blas_binary(boxes, clip, blas_sah, opt.builder, &references);
}

// The clusterings auto's candidates share: per (cluster size, orientation classes), per
// geometry, what make_clusters gave (kept from the cluster candidate's plans, whose
// clusters are exactly that; the mix keeps only some). The cluster shapes of one size
// differ in the leaf price of their BLAS alone, and the mix clusters as the first shape.
// So the first cluster shape of a size builds its clusters' BLAS for every leaf price
// of that size at once (`leaf_prices`, in the order the shapes build), and the later
// shapes take theirs (`blas`); the last one frees them.
// Every size's clustering starts from the same orientation classes (assign_classes: one
// look at every hull), made once per geometry before the candidates build. The hulls
// make_clusters read (`hulls`) serve the first shape's BLAS and the mix's plan, and go
// when those are done.
struct SharedClusterings {
  using Shape = std::pair<int, int>; // (cluster size, orientation classes)
  std::vector<std::optional<ClassAssignment>> classes; // per geometry, of the shapes' class count
  std::map<Shape, std::vector<std::optional<std::vector<Cluster>>>> by_shape;
  std::map<Shape, std::vector<std::optional<ClusterHulls>>> hulls; // per geometry
  Shape mix_shape; // the clustering the mix plans with (the given options')
  std::map<Shape, std::vector<double>> leaf_prices;
  std::map<Shape, std::vector<std::optional<std::vector<ClusterBlas>>>> blas; // per geometry
};

// Geometry gi's cluster instances; with `shared` (a cluster candidate of auto, whose
// clusters are its size's whole clustering, and whose size auto_candidates gave its leaf
// prices and BLAS slots) its BLAS from the ones that size's first shape built for every
// leaf price.
// Without `shared`, `hulls`: the clusters' member hulls, when the plan has them.
void append_clusters(const Scene& scene, int gi, const std::vector<Cluster>& clusters, const std::vector<int>& insts,
                     const AccelOptions& opt, SharedClusterings* shared, const ClusterHulls* hulls, PackedScene& ps,
                     HugePageVector<Aabb>& inst_boxes) {
  if (!shared) {
    append_cluster_instances(scene, gi, clusters, insts, opt.sah, opt.cluster.leaf_price, opt.builder, ps, inst_boxes,
                             hulls);
    return;
  }
  const SharedClusterings::Shape shape{opt.cluster.max_size, opt.cluster.classes};
  const std::vector<double>& prices = shared->leaf_prices.at(shape);
  const std::size_t index = std::size_t(std::find(prices.begin(), prices.end(), opt.cluster.leaf_price) - prices.begin());
  if (index == prices.size()) throw Error("accel: a cluster shape auto did not plan");
  std::optional<std::vector<ClusterBlas>>& built = shared->blas.at(shape).at(std::size_t(gi));
  if (!built) {
    std::optional<ClusterHulls>& read = shared->hulls.at(shape).at(std::size_t(gi));
    built = build_cluster_blases(scene, gi, clusters, insts, opt.sah, prices, opt.builder, ps, read ? &*read : nullptr);
    if (shape != shared->mix_shape) read.reset(); // (the mix reads its shape's later)
  }
  append_cluster_instances(gi, clusters, insts, *built, index, ps, inst_boxes);
  if (index + 1 == prices.size()) built.reset();
}

// Whether every geometry's plan keeps all its primitives in its BLAS, as Method::Ref's
// plan does (a mix that chose ref everywhere: the bear's capsules, for one).
bool plans_are_ref(const Scene& scene, const std::vector<GeometryPlan>& plans) {
  for (std::size_t gi = 0; gi < plans.size(); ++gi) {
    const GeometryPlan& p = plans[gi];
    if (!p.masq_prims.empty() || !p.clusters.empty()) return false;
    if (!p.blas_prims.empty() && p.blas_prims.size() != scene.geometries[gi].primitive_count()) return false;
  }
  return true;
}

// One method's structure; for Method::Auto the per-cluster mix of bvh/twolevel/method_plan.cpp.
// shared (auto's candidates): clusterings to reuse, and to add this build's to.
// price: fill stats.model_cost and model_triangles (auto's candidates, which are chosen by
// them); a plain build skips the walk (a tenth of the bear's masquerade build).
// plan_is_ref (auto's mix, which has ref's structure already): set when the mix's plan
// turns out to be ref's, and then nothing is built (an empty structure is returned).
PackedScene build_planned(const Scene& scene, Method method, const AccelOptions& opt, bool price,
                          SharedClusterings* shared = nullptr, bool* plan_is_ref = nullptr) {
  auto start = std::chrono::steady_clock::now();
  auto seconds_since_start = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };

  // What goes where, per geometry (bvh/twolevel/method_plan.h).
  PlanOptions plan_opt;
  plan_opt.cluster = opt.cluster;
  plan_opt.curve_obb = opt.curve_obb;
  plan_opt.prices = kMixPlannerPrices;
  std::vector<std::vector<int>> insts_of(scene.geometries.size());
  for (std::size_t si = 0; si < scene.instances.size(); ++si) insts_of[scene.instances[si].geometry].push_back(int(si));
  std::vector<GeometryPlan> plans(scene.geometries.size());
  // (Sized before the parallel loop, which then touches only its own geometry's entry.)
  std::vector<std::optional<std::vector<Cluster>>>* clusterings = nullptr;
  std::vector<std::optional<ClusterHulls>>* clustering_hulls = nullptr; // beside clusterings
  if (shared && (method == Method::Cluster || method == Method::Auto)) {
    // (auto_candidates made the slots of every shape it builds: only looked up here.)
    const SharedClusterings::Shape shape{opt.cluster.max_size, opt.cluster.classes};
    auto it = shared->by_shape.find(shape);
    if (it != shared->by_shape.end() && it->second.size() == scene.geometries.size()) {
      clusterings = &it->second;
      clustering_hulls = &shared->hulls.at(shape);
    }
  }
  parallel_chunks(scene.geometries.size(), 1, [&](std::size_t g0, std::size_t g1) {
    for (std::size_t gi = g0; gi < g1; ++gi) {
      if (insts_of[gi].empty() || scene.geometries[gi].primitive_count() == 0) continue;
      std::optional<std::vector<Cluster>>* known = clusterings ? &(*clusterings)[gi] : nullptr;
      std::optional<ClusterHulls>* known_hulls = clustering_hulls ? &(*clustering_hulls)[gi] : nullptr;
      // The first cluster shape of a size clusters every clusterable geometry (those
      // auto_candidates assigned classes to), and the later ones take its clusters.
      if (known && !*known && method == Method::Cluster && shared->classes[gi])
        *known = make_clusters(scene.geometries[gi], every_primitive(scene.geometries[gi]), opt.cluster,
                               &*shared->classes[gi], &known_hulls->emplace());
      plans[gi] = plan_geometry(scene.geometries[gi], method, plan_opt, known && *known ? &**known : nullptr,
                                known_hulls && *known_hulls ? &**known_hulls : nullptr);
      // The mix, the last to read this size's hulls, has copied those of the clusters it keeps.
      if (method == Method::Auto && known_hulls) known_hulls->reset();
    }
  });
  if (method == Method::Auto && plan_is_ref && plans_are_ref(scene, plans)) {
    *plan_is_ref = true;
    return {};
  }

  PackedScene ps;
  ps.method = method;
  ps.builder = opt.builder.kind;
  pack_primitives(scene, ps);
  ps.features.mode = opt.mode;
  ps.features.curve_iters = opt.curve_iters;
  ps.features.curve_isect = opt.curve_isect;
  ps.features.nodes = opt.nodes; // before any node is appended (cluster BLAS read it)
  ps.features.tlas_stack.entries = 0; // the trees' needs, as they are appended
  ps.features.blas_stack.entries = 0;
  ps.stats.cluster_size = opt.cluster.max_size;
  ps.stats.cluster_leaf_price = opt.cluster.leaf_price;
  for (const Instance& inst : scene.instances) {
    ps.features.prims[std::size_t(scene_prim_row(scene.geometries[inst.geometry].type).kernel_type)] = true;
    Affine3 w2o = inverse(inst.object_to_world);
    kernel::Frame f{};
    Mat3x4f m = to_mat3x4f(w2o);
    std::memcpy(f.world_to_object, m.data(), sizeof(f.world_to_object));
    ps.frames.push_back(f);
    ps.frame_object_to_world.push_back(to_mat3x4f(inst.object_to_world));
  }

  // The ordinary BLAS of each geometry over the primitives its plan keeps there.
  std::vector<int> blas_root(scene.geometries.size(), -1);
  bool blas_root_oriented = false; // o4: a rotated BLAS root needs the TLAS's exit bound
  std::vector<Aabb> blas_box(scene.geometries.size());
  ps.geometry_leaf_order.resize(scene.geometries.size());
  // The binary BLAS of all geometries at once (each in its own slot), then their wide
  // nodes appended in geometry order (the collapse appends to the shared arrays).
  std::vector<BinaryBvh> blas(scene.geometries.size());
  std::vector<std::size_t> blas_refs(scene.geometries.size(), 0);
  parallel_chunks(scene.geometries.size(), 1, [&](std::size_t g0, std::size_t g1) {
    for (std::size_t gi = g0; gi < g1; ++gi)
      build_geometry_blas(scene.geometries[gi], plans[gi].blas_prims, opt, blas[gi], blas_refs[gi]);
  });
  for (std::size_t gi = 0; gi < scene.geometries.size(); ++gi) {
    const std::vector<std::int32_t>& ids = plans[gi].blas_prims;
    if (ids.empty()) continue;
    const BinaryBvh& bvh = blas[gi];
    const std::size_t references = blas_refs[gi];
    const NodeFraming framing{[&](std::int32_t p) { return prim_hull(ps, int(gi), p); }, opt.oriented_gain};
    WideBvhInfo info = append_bvh_nodes(bvh, ids, opt.nodes, ps, &framing);
    blas_root_oriented = blas_root_oriented || info.root_oriented;
    blas_root[gi] = info.root;
    blas_box[gi] = bvh.nodes[0].box;
    ps.stats.blas_references += references;
    ps.stats.blas_primitives += ids.size();
    // The driver's submission order (rayquery) names each primitive once: spatial
    // splits may put one in several leaves; its first leaf decides.
    std::vector<char> seen(ids.size(), 0);
    for (int i : bvh.order)
      if (!seen[std::size_t(i)]) {
        seen[std::size_t(i)] = 1;
        ps.geometry_leaf_order[gi].push_back(ids[std::size_t(i)]);
      }
    ps.stats.blas_nodes += info.nodes;
    ps.stats.oriented_nodes += info.oriented;
    ps.stats.blas_leaves += info.leaves;
    ps.stats.blas_sah_cost += info.sah_cost;
    ps.stats.max_depth = std::max(ps.stats.max_depth, info.depth);
    ps.features.blas_stack.entries = std::max(ps.features.blas_stack.entries, info.kernel_stack);
  }

  // TLAS entries: per scene instance its BLAS and masquerade instances, then per
  // geometry its cluster instances (their BLAS are shared by the scene instances); the
  // compact masquerade entries come last (entry ids: PackedScene::tlas_ref).
  HugePageVector<Aabb> inst_boxes;
  HugePageVector<Aabb> compact_boxes;
  HugePageVector<Mat3x4f> compact_unit_to_world;
  std::map<std::pair<int, int>, std::uint32_t> owner_of; // (geometry, scene instance) -> owner
  // Room for every entry at once: growing arrays of a million masquerade entries by
  // doubling cost as much as filling them.
  std::size_t entries = scene.instances.size();
  for (const Instance& inst : scene.instances) entries += plans[inst.geometry].masq_prims.size();
  inst_boxes.reserve(entries);
  ps.instance_object_to_world.reserve(entries);
  if (opt.masq_instances == MasqInstances::Compact) {
    compact_boxes.reserve(entries);
    compact_unit_to_world.reserve(entries);
    ps.masq_instances.reserve(entries);
  } else {
    ps.instances.reserve(entries);
  }
  const std::size_t owner_limit = std::size_t(std::clamp(opt.masq_owner_limit, 0, MASQ_MAX_OWNERS));
  // The fits in blocks (computed on all threads), appended in primitive order; one
  // block's buffer for them all (bvh/twolevel/masq_fits.h). A block is just over one huge
  // page of fits (5,826), so that a large scene's buffer comes from the kept huge mappings
  // (scenes/huge_page_vector.h): 4,096 fits (1.4 MiB) came from malloc and were faulted
  // in afresh at every build (perf: the page faults of 6% of a build of Ratboy's
  // masquerade).
  constexpr std::size_t kFitBlock = (kHugePageBytes + sizeof(MasqFit) - 1) / sizeof(MasqFit);
  HugePageVector<MasqFit> fits;
  for (std::size_t si = 0; si < scene.instances.size(); ++si) {
    const Instance& inst = scene.instances[si];
    const Geometry& g = scene.geometries[inst.geometry];
    int gi = int(inst.geometry);
    if (blas_root[gi] >= 0) {
      Mat3x4f w2o;
      std::memcpy(w2o.data(), ps.frames[si].world_to_object, sizeof(float) * 12);
      ps.instances.push_back(make_instance(w2o, blas_root[gi], gi, -1, int(si)));
      ps.instance_object_to_world.push_back(ps.frame_object_to_world[si]);
      inst_boxes.push_back(transform_box(blas_box[gi], inst.object_to_world));
    }
    const std::vector<std::int32_t>& masq_prims = plans[std::size_t(gi)].masq_prims;
    if (masq_prims.empty()) continue;
    // Compact entries name their (geometry, scene instance) pair's owner index, made on
    // the pair's first primitive while there is room.
    std::optional<std::uint32_t> owner;
    if (opt.masq_instances == MasqInstances::Compact) {
      auto it = owner_of.find({gi, int(si)});
      if (it == owner_of.end() && owner_of.size() < owner_limit) {
        it = owner_of.emplace(std::pair<int, int>{gi, int(si)}, std::uint32_t(ps.masq_owners.size())).first;
        ps.masq_owners.push_back({gi, int(si), {0, 0}});
      }
      if (it != owner_of.end()) owner = it->second;
    }
    for (std::size_t b = 0; b < masq_prims.size(); b += kFitBlock) {
      std::span<const std::int32_t> block(masq_prims.data() + b, std::min(kFitBlock, masq_prims.size() - b));
      fits.resize(std::max(fits.size(), block.size()));
      fit_masquerades(g, block, inst.object_to_world, opt.curve_obb, owner.has_value(),
                      std::span<MasqFit>(fits).first(block.size()));
      for (std::size_t i = 0; i < block.size(); ++i) {
        std::int32_t p = block[i];
        if (std::optional<CompactMasquerade>& cm = fits[i].compact) { // else: a 64-byte Instance below
          set_masq_owner(cm->inst, *owner);
          ps.stats.obb_area += cm->box.obb_area;
          ps.stats.aabb_area += cm->box.aabb_area;
          ps.stats.masq_prims += 1;
          ps.masq_instances.push_back(cm->inst);
          compact_unit_to_world.push_back(cm->box.unit_to_world);
          compact_boxes.push_back(cm->box.world_box);
          continue;
        }
        const MasqueradeBox& mb = fits[i].full;
        ps.stats.obb_area += mb.obb_area;
        ps.stats.aabb_area += mb.aabb_area;
        ps.stats.masq_prims += 1;
        ps.instances.push_back(make_instance(mb.world_to_unit, -1, gi, int(p), int(si)));
        ps.instance_object_to_world.push_back(mb.unit_to_world);
        inst_boxes.push_back(mb.world_box);
      }
    }
  }
  for (std::size_t gi = 0; gi < scene.geometries.size(); ++gi)
    if (!plans[gi].clusters.empty()) {
      const ClusterHulls* hulls = plans[gi].cluster_hulls.empty() ? nullptr : &plans[gi].cluster_hulls;
      append_clusters(scene, int(gi), plans[gi].clusters, insts_of[gi], opt, method == Method::Cluster ? shared : nullptr,
                      hulls, ps, inst_boxes);
    }
  if (ps.masq_instances.size() > std::size_t(INT32_MAX) - ps.instances.size())
    throw Error("accel: more than 2^31-1 TLAS entries");
  inst_boxes.insert(inst_boxes.end(), compact_boxes.begin(), compact_boxes.end());
  ps.instance_object_to_world.insert(ps.instance_object_to_world.end(), compact_unit_to_world.begin(),
                                     compact_unit_to_world.end());
  ps.stats.instances = ps.tlas_entry_count();
  if (!inst_boxes.empty()) {
    // A TLAS of compact masquerade entries alone: the cpu tests a leaf's unit boxes four
    // at a time (kernels/masq_entry_simd_cpp.h), so the builder's leaf block prices its
    // leaves as a BLAS leaf over primitives is priced. Instances (BLAS, cluster and
    // 64-byte masquerade) are transformed one at a time and keep the per-entry price.
    SahOptions tlas_sah = opt.sah;
    if (ps.instances.empty()) tlas_sah.leaf_block = builder_leaf_block(opt.builder.kind);
    BinaryBvh tlas = build_boxes_binary(inst_boxes, tlas_sah, opt.builder);
    std::vector<std::int32_t> ids(inst_boxes.size()); // the leaves' references (entry e: tlas_ref(e))
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = ps.tlas_ref(i);
    const std::size_t first_tlas_ref = ps.refs.size();
    WideBvhInfo info = append_bvh_nodes(tlas, ids, opt.nodes, ps);
    ps.tlas_root = info.root;
    ps.tlas_leaf_order.assign(tlas.order.begin(), tlas.order.end());
    order_compact_entries_by_leaves(ps, first_tlas_ref);
    ps.stats.tlas_nodes = info.nodes;
    ps.stats.tlas_leaves = info.leaves;
    ps.stats.sah_cost = info.sah_cost;
    ps.stats.max_depth += info.depth;
    ps.features.tlas_stack.entries = info.kernel_stack;
  }
  // A single BLAS under an identity instance: the kernels skip the TLAS stage and the
  // ray transform (the TLAS is still built, for the rayquery backend and the stats).
  // Not for a cluster instance: its transform is the cluster's frame, not the scene's.
  // Not for a rotated o4 root: its padding grows with t, and the TLAS box's exit
  // distance is what bounds t (kernels/traverse.h).
  ps.features.single_blas = ps.instances.size() == 1 && ps.masq_instances.empty() && ps.instances[0].blas_root >= 0 &&
                            ps.instances[0].prim != MASQ_INST_CLUSTER && !blas_root_oriented &&
                            scene.instances[ps.instances[0].scene_inst].object_to_world.is_identity();
  // Masquerade entries: a TLAS box is one primitive's, so the boxes an occlusion query
  // starts in are the primitive it starts on and its neighbours, which it mostly leaves;
  // it tests them last (kernels/child_order.h). Clusters and BLAS instances keep the
  // nearest-first order: their box around the origin holds the likely occluders too.
  // Inside each BLAS the order is the caller's (AccelOptions::blas_occlusion).
  ps.features.tlas_starts_last = !ps.masq_instances.empty();
  ps.features.blas_starts_last = opt.blas_occlusion == BlasOcclusion::StartsLast;
  ps.stats.node_bytes = ps.node_bytes();
  if (price) {
    StructureCost sc = structure_cost(ps, opt.prices);
    ps.stats.model_cost = sc.total;
    ps.stats.model_triangles = sc.triangles;
  }
  ps.stats.build_seconds = seconds_since_start();
  return ps;
}

} // namespace

std::vector<ClusterOptions> auto_cluster_shapes(const ClusterOptions& given) {
  std::vector<ClusterOptions> out = {given};
  for (int size : {given.max_size, kAutoLargeCluster})
    for (double price : {given.leaf_price, 1.0}) {
      ClusterOptions c = given;
      c.max_size = size;
      c.leaf_price = price;
      bool seen = std::any_of(out.begin(), out.end(),
                              [&](const ClusterOptions& o) { return o.max_size == size && o.leaf_price == price; });
      if (!seen) out.push_back(c);
    }
  return out;
}

namespace {

void check_accel_input(const Scene& scene, const AccelOptions& opt) {
  if (opt.curve_iters < 1 || opt.curve_iters > 64)
    throw Error("accel: curve_iters " + std::to_string(opt.curve_iters) + " outside 1..64");
  validate_scene(scene);
  if (scene.primitive_count() > std::size_t(INT32_MAX) / 2)
    throw Error("scene: " + std::to_string(scene.primitive_count()) + " primitives exceed the 32-bit index range");
}

} // namespace

namespace {

AutoCandidates auto_candidates(const Scene& scene, const AccelOptions& opt) {
  check_accel_input(scene, opt);
  auto start = std::chrono::steady_clock::now();
  AutoCandidates out;
  auto build = [&](Method m, const ClusterOptions& shape, SharedClusterings* shared, bool* plan_is_ref = nullptr) {
    AccelOptions one = opt;
    one.cluster = shape;
    return build_planned(scene, m, one, true, shared, plan_is_ref);
  };
  // Triangles stay in a BLAS under every method: a mesh has one candidate, ref's.
  bool thin = std::any_of(scene.geometries.begin(), scene.geometries.end(),
                          [](const Geometry& g) { return !scene_prim_row(g.type).mesh && g.primitive_count() > 0; });
  if (!thin) {
    out.built.push_back(build(Method::Ref, opt.cluster, nullptr));
    out.costs.fill(out.built[0].stats.model_cost);
  } else {
    // The cluster candidate in several shapes, the cheapest by the model standing for
    // it: how many members a cluster takes and how full its leaves are decide between
    // transforms, node visits and intersector calls, and which wins depends on the
    // scene (a bundle of parallel strands wants a few large clusters, fur many small
    // ones; docs/methods.md).
    const std::vector<ClusterOptions> shapes = auto_cluster_shapes(opt.cluster);
    std::vector<PackedScene> shaped(shapes.size());
    PackedScene ref, masq, mix;
    // The candidates build in two groups at once (each build is parallel inside too, but
    // keeps about 1.3 of two threads busy: its serial stretches). A clustering is made by
    // the first shape of its size and reused by the rest, so each size's shapes stay in
    // one group, in order: the given size's, then ref, then the mix, which reuses that
    // clustering (and stops where its plan is ref's); the others with masq.
    // Every size's slots exist before the groups start, so the groups only look them up.
    // Each candidate is the one a serial build makes, and the choice below reads them in
    // the serial order.
    SharedClusterings shared;
    shared.classes.resize(scene.geometries.size());
    shared.mix_shape = {opt.cluster.max_size, opt.cluster.classes};
    std::vector<bool> instanced(scene.geometries.size(), false);
    for (const Instance& inst : scene.instances) instanced[std::size_t(inst.geometry)] = true;
    for (std::size_t gi = 0; gi < scene.geometries.size(); ++gi) {
      const Geometry& g = scene.geometries[gi];
      const ScenePrimRow& row = scene_prim_row(g.type);
      if (instanced[gi] && !row.mesh && row.oriented && g.primitive_count() > 0)
        shared.classes[gi] = assign_classes(g, every_primitive(g), opt.cluster.classes);
    }
    for (const ClusterOptions& c : shapes) {
      shared.by_shape[{c.max_size, c.classes}].resize(scene.geometries.size());
      shared.hulls[{c.max_size, c.classes}].resize(scene.geometries.size());
      shared.leaf_prices[{c.max_size, c.classes}].push_back(c.leaf_price);
      shared.blas[{c.max_size, c.classes}].resize(scene.geometries.size());
    }
    auto given_size = [&](const ClusterOptions& c) {
      return c.max_size == opt.cluster.max_size && c.classes == opt.cluster.classes;
    };
    parallel_pair(
        [&] {
          for (std::size_t k = 0; k < shapes.size(); ++k)
            if (given_size(shapes[k])) shaped[k] = build(Method::Cluster, shapes[k], &shared);
          ref = build(Method::Ref, opt.cluster, &shared);
          mix = build(Method::Auto, opt.cluster, &shared, &out.mix_is_ref);
        },
        [&] {
          masq = build(Method::Masq, opt.cluster, &shared);
          for (std::size_t k = 0; k < shapes.size(); ++k)
            if (!given_size(shapes[k])) shaped[k] = build(Method::Cluster, shapes[k], &shared);
        });
    std::size_t cheapest = 0;
    for (std::size_t k = 1; k < shaped.size(); ++k)
      if (shaped[k].stats.model_cost < shaped[cheapest].stats.model_cost) cheapest = k;
    for (const PackedScene& c : shaped) out.cluster_shape_costs.push_back(c.stats.model_cost);
    // A mix whose plan is ref's is ref's structure: priced as ref, and not a candidate of
    // its own (it could never be kept: model_choice and the pilot keep the earlier ref
    // over an equal later one), nor built or copied.
    if (out.mix_is_ref) out.costs[std::size_t(Method::Auto)] = ref.stats.model_cost;
    for (PackedScene* c : {&ref, &masq, &shaped[cheapest], &mix}) {
      if (c == &mix && out.mix_is_ref) continue;
      out.costs[std::size_t(c->method)] = c->stats.model_cost;
      out.built.push_back(std::move(*c));
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

} // namespace

AutoCandidates build_auto_candidates(const Scene& scene, const AccelOptions& opt) {
  AutoCandidates out;
  run_with_build_threads(opt.build_threads, [&] { out = auto_candidates(scene, opt); });
  return out;
}

std::size_t model_choice(const AutoCandidates& c) {
  // The lowest model cost, ties to the earlier (ref, masq, cluster, mix), compared
  // without the triangles' share, which every candidate has alike. A candidate other
  // than ref must be cheaper than ref by kAutoMargin: within that the model cannot tell
  // them apart (docs/methods.md).
  constexpr double kAutoMargin = 0.10;
  std::size_t best = 0;
  double best_key = 0;
  for (std::size_t i = 0; i < c.built.size(); ++i) {
    const PackedScene& p = c.built[i];
    double key = p.stats.model_cost - p.stats.model_triangles;
    if (p.method != Method::Ref) key /= 1.0 - kAutoMargin;
    if (i == 0 || key < best_key) {
      best = i;
      best_key = key;
    }
  }
  return best;
}

void mark_as_auto(PackedScene& kept, const AutoCandidates& c) {
  kept.stats.auto_choice = kept.method;
  kept.method = Method::Auto;
  kept.stats.auto_candidates = c.costs;
  kept.stats.build_seconds = c.seconds;
}

PackedScene build_accel(const Scene& scene, Method method, const AccelOptions& opt) {
  PackedScene out;
  run_with_build_threads(opt.build_threads, [&] {
    if (method != Method::Auto || opt.auto_select == AutoSelect::MixOnly) {
      check_accel_input(scene, opt);
      out = build_planned(scene, method, opt, method == Method::Auto);
      return;
    }
    // auto: build every candidate whole and keep the one the structure cost model prices
    // lowest. The per-cluster mix alone misjudges sparse scenes, where what an instance
    // does to the TLAS decides (docs/methods.md); the whole structures show it.
    AutoCandidates c = auto_candidates(scene, opt);
    out = std::move(c.built[model_choice(c)]);
    mark_as_auto(out, c);
  });
  return out;
}

} // namespace masq
