// Robust curve intersection by certified subdivision (robust mode's intersector; the
// phantom iteration stays fast mode's, kernels/curve_phantom.h).
//
// The solid is the union of the balls B(C(s), r), s in [0,1] (round ends included).
// Along the ray it is a union of t-intervals; the hit is the first interval boundary in
// [t_lo, tmax] (an entry, or the exit when the origin is inside) -- exactly what the
// long-double oracle computes (oracle/oracle_curve.cpp).
//
// Method: a depth-first search over the binary tree of dyadic s-intervals [s0, s1].
// The state is the node's (level, index) and one bit per level (which child was
// visited first): no stack of control points, no recursion. A node's control points
// are split from its parent's on the way down (de Casteljau at 1/2) and extracted from
// the whole curve at s0 and s1 on a jump to a sibling. Per node, in the ray frame:
//  - bounds: the piece lies in the hull of its control points, hence in their xy box
//    and z range, and within `dev` of its chord (|C(s) - chord(s)| <= max_i |P_i -
//    chord(i/3)|: the Bernstein weights sum to 1). hmin (from the box and the chord)
//    bounds its distance from the ray; its crossings lie within its z range grown by
//    sqrt(rp^2 - hmin^2) + pad, rp = r + pad. pad bounds the fp32 error of the control
//    points (64 u (M + r), M the largest frame coordinate). A node is pruned when these
//    bounds show it cannot hold a better answer.
//  - sandwich: the piece's solid lies between the capsules of radius r -+ (dev + pad)
//    about its chord. Missing the outer one prunes; crossing the inner one with both
//    ends of the two intervals within ttol (z_lo in neither band) makes a leaf.
//  - flat leaf: dev <= tol = max(MASQ_CURVE_FLAT u (r + span), 4 u M), a fraction of
//    the fp32 ambiguity band 4 u (r + D + L) but not below the rounding noise of dev
//    itself (zero-speed ends would never be flat); the leaf capsule and the piece's swept balls are
//    within dev of each other, so only rays whose clearance is below dev plus the
//    rounding can flip (rays near the outline descend this far).
// Pass 0 finds the nearest leaf entry at or after z_lo and stops at the first leaf that
// holds z_lo (the origin is inside); nodes are visited near end first and pruned beyond
// the best entry. If the origin is inside, later passes extend the exit: cur = the
// largest exit of the leaves holding cur, until a pass changes nothing (the merged
// interval's end). Then the hit is moved onto the curve's own surface (curve_refine).
// Every pruning step discards only nodes that provably hold no better answer, so the
// answer is certified up to tol, ttol and the rounding; the only uncertified outcome is
// the visit limit (MASQ_CURVE_VISITS per pass), which no stress or test ray reaches.
// docs/robustness.md ("Curve: certified subdivision") gives the argument in full.
#ifndef MASQ_KERNEL_CURVE_SUBDIV_H
#define MASQ_KERNEL_CURVE_SUBDIV_H
#include "curve_entry.h"

// Leaf flatness: this times u (r + span); at most 1/16 of the ambiguity band.
#define MASQ_CURVE_FLAT 0.25f
// A coarser piece is a leaf when the capsules of radius r -+ dev put both ends of the
// ray's interval within this times r, and on the same side of z_lo.
#define MASQ_CURVE_TTOL 7.8125e-3f
// Coarse leaves (roving): the least sin^2 of the angle between the ray and the chord.
#define MASQ_COARSE_SIN2 0.0625f
// ... and the most it may bow (dev / chord length), squared.
#define MASQ_COARSE_BOW2 9.765625e-4f
// Depth limit (s-intervals of 2^-22: far below any tolerance for finite curves).
#define MASQ_CURVE_DEPTH 22
// Node visits per pass (a grazing ray along a 1e4 r curve takes a few hundred).
#ifndef MASQ_CURVE_VISITS
#define MASQ_CURVE_VISITS 4096
#endif

KERNEL_NS_BEGIN

