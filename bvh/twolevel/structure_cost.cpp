#include "bvh/twolevel/structure_cost.h"
#include "bvh/nodes/compact_instance.h"
#include "bvh/bounds/obb.h"
#include "bvh/nodes/wide_bvh.h"
#include "bvh/binary/parallel.h"
#include "scenes/prim_table.h"
#include <cmath>
#include <glm/glm.hpp>
#include <vector>

namespace masq {

double isect_type_factor(int kernel_prim_type) {
  if (kernel_prim_type < 0 || kernel_prim_type >= MASQ_PRIM_TYPE_COUNT) return 1.0;
  return scene_prim_row_of_kernel_type(kernel_prim_type).isect_factor;
}

double blas_isect_price(int kernel_prim_type) {
  const CostPrices p;
  return p.isect * isect_type_factor(kernel_prim_type) / (0.5 * p.node);
}

namespace {

glm::dmat3 linear_part(const Mat3x4f& m) { return from_mat3x4f(m).linear; }

// Surface area of the parallelepiped that the box of extents e becomes under l.
double mapped_area(const glm::dmat3& l, const glm::dvec3& e) {
  glm::dvec3 a = l[0] * e.x, b = l[1] * e.y, c = l[2] * e.z;
  return 2.0 * (glm::length(glm::cross(a, b)) + glm::length(glm::cross(b, c)) + glm::length(glm::cross(c, a)));
}

// Slots of any node format, with the boxes the kernels test (bvh/nodes/wide_bvh.h); an
// o4 slot's box is in its node's frame, mapped back first.
// An axis-aligned slot's frame is the identity: l itself, not l times the inverse of
// the identity (glm's has -0 entries, which change no area: the area squares every
// component), which was most of the walk's time.
double slot_area(const NodeSlot& s, const glm::dmat3& l) {
  const glm::dvec3 e = glm::max(s.box.hi - s.box.lo, glm::dvec3(0.0));
  return mapped_area(s.frame.oriented ? l * s.frame.box_to_space() : l, e);
}

// What the walk needs of one TLAS entry, decoded beforehand (on all threads: a compact
// entry's decode is most of the walk's time on the masquerade TLAS).
struct EntryInfo {
  glm::dmat3 l;          // unit box (masquerade) or BLAS -> world, linear part
  double unit_area = 0;  // masquerade: area of the unit box's image
  int blas_root = -1;
  int type = 0;          // kernel primitive type
};

std::vector<EntryInfo> entry_infos(const PackedScene& ps) {
  std::vector<EntryInfo> out(ps.tlas_entry_count());
  parallel_chunks(out.size(), 1024, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t entry = lo; entry < hi; ++entry) {
      const kernel::Instance inst = tlas_entry_instance(ps, entry);
      EntryInfo& e = out[entry];
      e.l = linear_part(ps.instance_object_to_world[entry]);
      e.blas_root = inst.blas_root;
      e.type = ps.geoms[std::size_t(inst.geom)].type;
      if (inst.blas_root < 0) e.unit_area = mapped_area(e.l, glm::dvec3(2.0));
    }
  });
  return out;
}

struct Walker {
  const PackedScene& ps;
  double root_area = 1.0;
  StructureCost c;
  StructureCost tri; // what triangle instances added to c
  std::vector<EntryInfo> entries; // per TLAS entry (the TLAS walk)

  // A BLAS entered with probability p_root (its root node is visited then); its boxes
  // are mapped to the world by l. Leaves weigh their count by the geometry's price.
  void blas(int node, double p, const glm::dmat3& l, double factor) {
    c.nodes += p;
    for (const NodeSlot& s : node_slots(ps, node)) {
      if (s.count < 0) continue;
      double pc = std::min(p, slot_area(s, l) / root_area);
      if (s.count == 0)
        blas(s.child, pc, l, factor);
      else
        c.isects += pc * s.count * factor;
    }
  }

  // A TLAS leaf reference: an Instance or a compact masquerade entry (PackedScene::tlas_ref).
  void instance(std::int32_t ref, double p_slot) {
    const EntryInfo& e = entries[ps.tlas_entry(ref)];
    int type = e.type;
    double factor = isect_type_factor(type);
    StructureCost before = c;
    c.transforms += p_slot;
    if (e.blas_root >= 0)
      blas(e.blas_root, p_slot, e.l, factor);
    else // masquerade: the intersector runs when the ray is in the unit box's image (the OBB)
      c.isects += std::min(p_slot, e.unit_area / root_area) * factor;
    if (scene_prim_row_of_kernel_type(type).mesh) {
      tri.nodes += c.nodes - before.nodes;
      tri.transforms += c.transforms - before.transforms;
      tri.isects += c.isects - before.isects;
    }
  }

  void tlas(int node, double p) {
    c.nodes += p;
    const glm::dmat3 id(1.0);
    for (const NodeSlot& s : node_slots(ps, node)) {
      if (s.count < 0) continue;
      double pc = std::min(p, slot_area(s, id) / root_area);
      if (s.count == 0) {
        tlas(s.child, pc);
        continue;
      }
      for (int j = 0; j < s.count; ++j) instance(ps.refs[std::size_t(s.child + j)], pc);
    }
  }
};

// Area of the union box of a node's children under l (the scene box for the TLAS root).
double node_box_area(const PackedScene& ps, int node, const glm::dmat3& l) {
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const NodeSlot& s : node_slots(ps, node)) {
    if (s.count < 0) continue;
    lo = glm::min(lo, s.box.lo);
    hi = glm::max(hi, s.box.hi);
  }
  if (lo.x > hi.x) return 0.0;
  return mapped_area(l, hi - lo);
}

} // namespace

StructureCost structure_cost(const PackedScene& ps, const CostPrices& prices) {
  Walker w{ps};
  if (ps.tlas_root < 0) return w.c;
  if (ps.features.single_blas) {
    // No TLAS stage: the BLAS root is where every ray starts.
    const kernel::Instance& only = ps.instances[0];
    const glm::dmat3 l = linear_part(ps.instance_object_to_world[0]);
    w.root_area = std::max(node_box_area(ps, only.blas_root, l), 1e-300);
    int type = ps.geoms[std::size_t(only.geom)].type;
    w.blas(only.blas_root, 1.0, l, isect_type_factor(type));
    if (scene_prim_row_of_kernel_type(type).mesh) w.tri = w.c;
  } else {
    w.root_area = std::max(node_box_area(ps, ps.tlas_root, glm::dmat3(1.0)), 1e-300);
    w.entries = entry_infos(ps);
    w.tlas(ps.tlas_root, 1.0);
  }
  auto priced = [&](const StructureCost& k) {
    return prices.node * k.nodes + prices.transform * k.transforms + prices.isect * k.isects;
  };
  w.c.total = priced(w.c);
  w.c.triangles = priced(w.tri);
  return w.c;
}

} // namespace masq
