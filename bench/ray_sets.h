// The three ray sets a bench configuration is measured with: primary camera rays
// (coherent), shadow rays from the primary hits to a point light, and cosine-weighted
// diffuse bounce rays from the primary hits (incoherent: they exercise traversal the
// way a path tracer does).
#pragma once
#include "kernels/layout.h"
#include "masq/names.h"
#include "scenes/scene.h"
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace masq {

enum class RaySet { Primary, Shadow, Diffuse };
inline constexpr NameRow<RaySet> ray_set_rows[] = {
    {RaySet::Primary, "primary", "camera rays"},
    {RaySet::Shadow, "shadow", "from the primary hits to a light"},
    {RaySet::Diffuse, "diffuse", "cosine-weighted bounces from the primary hits"},
};
inline constexpr NameTable ray_set_table{"ray set", ray_set_rows};
inline const char* ray_set_name(RaySet s) { return ray_set_table.name(s); }
inline RaySet parse_ray_set(std::string_view name) { return ray_set_table.parse(name); } // throws masq::Error

// The point light of the shadow rays: above, right of and behind the camera's target,
// at the camera's distance (so shadow rays cross the scene at a different angle).
glm::dvec3 shadow_light(const Camera& camera);

// Secondary rays from the hits of `primary` (misses spawn none). Origins are the hit
// points o + t d; each ray starts at spawn_tmin, a small offset from its surface, the
// usual practice of renderers, so that every tracer (masq, Embree, the driver) answers
// the same question rather than each meeting its own surface at t ~ 0 by its own
// rounding. Shadow rays end at the light (tmax = 1 with d = light - origin); diffuse rays
// are cosine-weighted about the normal facing the incoming ray, seeded per ray index.
std::vector<kernel::Ray> make_secondary_rays(RaySet set, const Scene& scene, std::span<const kernel::Ray> primary,
                                             std::span<const kernel::Hit> hits, std::uint64_t seed = 1);

// The tmin of a ray leaving hit point p along d: max(r / 16, 2^-17 max|p_i|) / |d|, with
// r the hit primitive's world radius (0 for triangles).
float spawn_tmin(const Scene& scene, const kernel::Hit& hit, const glm::dvec3& p, const glm::dvec3& d);

} // namespace masq
