// Primary rays from a scene camera (pinhole or orthographic), row-major from the top.
#pragma once
#include "kernels/layout.h"
#include "scenes/scene.h"
#include <vector>

namespace masq {
std::vector<kernel::Ray> make_camera_rays(const Camera& camera, int width, int height);
// Points the camera at the scene's world bounding box (all primitives of all
// instances, radii included), from the -z side and a little above.
void frame_scene(Scene& scene);
kernel::Ray make_ray(const glm::dvec3& org, const glm::dvec3& dir, float tmin = 0.0f,
                     float tmax = 3.0e38f);
} // namespace masq
