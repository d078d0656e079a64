// The private halves of the public API's pimpl classes (include/masq/). Only api/*.cpp
// include this; it is not installed.
#pragma once
#include "bvh/twolevel/build_accel.h"
#include "masq/context.h"
#include "scenes/scene.h"

namespace masq::api {

struct Scene::Impl {
  masq::Scene scene;
  bool has_camera = false; // a loaded file's own camera (.json, .nff); else camera_rays frames the scene
  // The scene as an Accel sees it: without instances, every geometry placed once with the
  // identity (the documented default placement).
  masq::Scene placed() const;
};

struct Accel::Impl {
  masq::PackedScene packed;
  AccelOptions options;
  std::size_t primitives = 0; // the placed scene's, for AccelStats

};

} // namespace masq::api
