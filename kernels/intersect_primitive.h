// Dispatch to the intersector of a geometry's primitive type and the run's mode
// (robust or fast; for curves also the run's curve intersector, MASQ_CURVE_ISECT).
// Types a scene lacks are compiled out by the MASQ_HAVE_* switches.
#ifndef MASQ_KERNEL_INTERSECT_PRIMITIVE_H
#define MASQ_KERNEL_INTERSECT_PRIMITIVE_H
#include "kernel_data.h"
#include "variants.h"
#include "intersect_capsule.h"
#include "intersect_capsule_fast.h"
#include "intersect_curve.h"
#include "intersect_ribbon.h"
#include "intersect_round_cone.h"
#include "intersect_sphere.h"
#include "intersect_triangle.h"

KERNEL_NS_BEGIN
// A curve record against the ray, with the run's mode, intersector and query (the cpu's
// masquerade walk also calls it on its entry-ordered copy, kernels/traverse.h).
FN PrimHit intersect_curve_record(Curve c, vec3 o, vec3 d, float tmin, float tmax) {
  return curve_intersect_mode(c, o, d, tmin, tmax, MASQ_ROBUST ? 1 : 0, MASQ_CURVE_ISECT, MASQ_ANY_HIT ? 1 : 0);
}

FN_INLINED PrimHit intersect_primitive(KD_PARAM Geometry g, int prim, vec3 o, vec3 d, float tmin, float tmax) {
  int i = g.first + prim;
  if (MASQ_HAVE_CAPSULES && g.type == MASQ_PRIM_CAPSULE)
    return MASQ_ROBUST ? intersect_capsule(KD(capsules)[i], o, d, tmin, tmax)
                       : intersect_capsule_fast(KD(capsules)[i], o, d, tmin, tmax);
  if (MASQ_HAVE_CURVES && g.type == MASQ_PRIM_CURVE) return intersect_curve_record(KD(curves)[i], o, d, tmin, tmax);
  if (MASQ_HAVE_ROUND_CONES && g.type == MASQ_PRIM_ROUND_CONE)
    return MASQ_ROBUST ? intersect_round_cone(KD(round_cones)[i], o, d, tmin, tmax)
                       : intersect_round_cone_fast(KD(round_cones)[i], o, d, tmin, tmax);
  if (MASQ_HAVE_SPHERES && g.type == MASQ_PRIM_SPHERE)
    return MASQ_ROBUST ? intersect_sphere(KD(spheres)[i], o, d, tmin, tmax)
                       : intersect_sphere_fast(KD(spheres)[i], o, d, tmin, tmax);
  if (MASQ_HAVE_RIBBONS && g.type == MASQ_PRIM_RIBBON)
    return MASQ_ROBUST ? intersect_ribbon(KD(ribbons)[i], o, d, tmin, tmax)
                       : intersect_ribbon_fast(KD(ribbons)[i], o, d, tmin, tmax);
  if (MASQ_HAVE_TRIANGLES && g.type == MASQ_PRIM_TRIANGLE)
    return MASQ_ROBUST ? intersect_triangle(KD(triangles)[i], o, d, tmin, tmax)
                       : intersect_triangle_fast(KD(triangles)[i], o, d, tmin, tmax);
  return prim_miss();
}
KERNEL_NS_END
#endif
