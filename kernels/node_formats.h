// The node formats read as raw words (w8: 8-wide float boxes; q8: 8-bit quantised
// boxes; o4: 4-wide float boxes in the node's own rotated frame) and the one entry the
// traversal calls for every format. They are read from the node array as raw words
// (KD(node_words); GLSL binds that array once, under two names), at the word offsets
// that kernels/layout.h defines and the host checks against the structs.
#ifndef MASQ_KERNEL_NODE_FORMATS_H
#define MASQ_KERNEL_NODE_FORMATS_H
#include "box.h"
#include "kernel_data.h"
#include "variants.h"

KERNEL_NS_BEGIN

STRUCT_BEGIN(SlabHit)
  float tn; // entry distance (clamped to tmin), +inf when missed within [tmin, tmax]
  float tf;
STRUCT_END(SlabHit)

// The slab test of intersect_wide_node on one child box; padded != 0 grows it first as
// intersect_wide_node_padded does (by pad, and by 2u of each bound's magnitude since the
// subtraction rounds).
FN SlabHit slab_hit(vec3 lo, vec3 hi, vec3 o, vec3 inv_d, int padded, vec3 pad, float tmin, float tmax) {
  vec3 a = lo;
  vec3 b = hi;
  if (padded != 0) {
    a = lo - (pad + vabs_(lo) * (2.0f * MASQ_U));
    b = hi + (pad + vabs_(hi) * (2.0f * MASQ_U));
  }
  float tx0 = (a.x - o.x) * inv_d.x;
  float tx1 = (b.x - o.x) * inv_d.x;
  float ty0 = (a.y - o.y) * inv_d.y;
  float ty1 = (b.y - o.y) * inv_d.y;
  float tz0 = (a.z - o.z) * inv_d.z;
  float tz1 = (b.z - o.z) * inv_d.z;
  float tn = widen_lo(vmax3_(min(tx0, tx1), min(ty0, ty1), min(tz0, tz1)));
  float tf = widen_hi(vmin3_(max(tx0, tx1), max(ty0, ty1), max(tz0, tz1)));
  SlabHit h;
  h.tn = (tn <= tf && tf >= tmin && tn <= tmax) ? max(tn, tmin) : inf_();
  h.tf = tf;
  return h;
}

FN float node_word_f(KD_PARAM int w) { return as_float_(KD(node_words)[w]); }

// Byte `slot` of the pair of words at w (slot j: word j / 4, bits 8 (j % 4)).
FN uint node_byte(KD_PARAM int w, int slot) { return (KD(node_words)[w + (slot >> 2)] >> ((slot & 3) * 8)) & 255u; }

FN WideHits hits_w8_loop(KD_PARAM int node, vec3 o, vec3 inv_d, int padded, vec3 pad, float tmin, float tmax) {
  WideHits r;
  int b = node * MASQ_W8_WORDS;
  for (int i = 0; i < MASQ_WIDTH8; ++i) {
    r.child[i] = u2i_(KD(node_words)[b + MASQ_W8_CHILD + i]);
    r.count[i] = u2i_(KD(node_words)[b + MASQ_W8_COUNT + i]);
    r.tnear[i] = inf_();
    r.tfar[i] = 0.0f;
    if (r.count[i] < 0) continue;
    vec3 lo = VEC3(node_word_f(KD_ARG b + MASQ_W8_LO_X + i), node_word_f(KD_ARG b + MASQ_W8_LO_Y + i),
                   node_word_f(KD_ARG b + MASQ_W8_LO_Z + i));
    vec3 hi = VEC3(node_word_f(KD_ARG b + MASQ_W8_HI_X + i), node_word_f(KD_ARG b + MASQ_W8_HI_Y + i),
                   node_word_f(KD_ARG b + MASQ_W8_HI_Z + i));
    SlabHit h = slab_hit(lo, hi, o, inv_d, padded, pad, tmin, tmax);
    r.tnear[i] = h.tn;
    r.tfar[i] = h.tf;
  }
  return r;
}

