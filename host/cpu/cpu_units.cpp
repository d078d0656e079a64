#include "host/cpu/cpu_units.h"
#include "masq/error.h"
#include <string>

namespace masq::cpu {

UnitFn find_unit(std::span<const CpuUnit> units, std::string_view family,
                 const std::function<int(std::string_view key)>& value_of) {
  for (const CpuUnit& u : units) {
    bool match = true;
    for (const UnitAxis& a : u.axes)
      if (!a.key.empty() && value_of(a.key) != a.value) match = false;
    if (match) return u.fn;
  }
  std::string wanted;
  if (!units.empty())
    for (const UnitAxis& a : units.front().axes)
      if (!a.key.empty()) wanted += (wanted.empty() ? "" : ", ") + std::string(a.key) + " " + std::to_string(value_of(a.key));
  throw Error("cpu: no " + std::string(family) + " kernel unit was compiled for " + wanted +
              " (cmake/cpu_units.cmake, kernels/variant_table.h)");
}

} // namespace masq::cpu
