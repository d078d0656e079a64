/// @file masq/masq.h
/// The masq library: ray tracing of long, thin primitives (capsules, round cones,
/// cubic curves, spheres) and triangles on cpu, Vulkan, OpenCL or Vulkan ray query.
///
/// @code
///   #include <masq/masq.h>
///   masq::api::Scene scene;
///   masq::api::Capsule c{{0, 0, 0}, {1, 0, 0}, 0.01f};
///   scene.add_capsules({&c, 1});
///   auto accel = masq::api::Accel::build(scene, {masq::api::Method::Masq});
///   masq::api::Context ctx("best");
///   std::vector<masq::api::Hit> hits = ctx.trace(accel, rays);
/// @endcode
///
/// Errors are exceptions: masq::Error (bad input, device failures) and
/// masq::BackendUnavailable (a backend that cannot run here), both one line naming what
/// failed and where. See docs/library.md for the guide.
#pragma once
#include "masq/context.h"
#include "masq/error.h"
#include "masq/scene.h"
#include "masq/types.h"

namespace masq::api {
/// The library version, "major.minor.patch".
const char* version();
} // namespace masq::api