STRUCT_BEGIN(CurvePiece)
  vec3 p0;
  vec3 p1;
  vec3 p2;
  vec3 p3;
STRUCT_END(CurvePiece)

// A point of the frame curve and h C'(s) / 3 there (de Casteljau): one end of a piece
// of parameter width h.
STRUCT_BEGIN(CurvePieceEnd)
  vec3 p;
  vec3 dh;
STRUCT_END(CurvePieceEnd)

FN CurvePieceEnd curve_piece_end(CurveFrame f, float s, float h) {
  float t = 1.0f - s;
  vec3 a = t * f.b0 + s * f.b1;
  vec3 b = t * f.b1 + s * f.b2;
  vec3 c = t * f.b2 + s * f.b3;
  vec3 ab = t * a + s * b;
  vec3 bc = t * b + s * c;
  CurvePieceEnd e;
  e.p = t * ab + s * bc;
  e.dh = h * (bc - ab);
  return e;
}

// The piece of the frame curve on [s0, s1] (de Casteljau at both ends).
FN CurvePiece curve_piece(CurveFrame f, float s0, float s1) {
  float h = s1 - s0;
  CurvePieceEnd e0 = curve_piece_end(f, s0, h);
  CurvePieceEnd e1 = curve_piece_end(f, s1, h);
  CurvePiece pc;
  pc.p0 = e0.p;
  pc.p1 = e0.p + e0.dh;
  pc.p2 = e1.p - e1.dh;
  pc.p3 = e1.p;
  return pc;
}

// Half c (0: s in [s0, mid], 1: [mid, s1]) of a piece (de Casteljau at 1/2, exact
// halvings: the error grows by a rounding of the piece's own coordinates per level).
FN CurvePiece curve_half(CurvePiece pc, uint c) {
  vec3 m01 = 0.5f * (pc.p0 + pc.p1);
  vec3 m12 = 0.5f * (pc.p1 + pc.p2);
  vec3 m23 = 0.5f * (pc.p2 + pc.p3);
  vec3 a = 0.5f * (m01 + m12);
  vec3 b = 0.5f * (m12 + m23);
  vec3 m = 0.5f * (a + b);
  CurvePiece h;
  h.p0 = c == 0u ? pc.p0 : m;
  h.p1 = c == 0u ? m01 : b;
  h.p2 = c == 0u ? a : m23;
  h.p3 = c == 0u ? m : pc.p3;
  return h;
}

// The capsule of radius r about the chord p0 -> p3 against the z axis: its entry and
// exit z (x > y: missed), the normal (frame) at each and the chord parameter there.
STRUCT_BEGIN(CurveSpan)
  float zin;
  float zout;
  vec3 nin;
  vec3 nout;
  float uin;
  float uout;
STRUCT_END(CurveSpan)

// What the capsule tests about one chord share whatever their radius (a node tests two,
// the sandwich's, and a leaf a third): the end balls' distances from the z axis and the
// axis line's closest approach (chord parameter us, z0, distance hh). Computed once, the
// values are those each test computed for itself before, so every backend's bits are too.
STRUCT_BEGIN(CurveChord)
  vec3 a;
  vec3 b;
  vec3 e;      // b - a
  float ha;    // |a_xy|
  float hb;    // |b_xy|
  float aa;    // |e_xy|^2
  float ee;    // |e|^2
  int lateral; // the axis line is not along z: the lateral surface is tested
  float hh;    // its distance from the z axis
  float us;    // the chord parameter of its closest approach
  float z0;    // and that point's z
STRUCT_END(CurveChord)

// Every field set (no undefined value may reach a decision: docs/kernels.md).
FN CurveChord curve_chord_none() {
  CurveChord c;
  c.a = VEC3(0.0f, 0.0f, 0.0f);
  c.b = c.a;
  c.e = c.a;
  c.ha = 0.0f;
  c.hb = 0.0f;
  c.aa = 0.0f;
  c.ee = 0.0f;
  c.lateral = 0;
  c.hh = 0.0f;
  c.us = 0.0f;
  c.z0 = 0.0f;
  return c;
}