// The cpu dialect tests the eight slots at once (slab_simd_cpp.h: one AVX test where the
// build machine has AVX).
FN WideHits hits_w8(KD_PARAM int node, vec3 o, vec3 inv_d, int padded, vec3 pad, float tmin, float tmax) {
#if defined(MASQ_LANG_CPP)
  WideHits r;
  int b = node * MASQ_W8_WORDS;
  const uint* w = KD(node_words) + b;
  simd::slab_hits8((const float*)(w + MASQ_W8_LO_X), (const float*)(w + MASQ_W8_HI_X),
                   (const float*)(w + MASQ_W8_LO_Y), (const float*)(w + MASQ_W8_HI_Y),
                   (const float*)(w + MASQ_W8_LO_Z), (const float*)(w + MASQ_W8_HI_Z),
                   (const int*)(w + MASQ_W8_COUNT), o, inv_d, padded, pad, tmin, tmax, r.tnear, r.tfar);
  for (int i = 0; i < MASQ_WIDTH8; ++i) {
    r.child[i] = u2i_(w[MASQ_W8_CHILD + i]);
    r.count[i] = u2i_(w[MASQ_W8_COUNT + i]);
  }
  return r;
#else
  return hits_w8_loop(KD_ARG node, o, inv_d, padded, pad, tmin, tmax);
#endif
}

// A q8 node's frame: plane q of axis k lies at origin[k] + q * step[k].
STRUCT_BEGIN(Q8Frame)
  vec3 origin;
  vec3 step;
STRUCT_END(Q8Frame)

FN Q8Frame q8_frame(KD_PARAM int b) {
  Q8Frame f;
  f.origin = VEC3(node_word_f(KD_ARG b + MASQ_Q8_ORIGIN), node_word_f(KD_ARG b + MASQ_Q8_ORIGIN + 1),
                  node_word_f(KD_ARG b + MASQ_Q8_ORIGIN + 2));
  uint ex = KD(node_words)[b + MASQ_Q8_EXPS];
  f.step = VEC3(as_float_((ex & 255u) << 23), as_float_(((ex >> 8) & 255u) << 23),
                as_float_(((ex >> 16) & 255u) << 23));
  return f;
}

// The slots of the q8 node at word b decoded from their meta bytes: inner children are
// numbered from child_base, leaf references from ref_base, in slot order; empty slots
// get count -1. No box is tested yet (tnear +inf, tfar 0).
FN WideHits q8_slots(KD_PARAM int b) {
  WideHits r;
  int next_child = u2i_(KD(node_words)[b + MASQ_Q8_CHILD_BASE]);
  int next_ref = u2i_(KD(node_words)[b + MASQ_Q8_REF_BASE]);
  for (int i = 0; i < MASQ_WIDTH8; ++i) {
    uint m = node_byte(KD_ARG b + MASQ_Q8_META, i);
    r.tnear[i] = inf_();
    r.tfar[i] = 0.0f;
    r.child[i] = -1;
    r.count[i] = -1;
    if (m == MASQ_Q8_INNER) {
      r.child[i] = next_child;
      r.count[i] = 0;
      next_child = next_child + 1;
    } else if (m != 0u) {
      r.child[i] = next_ref;
      r.count[i] = u2i_(m);
      next_ref = next_ref + u2i_(m);
    }
  }
  return r;
}

// Decodes each child box as origin + q * 2^e per plane (exact product, one rounding of
// the sum: the host proved that value lies outside the true box), then the float test.
FN WideHits hits_q8_loop(KD_PARAM int node, vec3 o, vec3 inv_d, int padded, vec3 pad, float tmin, float tmax) {
  int b = node * MASQ_Q8_WORDS;
  Q8Frame f = q8_frame(KD_ARG b);
  WideHits r = q8_slots(KD_ARG b);
  for (int i = 0; i < MASQ_WIDTH8; ++i) {
    if (r.count[i] < 0) continue;
    vec3 lo = VEC3(f.origin.x + u2f_(node_byte(KD_ARG b + MASQ_Q8_QLO_X, i)) * f.step.x,
                   f.origin.y + u2f_(node_byte(KD_ARG b + MASQ_Q8_QLO_Y, i)) * f.step.y,
                   f.origin.z + u2f_(node_byte(KD_ARG b + MASQ_Q8_QLO_Z, i)) * f.step.z);
    vec3 hi = VEC3(f.origin.x + u2f_(node_byte(KD_ARG b + MASQ_Q8_QHI_X, i)) * f.step.x,
                   f.origin.y + u2f_(node_byte(KD_ARG b + MASQ_Q8_QHI_Y, i)) * f.step.y,
                   f.origin.z + u2f_(node_byte(KD_ARG b + MASQ_Q8_QHI_Z, i)) * f.step.z);
    SlabHit h = slab_hit(lo, hi, o, inv_d, padded, pad, tmin, tmax);
    r.tnear[i] = h.tn;
    r.tfar[i] = h.tf;
  }
  return r;
}

