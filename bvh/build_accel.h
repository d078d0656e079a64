// Builds the two-level structure of a scene for one method.
//  ref:  one BLAS per geometry over its primitives' AABBs; one TLAS entry per scene
//        instance (the reference method of Wald et al. 2020).
//  masq: every capsule becomes a TLAS entry whose transform maps the unit box onto its
//        OBB (the masquerade); triangle geometries keep their BLAS, since a triangle's
//        OBB is flat and a map of the unit box onto it would be singular.
#pragma once
#include "bvh/binned_sah.h"
#include "bvh/packed_scene.h"
#include "scenes/scene.h"

namespace masq {

PackedScene build_accel(const Scene& scene, Method method, const SahOptions& opt = {});

} // namespace masq
