#include "bvh/packed_scene.h"
#include "bvh/compact_instance.h"
#include "bvh/obb.h"
#include "scenes/error.h"
#include <algorithm>

namespace masq {

int node_format_id(NodeFormat f) {
  switch (f) {
    case NodeFormat::W4: return MASQ_NODES_W4;
    case NodeFormat::W8: return MASQ_NODES_W8;
    case NodeFormat::Q8: return MASQ_NODES_Q8;
  }
  return MASQ_NODES_W4;
}

std::size_t node_format_bytes(NodeFormat f) {
  switch (f) {
    case NodeFormat::W4: return sizeof(kernel::WideNode);
    case NodeFormat::W8: return sizeof(kernel::WideNode8);
    case NodeFormat::Q8: return sizeof(kernel::QuantNode8);
  }
  return 0;
}

const void* PackedScene::node_data() const {
  switch (features.nodes) {
    case NodeFormat::W8: return nodes8.data();
    case NodeFormat::Q8: return qnodes.data();
    default: return nodes.data();
  }
}

std::size_t PackedScene::node_count() const {
  switch (features.nodes) {
    case NodeFormat::W8: return nodes8.size();
    case NodeFormat::Q8: return qnodes.size();
    default: return nodes.size();
  }
}

std::size_t PackedScene::node_bytes() const { return node_count() * node_format_bytes(features.nodes); }

std::size_t PackedScene::acceleration_bytes() const {
  return node_bytes() + refs.size() * sizeof(std::int32_t) + instances.size() * sizeof(kernel::Instance) +
         masq_instances.size() * sizeof(kernel::MasqInstance) + masq_owners.size() * sizeof(kernel::MasqOwner) +
         frames.size() * sizeof(kernel::Frame);
}

std::int32_t PackedScene::tlas_ref(std::size_t entry) const {
  if (entry < instances.size()) return std::int32_t(entry);
  return ~std::int32_t(entry - instances.size());
}

std::size_t PackedScene::tlas_entry(std::int32_t ref) const {
  return ref >= 0 ? std::size_t(ref) : instances.size() + std::size_t(~ref);
}

kernel::Instance PackedScene::entry_instance(std::size_t entry) const {
  if (entry < instances.size()) return instances[entry];
  if (entry - instances.size() >= masq_instances.size())
    throw Error("scene: TLAS entry " + std::to_string(entry) + " of " + std::to_string(tlas_entry_count()));
  const kernel::MasqInstance& c = masq_instances[entry - instances.size()];
  const std::size_t owner = c.s2_owner & MASQ_OWNER_MASK;
  if (owner >= masq_owners.size())
    throw Error("scene: compact masquerade entry " + std::to_string(entry - instances.size()) + " names owner " +
                std::to_string(owner) + " of " + std::to_string(masq_owners.size()));
  kernel::Instance k{};
  Mat3x4f m = to_mat3x4f(decode_masq_instance(c));
  std::copy(m.begin(), m.end(), k.world_to_object);
  k.blas_root = -1;
  k.geom = masq_owners[owner].geom;
  k.prim = c.prim;
  k.scene_inst = masq_owners[owner].scene_inst;
  return k;
}

std::size_t PackedScene::primitive_bytes() const {
  return geoms.size() * sizeof(kernel::Geometry) + triangles.size() * sizeof(kernel::Triangle) +
         capsules.size() * sizeof(kernel::Capsule) + cones.size() * sizeof(kernel::RoundCone) +
         spheres.size() * sizeof(kernel::Sphere) + curves.size() * sizeof(kernel::Curve);
}

} // namespace masq
