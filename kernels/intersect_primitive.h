// Dispatch to the intersector of a geometry's primitive type. Types a scene lacks are
// compiled out by the MASQ_HAVE_* switches.
#ifndef MASQ_KERNEL_INTERSECT_PRIMITIVE_H
#define MASQ_KERNEL_INTERSECT_PRIMITIVE_H
#include "kernel_data.h"
#include "variants.h"
#include "intersect_capsule.h"
#include "intersect_triangle.h"

KERNEL_NS_BEGIN
FN PrimHit intersect_primitive(KD_PARAM Geometry g, int prim, vec3 o, vec3 d, float tmin, float tmax) {
  if (MASQ_HAVE_CAPSULES && g.type == MASQ_PRIM_CAPSULE)
    return intersect_capsule(KD(capsules)[g.first + prim], o, d, tmin, tmax);
  if (MASQ_HAVE_TRIANGLES && g.type == MASQ_PRIM_TRIANGLE)
    return intersect_triangle(KD(triangles)[g.first + prim], o, d, tmin, tmax);
  return prim_miss();
}
KERNEL_NS_END
#endif
