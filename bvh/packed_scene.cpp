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

std::size_t PackedScene::acceleration_bytes() const {
  return nodes.size() * sizeof(kernel::WideNode) + refs.size() * sizeof(std::int32_t) +
         instances.size() * sizeof(kernel::Instance) + frames.size() * sizeof(kernel::Frame);
}

std::size_t PackedScene::primitive_bytes() const {
  return geoms.size() * sizeof(kernel::Geometry) + triangles.size() * sizeof(kernel::Triangle) +
         capsules.size() * sizeof(kernel::Capsule) + cones.size() * sizeof(kernel::RoundCone) +
         spheres.size() * sizeof(kernel::Sphere) + curves.size() * sizeof(kernel::Curve);
}

} // namespace masq
