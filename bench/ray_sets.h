// The three ray sets a bench configuration is measured with: primary camera rays
// (coherent), shadow rays from the primary hits to a point light, and cosine-weighted
// diffuse bounce rays from the primary hits (incoherent: they exercise traversal the
// way a path tracer does).
#pragma once
#include "kernels/layout.h"
#include "scenes/scene.h"
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace masq {

enum class RaySet { Primary, Shadow, Diffuse };
const char* ray_set_name(RaySet s); // "primary", "shadow", "diffuse"
RaySet parse_ray_set(const std::string& name); // throws masq::Error

// The point light of the shadow rays: above, right of and behind the camera's target,
// at the camera's distance (so shadow rays cross the scene at a different angle).
glm::dvec3 shadow_light(const Camera& camera);

// Secondary rays from the hits of `primary` (misses spawn none). Origins are the hit
// points o + t d exactly (the robust intersectors' self-intersection window is what
// keeps them off their own surface; fast mode's self hits are part of what is measured).
// Shadow rays end at the light (tmax = 1 with d = light - origin); diffuse rays are
// cosine-weighted about the normal facing the incoming ray, seeded per ray index.
std::vector<kernel::Ray> make_secondary_rays(RaySet set, const Camera& camera, std::span<const kernel::Ray> primary,
                                             std::span<const kernel::Hit> hits, std::uint64_t seed = 1);

} // namespace masq
