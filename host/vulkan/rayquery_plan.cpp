#include "host/vulkan/rayquery_plan.h"
#include "bvh/nodes/compact_instance.h"
#include "bvh/nodes/wide_bvh.h"
#include "masq/error.h"
#include <fmt/format.h>
#include <algorithm>

namespace masq::vk {

RayQueryPlan plan_ray_query(const PackedScene& s, std::uint64_t max_primitives, const char* backend) {
  RayQueryPlan plan;
  std::vector<std::vector<std::int32_t>> geom_blas(s.geoms.size()); // per geometry: its BLAS ids
  for (const kernel::Instance& inst : s.instances) {
    if (inst.prim == MASQ_INST_CLUSTER) {
      if (plan.clusters.count(inst.blas_root)) continue;
      plan.clusters[inst.blas_root] = static_cast<std::int32_t>(plan.blas.size());
      plan.blas.push_back({-1, inst.blas_root, 0, 0, s.geoms.at(std::size_t(inst.geom)).type});
    } else if (inst.blas_root >= 0 && geom_blas.at(static_cast<std::size_t>(inst.geom)).empty()) {
      // The geometry's leaf order cut into runs of at most max_primitives (one BLAS each).
      std::size_t n = geometry_leaf_order(s, static_cast<std::size_t>(inst.geom)).size();
      for (std::size_t first = 0; first < std::max<std::size_t>(n, 1); first += max_primitives) {
        geom_blas[static_cast<std::size_t>(inst.geom)].push_back(static_cast<std::int32_t>(plan.blas.size()));
        plan.blas.push_back({inst.geom, -1, first, std::min<std::size_t>(max_primitives, n - first),
                              s.geoms[static_cast<std::size_t>(inst.geom)].type});
      }
    }
  }
  if (sbt_record_count(plan) > (1u << 24))
    throw Error(fmt::format("{}: {} bottom-level structures; SBT record offsets hold 24 bits", backend,
                            plan.blas.size()));
  for (std::int32_t i : s.tlas_leaf_order) {
    const kernel::Instance inst = tlas_entry_instance(s, static_cast<std::size_t>(i)); // compact ones expanded
    if (inst.prim == MASQ_INST_CLUSTER) plan.entries.push_back({i, plan.clusters.at(inst.blas_root)});
    else if (inst.blas_root >= 0)
      for (std::int32_t b : geom_blas[static_cast<std::size_t>(inst.geom)]) plan.entries.push_back({i, b});
    else {
      const int type = s.geoms.at(static_cast<std::size_t>(inst.geom)).type;
      if (type < 0 || type >= MASQ_PRIM_TYPE_COUNT) // its hit record would lie past the table
        throw Error(fmt::format("{}: geometry {} has primitive type {} (expected 0..{})", backend, inst.geom, type,
                                MASQ_PRIM_TYPE_COUNT - 1));
      plan.entries.push_back({i, -1});
      plan.unit_box = true;
    }
  }
  return plan;
}

std::vector<std::int32_t> geometry_leaf_order(const PackedScene& s, std::size_t g) {
  auto n = static_cast<std::size_t>(s.geoms.at(g).count);
  if (g < s.geometry_leaf_order.size() && !s.geometry_leaf_order[g].empty()) {
    const auto& order = s.geometry_leaf_order[g];
    if (order.size() > n)
      throw Error(fmt::format("driver structures: geometry_leaf_order[{}] has {} entries for {} primitives", g, order.size(),
                              n));
    for (std::int32_t p : order)
      if (p < 0 || static_cast<std::size_t>(p) >= n)
        throw Error(fmt::format("driver structures: geometry_leaf_order[{}] holds primitive {} of {}", g, p, n));
    return order;
  }
  std::vector<std::int32_t> id(n);
  for (std::size_t i = 0; i < n; ++i) id[i] = static_cast<std::int32_t>(i);
  return id;
}

std::vector<std::int32_t> cluster_members(const PackedScene& s, int root) {
  std::vector<std::int32_t> out;
  std::vector<int> stack{root};
  while (!stack.empty()) {
    const NodeSlots slots = node_slots(s, stack.back()); // any node format
    stack.pop_back();
    for (const NodeSlot& n : slots) {
      if (n.count == 0) stack.push_back(n.child);
      for (int j = 0; j < n.count; ++j) out.push_back(s.refs.at(static_cast<std::size_t>(n.child + j)));
    }
  }
  return out;
}

std::vector<std::int32_t> primitive_id_map(const PackedScene& s, const RayQueryPlan& plan) {
  std::vector<std::int32_t> map(plan.blas.size());
  for (std::size_t b = 0; b < plan.blas.size(); ++b) {
    const RayQueryPlan::Blas& spec = plan.blas[b];
    if (map.size() > std::size_t(INT32_MAX))
      throw Error(fmt::format("driver structures: the primitive id map has {} entries (over 2^31-1)", map.size()));
    map[b] = static_cast<std::int32_t>(map.size());
    std::vector<std::int32_t> ids = spec.geom >= 0 ? geometry_leaf_order(s, static_cast<std::size_t>(spec.geom))
                                                   : cluster_members(s, spec.root);
    std::size_t first = spec.geom >= 0 ? spec.first : 0;
    std::size_t count = spec.geom >= 0 ? spec.count : ids.size();
    map.insert(map.end(), ids.begin() + std::ptrdiff_t(first), ids.begin() + std::ptrdiff_t(first + count));
  }
  return map;
}

} // namespace masq::vk
