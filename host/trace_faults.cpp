#include "host/trace_faults.h"
#include "masq/error.h"
#include "masq/knobs.h"
#include <fmt/format.h>
#include <algorithm>
#include <climits>

namespace masq {

std::int32_t step_budget(std::size_t nodes) {
  return static_cast<std::int32_t>(std::clamp<std::size_t>(nodes, 1, INT32_MAX));
}

int diagnose_ray_count() {
  return static_cast<int>(knob_integer(Knob::Diagnose).value_or(0));
}

std::string describe_fault(std::size_t ray, const kernel::Hit& h) {
  const int what = h.fault & 0xff;
  const int level = h.fault >> 8;
  const char* what_name = what == MASQ_FAULT_STACK_FULL    ? "a push onto the full stack"
                          : what == MASQ_FAULT_STEP_BUDGET ? "past the step budget"
                                                           : "an unknown fault";
  const char* level_name = level == MASQ_LEVEL_TLAS   ? "TLAS"
                           : level == MASQ_LEVEL_BLAS ? "BLAS"
                           : level == MASQ_LEVEL_BV   ? "bv hierarchy"
                                                      : "unknown";
  return fmt::format("ray {}: {} in a {} walk at node {}, stack depth {} (fault word {:#x})", ray, what_name,
                     level_name, h.fault_node, h.fault_depth, static_cast<unsigned>(h.fault));
}

void check_trace_faults(std::string_view backend, std::string_view device, std::span<const kernel::Hit> hits,
                        std::int32_t budget) {
  std::size_t stack_full = 0, over_budget = 0, other = 0;
  for (const kernel::Hit& h : hits) {
    if (h.fault == 0) continue;
    const int what = h.fault & 0xff;
    if (what == MASQ_FAULT_STACK_FULL) ++stack_full;
    else if (what == MASQ_FAULT_STEP_BUDGET) ++over_budget;
    else ++other;
  }
  const std::size_t faults = stack_full + over_budget + other;
  if (faults == 0) return;
  const int listed = diagnose_ray_count();
  std::string msg = fmt::format(
      "{} on '{}': the traversal stopped {} of {} rays ({} on a full stack, {} past the step budget of {} steps{}): "
      "a cycle in the structure, or node data or stack entries read wrong",
      backend, device, faults, hits.size(), stack_full, over_budget, budget,
      other ? fmt::format(", {} with an unknown fault word", other) : std::string());
  if (listed == 0) {
    msg += "; MASQ_DIAGNOSE=8 lists the first rays' state";
  } else {
    int shown = 0;
    for (std::size_t i = 0; i < hits.size() && shown < listed; ++i)
      if (hits[i].fault != 0) {
        msg += "\n  " + describe_fault(i, hits[i]);
        ++shown;
      }
  }
  throw Error(msg);
}

} // namespace masq
