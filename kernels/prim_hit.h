// What every primitive intersector returns: the nearest surface point with t in
// [tmin, tmax], in the space of the ray it was given.
#ifndef MASQ_KERNEL_PRIM_HIT_H
#define MASQ_KERNEL_PRIM_HIT_H
#include "math.h"

KERNEL_NS_BEGIN
STRUCT_BEGIN(PrimHit)
  int hit;
  float t;
  vec3 normal; // unnormalised geometric normal
  float u;
  float v;
STRUCT_END(PrimHit)

FN PrimHit prim_miss() {
  PrimHit h;
  h.hit = 0;
  h.t = inf_();
  h.normal = VEC3(0.0f, 0.0f, 0.0f);
  h.u = 0.0f;
  h.v = 0.0f;
  return h;
}
KERNEL_NS_END
#endif