FN CurveChord curve_chord(vec3 a, vec3 b) {
  CurveChord c;
  c.a = a;
  c.b = b;
  c.ha = sqrt(a.x * a.x + a.y * a.y);
  c.hb = sqrt(b.x * b.x + b.y * b.y);
  c.e = b - a;
  c.aa = c.e.x * c.e.x + c.e.y * c.e.y;
  c.ee = dot(c.e, c.e);
  c.lateral = c.aa > 1e-12f * c.ee ? 1 : 0;
  c.hh = 0.0f;
  c.us = 0.0f;
  c.z0 = 0.0f;
  if (c.lateral != 0) {
    // Dot2-accurate cross product: hh = |a_xy x e_xy| / |e_xy|.
    c.hh = fabs_(curve_dop(a.x, c.e.y, a.y, c.e.x)) / sqrt(c.aa);
    c.us = -(a.x * c.e.x + a.y * c.e.y) / c.aa;
    c.z0 = a.z + c.us * c.e.z;
  }
  return c;
}

// The capsule of radius r about the chord against the z axis. End balls in the
// closest-approach form (r - h)(r + h); the lateral surface spans z0 -+ sqrt(r^2 - hh^2)
// |e| / |e_xy| about the axis line's closest approach, its crossings counting where their
// chord parameter lies in [0, 1] (beyond, the end balls hold the capsule).
FN CurveSpan curve_chord_capsule(CurveChord ch, float r) {
  CurveSpan sp;
  sp.zin = inf_();
  sp.zout = -inf_();
  sp.nin = VEC3(0.0f, 0.0f, 0.0f);
  sp.nout = sp.nin;
  sp.uin = 0.0f;
  sp.uout = 0.0f;
  for (int k = 0; k < 2; ++k) {
    vec3 c = k == 0 ? ch.a : ch.b;
    float hc = k == 0 ? ch.ha : ch.hb;
    float disc = (r - hc) * (r + hc);
    if (disc >= 0.0f) {
      float w = sqrt(disc);
      float uk = k == 0 ? 0.0f : 1.0f;
      if (c.z - w < sp.zin) {
        sp.zin = c.z - w;
        sp.nin = VEC3(-c.x, -c.y, -w);
        sp.uin = uk;
      }
      if (c.z + w > sp.zout) {
        sp.zout = c.z + w;
        sp.nout = VEC3(-c.x, -c.y, w);
        sp.uout = uk;
      }
    }
  }
  if (ch.lateral != 0) {
    float disc = (r - ch.hh) * (r + ch.hh);
    if (disc >= 0.0f) {
      float hw = sqrt(disc * ch.ee / ch.aa);
      float du = hw * ch.e.z / ch.ee;
      for (int k = 0; k < 2; ++k) {
        float sgn = k == 0 ? -1.0f : 1.0f;
        float u = ch.us + sgn * du;
        float z = ch.z0 + sgn * hw;
        if (u >= 0.0f && u <= 1.0f) {
          vec3 n = VEC3(0.0f, 0.0f, z) - (ch.a + u * ch.e);
          if (k == 0 && z < sp.zin) {
            sp.zin = z;
            sp.nin = n;
            sp.uin = u;
          }
          if (k == 1 && z > sp.zout) {
            sp.zout = z;
            sp.nout = n;
            sp.uout = u;
          }
        }
      }
    }
  }
  return sp;
}