// The cpu dialect decodes and tests the eight slots as two groups of four
// (slab_simd_cpp.h), the same operations as the loop.
FN WideHits hits_q8(KD_PARAM int node, vec3 o, vec3 inv_d, int padded, vec3 pad, float tmin, float tmax) {
#if defined(MASQ_LANG_CPP)
  int b = node * MASQ_Q8_WORDS;
  Q8Frame f = q8_frame(KD_ARG b);
  WideHits r = q8_slots(KD_ARG b);
  const uint* w = KD(node_words) + b;
  for (int g = 0; g < MASQ_WIDTH8; g += 4) {
    int k = g >> 2;
    simd::Planes4 planes{simd::dequantise4(w[MASQ_Q8_QLO_X + k], f.origin.x, f.step.x),
                         simd::dequantise4(w[MASQ_Q8_QHI_X + k], f.origin.x, f.step.x),
                         simd::dequantise4(w[MASQ_Q8_QLO_Y + k], f.origin.y, f.step.y),
                         simd::dequantise4(w[MASQ_Q8_QHI_Y + k], f.origin.y, f.step.y),
                         simd::dequantise4(w[MASQ_Q8_QLO_Z + k], f.origin.z, f.step.z),
                         simd::dequantise4(w[MASQ_Q8_QHI_Z + k], f.origin.z, f.step.z)};
    simd::slab_hits4v(planes, simd::load<simd::I4>(r.count + g) >= 0, o, inv_d, padded, pad, tmin, tmax,
                      r.tnear + g, r.tfar + g);
  }
  return r;
#else
  return hits_q8_loop(KD_ARG node, o, inv_d, padded, pad, tmin, tmax);
#endif
}

FN WideHits hits_w4(KD_PARAM int node, vec3 o, vec3 inv_d, int padded, vec3 pad, float tmin, float tmax) {
  WideNode n = KD(nodes)[node];
  return padded != 0 ? intersect_wide_node_padded(n, o, inv_d, pad, tmin, tmax)
                     : intersect_wide_node(n, o, inv_d, tmin, tmax);
}

// The w4 box layout (WideNode's words) at word b of the node array: the slab test of
// box.h's w4 loop, read word by word. (Assembling a WideNode from the words and calling
// intersect_wide_node instead took NodeFormatsAgree/vulkan_bound on lavapipe from 56 s
// to over 600 s under ctest.)
// Slots 4..7 stay as wide_hits_none leaves them: node_width() is 4 for this layout.
FN WideHits hits_box4_words(KD_PARAM int b, vec3 o, vec3 inv_d, int padded, vec3 pad, float tmin, float tmax) {
  WideHits r = wide_hits_none();
#if defined(MASQ_LANG_CPP)
  const uint* w = KD(node_words) + b;
  const WideNode* n = (const WideNode*)w;
  simd::slab_hits4(n->lo_x, n->hi_x, n->lo_y, n->hi_y, n->lo_z, n->hi_z, n->count, o, inv_d, padded, pad, tmin, tmax,
                   r.tnear, r.tfar);
  for (int i = 0; i < MASQ_WIDTH; ++i) {
    r.child[i] = n->child[i];
    r.count[i] = n->count[i];
  }
#else
  // Word offsets of WideNode: lo_x 0, hi_x 4, lo_y 8, hi_y 12, lo_z 16, hi_z 20, child 24, count 28.
  for (int i = 0; i < MASQ_WIDTH; ++i) {
    r.child[i] = u2i_(KD(node_words)[b + 24 + i]);
    r.count[i] = u2i_(KD(node_words)[b + 28 + i]);
    r.tnear[i] = inf_();
    r.tfar[i] = 0.0f;
    if (r.count[i] < 0) continue;
    vec3 lo = VEC3(node_word_f(KD_ARG b + i), node_word_f(KD_ARG b + 8 + i), node_word_f(KD_ARG b + 16 + i));
    vec3 hi = VEC3(node_word_f(KD_ARG b + 4 + i), node_word_f(KD_ARG b + 12 + i), node_word_f(KD_ARG b + 20 + i));
    SlabHit h = slab_hit(lo, hi, o, inv_d, padded, pad, tmin, tmax);
    r.tnear[i] = h.tn;
    r.tfar[i] = h.tf;
  }
#endif
  return r;
}

