// The rays of Context.trace and Context.occluded, in whichever form numpy users hold
// them: origins and directions of any leading shape (..., 3) broadcast against each
// other and against tmin and tmax; (..., 6) rays holding origin and direction in one row
// (Open3D's layout); or a masq.ray_dtype array of any shape. Results take the rays'
// leading shape: hits of an (H, W, 3) grid are (H, W).
#pragma once
#include "bindings.h"
#include <span>
#include <vector>

namespace masq::py {

struct RayInput {
  pyb::array given;                // a ray_dtype array used where it lies, or empty
  std::vector<pyb::ssize_t> shape; // the rays' shape: the shape of hits, counters and flags
  std::span<const api::Ray> rays;  // the rays in C order (given's, or a per-thread buffer)
};

// Checks and packs the rays; errors name `function` and the argument ("Context.trace:
// origins: NaN in row 2 (column 0)"). tmin and tmax: numbers, arrays or None (0 and +inf;
// with a ray_dtype array they must be None, its fields holding the bounds). An infinite
// tmax becomes the largest float, which every backend's arithmetic handles.
RayInput ray_input(const pyb::handle& origins, const pyb::handle& directions, const pyb::handle& tmin,
                   const pyb::handle& tmax, const char* function);

} // namespace masq::py