// The leaf's chord parameter is not the curve's (the speed varies along the piece), and
// its normal leans by up to dev / r: the hit point X = (0, 0, z) is projected onto the
// curve by a few Newton steps on (C(s) - X) . C'(s) = 0 from the leaf's s, each kept
// within w = 16 leaf widths (the foot can lie several leaves away in s where the
// speed is low, yet not on another leg of a folded curve; a radius of curvature below r makes |C(s) - X|^2 concave
// near the foot: there, half-width steps downhill). The crossing of the ball at that foot point then replaces
// z (twice), and the normal is X - C(s), the swept ball's.
FN CurveRoot curve_refine(CurveFrame f, CurveRoot rt, float w, float side, float ttol, int passes) {
  float s = rt.s;
  vec3 v = VEC3(0.0f, 0.0f, 0.0f);
  for (int pass = 0; pass < passes; ++pass) {
    vec3 x = VEC3(0.0f, 0.0f, rt.z);
    CurvePoint e = curve_eval(f, s);
    v = e.p - x;
    for (int k = 0; k < 4; ++k) {
      float g = dot(v, e.d);
      float gd = dot(e.d, e.d) + dot(v, e.dd);
      // Newton where |C(s) - X|^2 is convex, else a step of w / 2 downhill (then
      // halved). No test of the distance itself: near the foot it changes by less
      // than its rounding (u of the curve's size).
      float ds = gd > 0.0f ? min(max(g / gd, -w), w) : (g > 0.0f ? 0.5f * w : -0.5f * w);
      if (!(gd > 0.0f)) w *= 0.5f;
      s = min(max(s - ds, 0.0f), 1.0f);
      e = curve_eval(f, s);
      v = e.p - x;
    }
    // The ball at the foot point is tangent to the surface at the hit: its crossing
    // moves t by the second order of the foot point's error only.
    float h = sqrt(e.p.x * e.p.x + e.p.y * e.p.y);
    float disc = (f.r - h) * (f.r + h);
    if (!(disc >= 0.0f)) break;
    float zb = e.p.z + side * sqrt(disc);
    if (!(fabs_(zb - rt.z) <= ttol)) break; // (another leg's foot: keep the leaf's)
    rt.z = zb;
    v = e.p - VEC3(0.0f, 0.0f, zb);
  }
  // The foot must be this crossing's: X on its ball's sphere (else keep the leaf's).
  float vl = length(v);
  if (fabs_(vl - f.r) <= 4.0f * ttol) {
    rt.s = s;
    rt.nrm = -v;
  }
  return rt;
}

// Whether the piece, seen along the ray (xy), moves forward along its chord ch all the
// way: every leg of its control polygon does (the derivative lies in their hull).
FN int curve_runs_along(CurvePiece pc, vec3 ch) {
  float a = (pc.p1.x - pc.p0.x) * ch.x + (pc.p1.y - pc.p0.y) * ch.y;
  float b = (pc.p2.x - pc.p1.x) * ch.x + (pc.p2.y - pc.p1.y) * ch.y;
  float c = (pc.p3.x - pc.p2.x) * ch.x + (pc.p3.y - pc.p2.y) * ch.y;
  return a > 0.0f && b > 0.0f && c > 0.0f ? 1 : 0;
}

