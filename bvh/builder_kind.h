// The binary-BVH builders a scene can be built with (bvh/builder.h, docs/builders.md).
#pragma once
#include <string>
#include <vector>

namespace masq {

enum class Builder { Sah, Sbvh, SahReinsert, SbvhReinsert, Sah4, SahPriced };
// "sah", "sbvh", "sah+reinsert", "sbvh+reinsert", "sah4", "sah-priced"
const char* builder_name(Builder b);
Builder parse_builder(const std::string& name); // throws masq::Error naming the choices
const std::vector<Builder>& all_builders();
inline bool builder_splits(Builder b) { return b == Builder::Sbvh || b == Builder::SbvhReinsert; }
// Primitives per priced block of a BLAS leaf over primitives (SahOptions::leaf_block).
inline int builder_leaf_block(Builder b) { return b == Builder::Sah4 ? 4 : 1; }
inline bool builder_reinserts(Builder b) { return b == Builder::SahReinsert || b == Builder::SbvhReinsert; }
// Whether a BLAS over primitives prices each leaf primitive at its type's intersector
// price against a box step (blas_isect_price in bvh/structure_cost.h) rather than at 1.
inline bool builder_prices_isect(Builder b) { return b == Builder::SahPriced; }

} // namespace masq
