// The BLAS occlusion order chosen by measurement (AccelOptions::blas_occlusion,
// kernels/child_order.h). The order decides only how soon an occlusion query meets an
// occluder: the structure, and whether each ray is occluded, are the same in both. Which
// order is faster depends on the scene (hair in one BLAS: starts-last; the default
// bundle and clusters: nearest, docs/results.md, twelfth round), so the peers suite
// traces its chosen structure's pilot shadow rays in both and keeps the faster.
#pragma once
#include "bench/peer_rounds.h"
#include "bvh/packed_scene.h"
#include "host/backend.h"
#include <cstddef>
#include <span>

namespace masq {

struct OcclusionOrderChoice {
  BlasOcclusion order = BlasOcclusion::Nearest;
  Spread nearest_cpu_s;     // CPU time of a sample, per round: median and range
  Spread starts_last_cpu_s;
  nlohmann::json json() const;
};

// Whether the order can change a walk of `ps`: some BLAS has more than its root node, so
// a BLAS node has inner children (the masquerade method over thin primitives alone has
// no BLAS nodes at all: its entries' unit boxes are tested in place).
bool blas_order_matters(const PackedScene& ps);

// `ps` with its occlusion queries' BLAS order set to `order` (KernelFeatures::
// blas_starts_last), everything else as it was.
PackedScene with_blas_occlusion(PackedScene ps, BlasOcclusion order);

// `ps` in both orders, each uploaded once to a backend of its own (`nearest`,
// `starts_last`: two of one kind), its occlusion queries of `rays` timed round by round
// (time_round_by_round: `rounds` after a warm-up, each sample the set repeated to at
// least `sample_rays` rays). StartsLast is kept only when its median CPU time is lower
// than nearest's by more than `margin` (a fraction): within the noise, the order every
// closest-hit query takes.
OcclusionOrderChoice choose_blas_occlusion(Backend& nearest, Backend& starts_last, const PackedScene& ps,
                                           std::span<const kernel::Ray> rays, std::size_t sample_rays, int rounds,
                                           double margin);

} // namespace masq