// The search's answer: frame z of the hit (found = 0: none in the window), normal
// (frame), curve parameter.
// maybe_inside = 0: the point at zlo is known to lie outside the solid.
// The search covers s in [sa, sa + sw] ([0, 1]: the whole curve; roving capsules pass
// the part their clipping left, kernels/curve_roving.h). coarse > 0 (roving): a piece
// flat to coarse whose inner capsule the ray crosses, starting before its outer one, is
// a leaf whose entry is found by curve_refine right away (curve_roving.h, step 3).
// zstop (an occlusion query, curve_occlusion.h; -inf otherwise): the first entry found at
// or before it ends the search, nearer ones or not. The caller passes it only where such
// an entry proves the ray meets the solid in its window (zlo outside the solid, or the
// window's end outside the curve's bounding ball).
FN CurveRoot curve_subdiv(CurveFrame f, float sa, float sw, float zlo, float zmax, float tol, float ttol, float pad,
                          int maybe_inside, float coarse, float zstop) {
  CurveRoot rt = curve_root_none(0.0f);
  float r = f.r;
  float rp = r + pad;
  float best = zmax; // entry pass: nearest entry at or after zlo
  int inside = 0;    // some leaf contains zlo
  float cur = zlo;   // extension passes: end of the merged interval holding zlo
  vec3 ncur = VEC3(0.0f, 0.0f, 0.0f);
  float scur = 0.0f;
  float wbest = 0.0f; // s-width of the leaf that gave the answer
  float wcur = 0.0f;
  int refined = 0; // the answer came from a coarse leaf, already on the surface
  int cref = 0;    // cur came from a coarse leaf (on the surface)
  // Passes: 0 entry and containment (the nearest entry at or after zlo, stopping at
  // the first leaf that holds zlo), 1 entry alone (zlo known to be outside), then
  // 2 extension (inside, repeated until cur stays).
  int mode = maybe_inside != 0 ? 0 : 1;
  for (int pass = 0; pass < 8; ++pass) {
    float cur0 = cur;
    int stop = 0;
    int level = 0;
    uint idx = 0u;
    uint first = 0u; // bit l: the child of the level-(l-1) node visited first
    uint lbit = 1u;  // 2^level
    float hs = sw;   // 2^-level sw
    // pc: the node being visited; the root piece to begin with, so no path reads it
    // unset (have: pc already holds this node, split from its parent or the root).
    CurvePiece pc = curve_piece(f, sa, sa + sw);
    int have = 1;
    for (int it = 0; it < MASQ_CURVE_VISITS; ++it) {
      float s0 = sa + u2f_(idx) * hs;
      if (have == 0) pc = curve_piece(f, s0, s0 + hs);
      have = 0;
      float xlo = vmin3_(pc.p0.x, pc.p1.x, min(pc.p2.x, pc.p3.x));
      float xhi = vmax3_(pc.p0.x, pc.p1.x, max(pc.p2.x, pc.p3.x));
      float ylo = vmin3_(pc.p0.y, pc.p1.y, min(pc.p2.y, pc.p3.y));
      float yhi = vmax3_(pc.p0.y, pc.p1.y, max(pc.p2.y, pc.p3.y));
      float bx = max(max(xlo, -xhi), 0.0f);
      float by = max(max(ylo, -yhi), 0.0f);
      vec3 ch = pc.p3 - pc.p0;
      vec3 g1 = pc.p1 - (pc.p0 + ch * (1.0f / 3.0f));
      vec3 g2 = pc.p2 - (pc.p3 - ch * (1.0f / 3.0f));
      float dev = sqrt(max(dot(g1, g1), dot(g2, g2)));
      float cc = ch.x * ch.x + ch.y * ch.y;
      float uc = cc > 0.0f ? min(max(-(pc.p0.x * ch.x + pc.p0.y * ch.y) / cc, 0.0f), 1.0f) : 0.0f;
      float cx = pc.p0.x + uc * ch.x;
      float cy = pc.p0.y + uc * ch.y;
      // hmin: a lower bound of the piece's distance from the ray axis (the xy box, and
      // the chord less dev); the ray's chord through a ball of the piece is then at
      // most 2 sqrt(rp^2 - hmin^2) long, which bounds the piece's entries and exits.
      float hmin = max(sqrt(bx * bx + by * by), sqrt(cx * cx + cy * cy) - dev);
      float wz = sqrt(max((rp - hmin) * (rp + hmin), 0.0f)) + pad;
      float zl = vmin3_(pc.p0.z, pc.p1.z, min(pc.p2.z, pc.p3.z)) - wz;
      float zh = vmax3_(pc.p0.z, pc.p1.z, max(pc.p2.z, pc.p3.z)) + wz;
      // Keep the node only if it may hold what the pass looks for (NaN prunes): an
      // entry before best or a leaf holding zlo, a leaf that extends the interval past cur.
      int keep = hmin <= rp ? 1 : 0;
      if (mode <= 1) keep = keep != 0 && zl < best && zh >= zlo ? 1 : 0;
      else keep = keep != 0 && zl <= cur && zh > cur ? 1 : 0;
      int down = 0;
      if (keep != 0) {
        int leaf = dev <= tol || level >= MASQ_CURVE_DEPTH ? 1 : 0;
        CurveRoot cand = curve_root_none(0.0f); // a coarse leaf's entry, on the curve's surface
        CurveChord line = curve_chord_none(); // the chord's capsule terms, once computed (have_line)
        int have_line = 0;
        if (leaf == 0 && dev <= max(4.0f * ttol, coarse)) {
          // The piece's solid lies between the capsules of radius r -+ (dev + pad)
          // about its chord: if the ray crosses both within ttol at each end of its
          // interval, the capsule of radius r gives both ends to ttol (and the
          // hit/miss is certain); only rays near this piece's outline go deeper.
          float rdev = dev + pad;
          line = curve_chord(pc.p0, pc.p3);
          have_line = 1;
          CurveSpan so = curve_chord_capsule(line, r + rdev);
          // The outer capsule bounds the piece's entries and exits tightly: prune a
          // piece that cannot move the answer by more than ttol.
          if (!(so.zin <= so.zout)) keep = 0; // misses the outer capsule
          else if (mode == 0 && (so.zout < zlo || (so.zin > zlo && so.zin >= best - ttol))) keep = 0;
          else if (mode == 1 && (so.zin >= best - ttol || so.zout < zlo)) keep = 0;
          else if (mode == 2 && (so.zin > cur || so.zout <= cur + ttol)) keep = 0;
          // (The inner capsule only where the outer one keeps the piece.)
          CurveSpan si = so;
          if (keep != 0) si = curve_chord_capsule(line, r - rdev);
          if (keep != 0 && r > rdev && si.zin <= si.zout && si.zin - so.zin <= ttol && so.zout - si.zout <= ttol &&
              !(so.zin <= zlo && zlo <= si.zin) && !(si.zout <= zlo && zlo <= so.zout))
            leaf = 1; // (and zlo is not in either band: inside or outside is certain)
          else if (keep != 0 && dev <= coarse && r > rdev && cc >= MASQ_COARSE_SIN2 * dot(ch, ch) &&
                   dev * dev <= MASQ_COARSE_BOW2 * dot(ch, ch) && curve_runs_along(pc, ch) != 0) {
            // A coarse piece: its z_in and z_out are convex and concave, so the least
            // entry and the greatest exit are where the envelope condition holds on the
            // curve itself (curve_entry.h). That needs a ray crossing the piece at an
            // angle (a ray nearly along it sees the bends, not the line), a piece that
            // bows by little against its length (its tangent turns little), and one that
            // runs one way along its chord seen along the ray (a fold or cusp doubles
            // back). An answer outside the band the two capsules leave is not trusted:
            // the piece is split instead.
            if (mode <= 1 && si.zin <= si.zout && zlo < so.zin) {
              // The ray crosses the inner capsule, from before the outer one: the piece
              // surely holds an entry, in [so.zin, si.zin].
              cand = curve_piece_entry(f, s0, s0 + hs, s0 + so.uin * hs, sa, sa + sw, 1.0f);
              // (found 2: an entry at the joint with a neighbour, whose own is lower: a
              // bound, moved onto the surface by curve_refine if nothing beats it)
              if (cand.found >= 1 && cand.z >= so.zin - ttol && cand.z <= si.zin + ttol && cand.z >= zlo) leaf = 2;
            } else if (mode == 2 || zlo >= so.zin) {
              // The ray starts past the piece's first entries (a secondary ray leaving
              // or entering this curve), or the merged interval is being extended past
              // cur: what matters is the piece's greatest exit. If it lies before the
              // point (zlo, or cur), no ball of the piece reaches it: nothing here. If
              // the point is inside the inner capsule, the piece's interval holds it and
              // ends at that exit.
              float from = mode == 2 ? cur : zlo;
              cand = curve_piece_entry(f, s0, s0 + hs, s0 + so.uout * hs, sa, sa + sw, -1.0f);
              if (cand.found >= 1 && cand.z >= so.zin && cand.z <= so.zout + ttol) {
                if (cand.z < from || (mode == 2 && cand.z <= cur)) keep = 0;
                else if (mode != 1 && si.zin < from && from < si.zout) leaf = 3;
              }
            }
          }
        }
        if (keep != 0 && leaf == 3) {
          // The ray at zlo (mode 0) or cur (mode 2) is inside: the interval ends at the
          // piece's greatest exit, or later.
          inside = 1;
          if (mode == 0 || cand.z > cur) {
            cur = cand.z;
            ncur = cand.nrm;
            scur = cand.s;
            cref = cand.found == 1 ? 1 : 0; // (2: at a joint; refined if it stays the end)
            wcur = hs;
          }
          if (mode == 0) stop = 1;
        } else if (keep != 0 && leaf == 2) {
          if (cand.z <= best) {
            best = cand.z;
            rt = cand;
            rt.found = 1;
            refined = cand.found == 1 ? 1 : 0; // (2: at a joint; refined if it stays the answer)
            wbest = hs;
            if (cand.found == 1 && cand.z <= zstop) stop = 1; // (2 is a bound, not a crossing)
          }
        } else
        if (keep != 0 && leaf != 0) {
          if (have_line == 0) line = curve_chord(pc.p0, pc.p3);
          CurveSpan sp = curve_chord_capsule(line, r);
          int met = sp.zin <= sp.zout ? 1 : 0; // (missed: zin = inf, zout = -inf)
          if (met != 0 && mode <= 1 && sp.zin >= zlo && sp.zin <= best) {
            best = sp.zin;
            refined = 0;
            rt.found = 1;
            rt.z = sp.zin;
            rt.s = s0 + sp.uin * hs;
            rt.nrm = sp.nin;
            wbest = hs;
            if (sp.zin <= zstop) stop = 1;
          }
          if (met != 0 && ((mode == 0 && sp.zin < zlo && sp.zout >= zlo) || (mode == 2 && sp.zin <= cur && sp.zout > cur))) {
            inside = 1;
            cur = sp.zout;
            cref = 0;
            ncur = sp.nout;
            scur = s0 + sp.uout * hs;
            wcur = hs;
            if (mode == 0) stop = 1; // one witness is enough
          }
        } else if (keep != 0) {
          // Near end first: the child holding the end of smaller z.
          uint c = pc.p0.z <= pc.p3.z ? 0u : 1u;
          level += 1;
          hs *= 0.5f;
          idx = 2u * idx + c;
          lbit = lbit << 1u;
          first = (first & ~lbit) | (c != 0u ? lbit : 0u);
          pc = curve_half(pc, c);
          have = 1;
          down = 1;
        }
      }
      if (stop != 0) break;
      if (down == 0) {
        // Next: the sibling if this is the first child visited, else up.
        int done = 1;
        while (level > 0) {
          uint cb = (first & lbit) != 0u ? 1u : 0u;
          if ((idx & 1u) == cb) {
            idx = idx ^ 1u;
            done = 0;
            break;
          }
          idx = idx >> 1u;
          lbit = lbit >> 1u;
          level -= 1;
          hs *= 2.0f;
        }
        if (done != 0) break;
      }
    }
    if (inside == 0 || cur > zmax) break; // outside: best is the first entry
    if (mode == 2 && !(cur > cur0)) break; // no leaf extended the interval
    mode = inside != 0 ? 2 : 1;
  }
  if (inside != 0) {
    refined = cref;
    rt.found = cur <= zmax ? 1 : 0;
    rt.z = cur;
    rt.s = scur;
    rt.nrm = ncur;
    wbest = wcur;
  }
  if (rt.found != 0 && refined == 0)
    rt = curve_refine(f, rt, min(16.0f * wbest, 0.25f), inside != 0 ? 1.0f : -1.0f, ttol, 2);
  return rt;
}

KERNEL_NS_END
#endif
