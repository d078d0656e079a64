// Compact masquerade entries (compact_instance.h): the fit's stages run in compact_fit.cpp
// and compact_fit_lanes.cpp (why the stored map is conservative: compact_fit.cpp); here
// the entries' interface, the decode and the owners.
#include "bvh/nodes/compact_instance.h"
#include "bvh/nodes/compact_fit.h"
#include "bvh/bounds/prim_bounds.h"
#include "masq/error.h"
#include <cstdint>
#include <string>

namespace masq {

using namespace compact_fit;

Affine3 decode_masq_instance(const kernel::MasqInstance& c) {
  return decode_with(quat_matrix(half_i16(c.q01, 0), half_i16(c.q01, 1), half_i16(c.q23, 0), half_i16(c.q23, 1)), c);
}

void set_masq_owner(kernel::MasqInstance& c, std::uint32_t owner) {
  if (owner >= std::uint32_t(MASQ_MAX_OWNERS)) throw Error("compact masquerade: owner index over 16 bits");
  c.s2_owner = (c.s2_owner & 0xFFFF0000u) | owner;
}

std::uint32_t masq_owner(const kernel::MasqInstance& c) { return c.s2_owner & MASQ_OWNER_MASK; }

void compact_masquerades(const Geometry& g, std::span<const std::int32_t> prims, const Affine3& xf,
                         std::optional<CompactMasquerade>* const* out) {
  if (prims.size() > std::size_t(kCompactLanes))
    throw Error("compact_masquerades: " + std::to_string(prims.size()) + " primitives, at most " +
                std::to_string(kCompactLanes) + " at once");
  const int n = int(prims.size());
  if (n == 0) return;
  CompactFit f[kCompactLanes];
  CompactFit* lanes[kCompactLanes]; // the live fits, in order
  for (int l = 0; l < n; ++l) lanes[l] = &f[l];
  fit_axes_lanes(lanes, n, g, prims.data(), xf);
  fit_rotation_lanes(lanes, n, xf);
  auto keep_live = [&] {
    int m = 0;
    for (int l = 0; l < n; ++l)
      if (f[l].live) lanes[m++] = &f[l];
    return m;
  };
  int n_live = keep_live();
  if (n_live > 0) fit_extent_lanes(lanes, n_live, xf);
  n_live = keep_live();
  MasqueradeBox* boxes[kCompactLanes];
  std::optional<CompactMasquerade>* live_out[kCompactLanes];
  for (int l = 0, k = 0; l < n; ++l) {
    out[l]->reset();
    if (!f[l].live) continue;
    kernel::MasqInstance& c = f[l].c; // t fitted; the rest packed here, before the decode reads it
    c.prim = prims[std::size_t(l)];
    c.q01 = pack_i16(f[l].qi[0], f[l].qi[1]);
    c.q23 = pack_i16(f[l].qi[2], f[l].qi[3]);
    c.s01 = (f[l].sigma[0] >> 16) | (f[l].sigma[1] & 0xFFFF0000u);
    c.s2_owner = f[l].sigma[2] & 0xFFFF0000u;
    out[l]->emplace().inst = c;
    boxes[k] = &(*out[l])->box; // written in place by complete_lanes
    live_out[k++] = out[l];
  }
  if (n_live == 0) return;
  bool ok[kCompactLanes];
  complete_lanes(lanes, n_live, boxes, ok);
  for (int k = 0; k < n_live; ++k)
    if (!ok[k]) live_out[k]->reset();
}

std::optional<CompactMasquerade> compact_masquerade(const Geometry& g, std::size_t prim, const Affine3& xf) {
  std::optional<CompactMasquerade> cm;
  std::optional<CompactMasquerade>* out[1] = {&cm};
  const std::int32_t p = std::int32_t(prim);
  compact_masquerades(g, std::span<const std::int32_t>(&p, 1), xf, out);
  return cm;
}

kernel::Instance tlas_entry_instance(const PackedScene& s, std::size_t entry) {
  if (entry < s.instances.size()) return s.instances[entry];
  if (entry - s.instances.size() >= s.masq_instances.size())
    throw Error("scene: TLAS entry " + std::to_string(entry) + " of " + std::to_string(s.tlas_entry_count()));
  const kernel::MasqInstance& c = s.masq_instances[entry - s.instances.size()];
  const std::size_t owner = masq_owner(c);
  if (owner >= s.masq_owners.size())
    throw Error("scene: compact masquerade entry " + std::to_string(entry - s.instances.size()) + " names owner " +
                std::to_string(owner) + " of " + std::to_string(s.masq_owners.size()));
  kernel::Instance k{};
  Mat3x4f m = to_mat3x4f(decode_masq_instance(c));
  std::copy(m.begin(), m.end(), k.world_to_object);
  k.blas_root = -1;
  k.geom = s.masq_owners[owner].geom;
  k.prim = c.prim;
  k.scene_inst = s.masq_owners[owner].scene_inst;
  return k;
}

} // namespace masq