// Entry e (row e / 3, column e % 3) of an o4 node's frame: a signed byte over 128.
FN float o4_entry(KD_PARAM int b, int e) {
  int q = u2i_((KD(node_words)[b + MASQ_O4_ROT + (e >> 2)] >> ((e & 3) * 8)) & 255u);
  return i2f_(q > 127 ? q - 256 : q) * 0.0078125f;
}

// The ray in an o4 node's frame, all of it that does not depend on the node's exit
// distance: M o, the reciprocals of M d, transform_error's two parts and an incoming pad
// (the ray itself transformed: cluster BLAS) carried through |M| (padded != 0, else 0).
STRUCT_BEGIN(O4Ray)
  vec3 mo;
  vec3 inv_md;
  vec3 err_o;
  vec3 err_d;
  vec3 in_pad;
STRUCT_END(O4Ray)

// The ray in the frame of the oriented o4 node at word b.
FN O4Ray o4_ray(KD_PARAM int b, vec3 o, vec3 d, int padded, vec3 pad) {
  Affine m;
  m.r0 = VEC3(o4_entry(KD_ARG b, 0), o4_entry(KD_ARG b, 1), o4_entry(KD_ARG b, 2));
  m.r1 = VEC3(o4_entry(KD_ARG b, 3), o4_entry(KD_ARG b, 4), o4_entry(KD_ARG b, 5));
  m.r2 = VEC3(o4_entry(KD_ARG b, 6), o4_entry(KD_ARG b, 7), o4_entry(KD_ARG b, 8));
  m.t = VEC3(0.0f, 0.0f, 0.0f);
  O4Ray r;
  r.mo = affine_vector(m, o);
  r.inv_md = safe_rcp3(affine_vector(m, d));
  r.err_o = transform_error_origin(m, o);
  r.err_d = transform_error_dir(m, d);
  r.in_pad = VEC3(0.0f, 0.0f, 0.0f);
  if (padded != 0)
    r.in_pad = VEC3(dot(vabs_(m.r0), pad), dot(vabs_(m.r1), pad), dot(vabs_(m.r2), pad)) * (1.0f + 8.0f * MASQ_U);
  return r;
}

// The boxes of the oriented node at word b against the ray in its frame, padded by the
// transform's error bound at t_bound (transform_pad's) and the incoming pad.
FN WideHits o4_box_hits(KD_PARAM int b, O4Ray r, int padded, float tmin, float tmax, float t_bound) {
  vec3 mpad = transform_error_at(r.err_o, r.err_d, t_bound) * (1.0f + 8.0f * MASQ_U);
  if (padded != 0) mpad = mpad + r.in_pad;
  return hits_box4_words(KD_ARG b, r.mo, r.inv_md, 1, mpad, tmin, tmax);
}

// An o4 node: the ray goes into the node's frame (o' = M o, d' = M d) and the boxes are
// padded by that product's fp32 error, which grows with t: t_bound is the exit distance
// of this node's box in its parent (no hit below it lies farther), as transform_pad
// bounds a cluster's ray. An incoming pad (the ray itself transformed: cluster BLAS)
// carries over through |M|. Axis-aligned nodes are tested as w4 nodes.
FN WideHits hits_o4(KD_PARAM int node, vec3 o, vec3 d, vec3 inv_d, int padded, vec3 pad, float tmin, float tmax,
                    float t_bound) {
  int b = node * MASQ_O4_WORDS;
  if (KD(node_words)[b + MASQ_O4_ORIENTED] == 0u) return hits_box4_words(KD_ARG b, o, inv_d, padded, pad, tmin, tmax);
  return o4_box_hits(KD_ARG b, o4_ray(KD_ARG b, o, d, padded, pad), padded, tmin, tmax, t_bound);
}

#if defined(MASQ_LANG_CPP)
// cpu: the ray in the frame of the last rotated node an o4 walk met (o4_ray), kept for
// the next node with the same rotation: nodes over parallel strands share one, and on
// the default bundle's camera rays the rotation, its product with the ray and the three
// divisions were about a quarter of the trace. The same bits as hits_o4.
struct O4RayCache {
  bool valid = false;
  uint key[3] = {0u, 0u, 0u}; // the rotation words (OrientedNode4::rot)
  O4Ray ray{};
};

