// Primary rays from a scene camera (pinhole or orthographic), row-major from the top.
#pragma once
#include "kernels/layout.h"
#include "scenes/scene.h"
#include <vector>

namespace masq {
std::vector<kernel::Ray> make_camera_rays(const Camera& camera, int width, int height);
// The world-space box of every primitive of every instance, radii included: each hull
// ball (scenes/prim_table.h) placed by its instance, a ball's extent along axis i scaled by
// the length of row i of the instance's linear part (the exact box of the transformed
// ball). A curve is bounded by its control points' balls. No instances, no primitives:
// lo = +inf, hi = -inf.
void scene_world_bounds(const Scene& scene, glm::dvec3& lo, glm::dvec3& hi);
// Points the camera at the scene's world bounding box (scene_world_bounds), from the -z
// side and a little above.
void frame_scene(Scene& scene);
kernel::Ray make_ray(const glm::dvec3& org, const glm::dvec3& dir, float tmin = 0.0f,
                     float tmax = 3.0e38f);
} // namespace masq
