#include "bvh/packed_scene.h"
#include "scenes/error.h"

namespace masq {

const char* method_name(Method m) {
  switch (m) {
    case Method::Ref: return "ref";
    case Method::Masq: return "masq";
    case Method::Cluster: return "cluster";
    case Method::Auto: return "auto";
  }
  return "?";
}

Method parse_method(const std::string& name) {
  for (Method m : {Method::Ref, Method::Masq, Method::Cluster, Method::Auto})
    if (name == method_name(m)) return m;
  throw Error("unknown method '" + name + "' (expected ref, masq, cluster or auto)");
}

const char* mode_name(Mode m) { return m == Mode::Robust ? "robust" : "fast"; }

Mode parse_mode(const std::string& name) {
  if (name == "robust") return Mode::Robust;
  if (name == "fast") return Mode::Fast;
  throw Error("unknown mode '" + name + "' (expected robust or fast)");
}

const char* node_format_name(NodeFormat f) {
  switch (f) {
    case NodeFormat::W4: return "w4";
    case NodeFormat::W8: return "w8";
    case NodeFormat::Q8: return "q8";
  }
  return "?";
}

NodeFormat parse_node_format(const std::string& name) {
  for (NodeFormat f : {NodeFormat::W4, NodeFormat::W8, NodeFormat::Q8})
    if (name == node_format_name(f)) return f;
  throw Error("unknown node format '" + name + "' (expected w4, w8 or q8)");
}

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
  return node_bytes() + refs.size() * sizeof(std::int32_t) +
         instances.size() * sizeof(kernel::Instance) + frames.size() * sizeof(kernel::Frame);
}

std::size_t PackedScene::primitive_bytes() const {
  return geoms.size() * sizeof(kernel::Geometry) + triangles.size() * sizeof(kernel::Triangle) +
         capsules.size() * sizeof(kernel::Capsule) + cones.size() * sizeof(kernel::RoundCone) +
         spheres.size() * sizeof(kernel::Sphere) + curves.size() * sizeof(kernel::Curve);
}

} // namespace masq