FN_INLINED WideHits hits_o4_cached(KD_PARAM int node, vec3 o, vec3 d, vec3 inv_d, int padded, vec3 pad, float tmin,
                                   float tmax, float t_bound, O4RayCache& c) {
  int b = node * MASQ_O4_WORDS;
  const uint* w = KD(node_words) + b;
  if (w[MASQ_O4_ORIENTED] == 0u) return hits_box4_words(KD_ARG b, o, inv_d, padded, pad, tmin, tmax);
  if (!c.valid || w[MASQ_O4_ROT] != c.key[0] || w[MASQ_O4_ROT + 1] != c.key[1] || w[MASQ_O4_ROT + 2] != c.key[2]) {
    c.valid = true;
    for (int k = 0; k < 3; ++k) c.key[k] = w[MASQ_O4_ROT + k];
    c.ray = o4_ray(KD_ARG b, o, d, padded, pad);
  }
  return o4_box_hits(KD_ARG b, c.ray, padded, tmin, tmax, t_bound);
}
#endif

#if defined(MASQ_LANG_CPP)
// cpu: asks for every cache line of a node the walk will visit, so that its fetch
// overlaps the work done before the visit (the leaves of the node that named it).
FN_INLINED void prefetch_node(KD_PARAM int node) {
  const int words = MASQ_NODE_FORMAT == MASQ_NODES_W8   ? MASQ_W8_WORDS
                    : MASQ_NODE_FORMAT == MASQ_NODES_Q8 ? MASQ_Q8_WORDS
                    : MASQ_NODE_FORMAT == MASQ_NODES_O4 ? MASQ_O4_WORDS
                                                        : 0; // w4: a WideNode of KD(nodes)
  const char* p = words > 0 ? (const char*)(KD(node_words) + node * words) : (const char*)(KD(nodes) + node);
  const int bytes = words > 0 ? 4 * words : int(sizeof(WideNode));
  for (int at = 0; at < bytes; at += 64) __builtin_prefetch(p + at);
  __builtin_prefetch(p + bytes - 1); // a node that straddles one more line than its size
}
#endif

// The node test of the scene's format: child entry distances and the decoded slots.
// d and t_bound serve the o4 format's rotation (the other formats test with inv_d).
FN WideHits node_hits(KD_PARAM int node, vec3 o, vec3 d, vec3 inv_d, int padded, vec3 pad, float tmin, float tmax,
                      float t_bound) {
  if (MASQ_NODE_FORMAT == MASQ_NODES_W8) return hits_w8(KD_ARG node, o, inv_d, padded, pad, tmin, tmax);
  if (MASQ_NODE_FORMAT == MASQ_NODES_Q8) return hits_q8(KD_ARG node, o, inv_d, padded, pad, tmin, tmax);
  if (MASQ_NODE_FORMAT == MASQ_NODES_O4) return hits_o4(KD_ARG node, o, d, inv_d, padded, pad, tmin, tmax, t_bound);
  return hits_w4(KD_ARG node, o, inv_d, padded, pad, tmin, tmax);
}

#if defined(MASQ_LANG_CPP)
// cpu: node_hits, the o4 format through the ray cache (the walk's own cache, as it meets
// nodes one after another).
FN_INLINED WideHits node_hits_cached(KD_PARAM int node, vec3 o, vec3 d, vec3 inv_d, int padded, vec3 pad, float tmin,
                                     float tmax, float t_bound, O4RayCache& c) {
  if (MASQ_NODE_FORMAT == MASQ_NODES_O4)
    return hits_o4_cached(KD_ARG node, o, d, inv_d, padded, pad, tmin, tmax, t_bound, c);
  return node_hits(KD_ARG node, o, d, inv_d, padded, pad, tmin, tmax, t_bound);
}
#endif

// Nested choices rather than '||': PoCL's clang warns of '||' between constant operands
// ("use of logical '||' with constant operand"), once per kernel build, on stderr.
FN int node_width() {
  return MASQ_NODE_FORMAT == MASQ_NODES_W8 ? MASQ_WIDTH8 : (MASQ_NODE_FORMAT == MASQ_NODES_Q8 ? MASQ_WIDTH8 : MASQ_WIDTH);
}

KERNEL_NS_END
#endif
