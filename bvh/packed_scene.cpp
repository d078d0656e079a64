#include "bvh/packed_scene.h"
#include "scenes/prim_table.h"
#include "masq/error.h"
#include <algorithm>

namespace masq {

int node_format_id(NodeFormat f) {
  switch (f) {
    case NodeFormat::W4: return MASQ_NODES_W4;
    case NodeFormat::W8: return MASQ_NODES_W8;
    case NodeFormat::Q8: return MASQ_NODES_Q8;
    case NodeFormat::O4: return MASQ_NODES_O4;
  }
  return MASQ_NODES_W4;
}

std::size_t node_format_bytes(NodeFormat f) {
  switch (f) {
    case NodeFormat::W4: return sizeof(kernel::WideNode);
    case NodeFormat::W8: return sizeof(kernel::WideNode8);
    case NodeFormat::Q8: return sizeof(kernel::QuantNode8);
    case NodeFormat::O4: return sizeof(kernel::OrientedNode4);
  }
  return 0;
}

const void* PackedScene::node_data() const {
  switch (features.nodes) {
    case NodeFormat::W8: return nodes8.data();
    case NodeFormat::Q8: return qnodes.data();
    case NodeFormat::O4: return onodes.data();
    default: return nodes.data();
  }
}

std::size_t PackedScene::node_count() const {
  switch (features.nodes) {
    case NodeFormat::W8: return nodes8.size();
    case NodeFormat::Q8: return qnodes.size();
    case NodeFormat::O4: return onodes.size();
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

std::size_t PackedScene::primitive_bytes() const {
  std::size_t bytes = geoms.size() * sizeof(kernel::Geometry);
  for (std::size_t i = 0; i < prim_type_count; ++i) bytes += scene_prim_row(static_cast<PrimType>(i)).kernel_bytes(*this);
  return bytes;
}

} // namespace masq
