#include "bvh/packed_scene.h"
#include "scenes/error.h"

namespace masq {

const char* method_name(Method m) { return m == Method::Ref ? "ref" : "masq"; }

Method parse_method(const std::string& name) {
  if (name == "ref") return Method::Ref;
  if (name == "masq") return Method::Masq;
  throw Error("unknown method '" + name + "' (expected ref or masq)");
}

std::size_t PackedScene::acceleration_bytes() const {
  return nodes.size() * sizeof(kernel::WideNode) + refs.size() * sizeof(std::int32_t) +
         instances.size() * sizeof(kernel::Instance) + frames.size() * sizeof(kernel::Frame);
}

std::size_t PackedScene::primitive_bytes() const {
  return geoms.size() * sizeof(kernel::Geometry) + triangles.size() * sizeof(kernel::Triangle) +
         capsules.size() * sizeof(kernel::Capsule);
}

} // namespace masq
