// Rays a traversal kernel stopped instead of finishing (kernel::Hit::fault: a push onto a
// full stack, or a walk past its step budget; kernels/layout.h), turned into one error.
// A correct structure read correctly never produces either, so such a ray means a cycle
// in the structure, or node data or stack entries the device read wrong: it must never
// reach a user as a miss. Every backend calls check_trace_faults after a trace.
#pragma once
#include "kernels/layout.h"
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace masq {

// The step budget of one tree walk over a node array of `nodes` nodes (TLAS and every
// BLAS together, or one bv hierarchy): no correct walk of any one tree in it takes more
// steps (each step visits or skips one node of that tree, each reached at most once).
std::int32_t step_budget(std::size_t nodes);

// The first rays whose state MASQ_DIAGNOSE=N asks the fault error to list (0: none; the
// one-line error only). Throws masq::Error for a value that is no non-negative integer.
int diagnose_ray_count();

// One line per faulted ray: "ray I: <what> in a <level> walk at node N, stack depth D".
std::string describe_fault(std::size_t ray, const kernel::Hit& h);

// Throws masq::Error when any hit carries a fault:
//   "<backend> on '<device>': the traversal stopped F of N rays (S on a full stack, B past
//    the step budget of K steps): a cycle in the structure, or node data or stack entries
//    read wrong; MASQ_DIAGNOSE=8 lists the first rays' state"
// followed, with MASQ_DIAGNOSE=N, by the first N faulted rays' state (describe_fault).
// budget: the step budget the trace ran with (for the message).
void check_trace_faults(std::string_view backend, std::string_view device, std::span<const kernel::Hit> hits,
                        std::int32_t budget);

} // namespace masq
