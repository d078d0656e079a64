// The options a structure is built with (method, builder, intersector mode, node format,
// curve OBBs, masquerade instance form, BLAS occlusion order), each with its one name
// table (masq/names.h).
// Method, Builder, Mode, NodeFormat and BlasOcclusion are the public API's own enums and tables
// (include/masq/types.h), named here in namespace masq, so the API passes them through
// as they are. A small header of its own: obb.h, prim_bounds.h and packed_scene.h all
// need these types, and none of them needs the others for it.
#pragma once
#include "masq/names.h"
#include "masq/types.h"
#include <string_view>
#include <vector>

namespace masq {

using Method = api::Method;
using api::method_table;
inline const char* method_name(Method m) { return method_table.name(m); }
inline Method parse_method(std::string_view name) { return method_table.parse(name); } // throws masq::Error

using CurveIsect = api::CurveIsect;
using api::curve_isect_table;
inline const char* curve_isect_name(CurveIsect c) { return curve_isect_table.name(c); }
inline CurveIsect parse_curve_isect(std::string_view name) { return curve_isect_table.parse(name); } // throws

using Mode = api::Mode;
using api::mode_table;
inline const char* mode_name(Mode m) { return mode_table.name(m); }
inline Mode parse_mode(std::string_view name) { return mode_table.parse(name); } // throws masq::Error

using NodeFormat = api::NodeFormat;
using api::node_format_table;
inline const char* node_format_name(NodeFormat f) { return node_format_table.name(f); }
inline NodeFormat parse_node_format(std::string_view name) { return node_format_table.parse(name); } // throws

using BlasOcclusion = api::BlasOcclusion;
using api::blas_occlusion_table;
inline const char* blas_occlusion_name(BlasOcclusion b) { return blas_occlusion_table.name(b); }
inline BlasOcclusion parse_blas_occlusion(std::string_view name) { return blas_occlusion_table.parse(name); } // throws

// The binary-BVH builders (bvh/binary/builder.h, docs/builders.md); their parts are columns of
// builder_table.
using Builder = api::Builder;
using api::builder_table;
inline const char* builder_name(Builder b) { return builder_table.name(b); }
inline Builder parse_builder(std::string_view name) { return builder_table.parse(name); } // throws masq::Error
inline std::vector<Builder> all_builders() { return builder_table.values(); }
inline bool builder_splits(Builder b) { return builder_table.row(b).spatial_splits; }
// Primitives per priced block of a BLAS leaf over primitives (SahOptions::leaf_block).
inline int builder_leaf_block(Builder b) { return builder_table.row(b).leaf_block; }
inline bool builder_reinserts(Builder b) { return builder_table.row(b).reinsertion; }
// Whether a BLAS over primitives prices each leaf primitive at its type's intersector
// price against a box step (blas_isect_price in bvh/twolevel/structure_cost.h) rather than at 1.
inline bool builder_prices_isect(Builder b) { return builder_table.row(b).priced_isect; }

// How a curve's OBB is oriented (bvh/bounds/obb.h). paper: Wald et al. 2020's, the chord p0->p3
// as axis and a square cross-section wide enough for the control points' distance to
// the chord plus the radius (a cylinder's box). tight: the same axis, but the
// cross-section axes follow the control polygon's largest offset from the chord, and
// every side is fitted to the control balls' support (never larger than paper).
enum class CurveObb { Paper, Tight };
inline constexpr NameRow<CurveObb> curve_obb_rows[] = {
    {CurveObb::Paper, "paper", "chord axis, a cylinder's square cross-section"},
    {CurveObb::Tight, "tight", "chord axis, cross-section fitted to the control polygon"},
};
inline constexpr NameTable curve_obb_table{"curve OBB", curve_obb_rows};
inline const char* curve_obb_name(CurveObb m) { return curve_obb_table.name(m); }
inline CurveObb parse_curve_obb(std::string_view name) { return curve_obb_table.parse(name); } // throws

// How masquerade primitives are stored (docs/kernels.md, "Compact masquerade
// instances"): compact MasqInstance records or full Instances (kernels/layout.h).
// Cluster and BLAS instances are always full Instances.
enum class MasqInstances { Compact, Full };
inline constexpr NameRow<MasqInstances> masq_instances_rows[] = {
    {MasqInstances::Compact, "compact", "32 bytes: quaternion, bfloat16 scales, owner index"},
    {MasqInstances::Full, "full", "the 64-byte instance of RT hardware"},
};
inline constexpr NameTable masq_instances_table{"masquerade instance form", masq_instances_rows};
inline const char* masq_instances_name(MasqInstances m) { return masq_instances_table.name(m); }
inline MasqInstances parse_masq_instances(std::string_view name) { return masq_instances_table.parse(name); } // throws

} // namespace masq
