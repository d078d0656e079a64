#include "bench/driver_calls.h"
#include "bench/bench_report.h"
#include "host/backend.h"
#include <fmt/format.h>

namespace masq {

std::vector<std::string> driver_backends(const std::vector<std::string>& backends) {
  std::vector<std::string> out;
  for (const std::string& b : backends)
    if (driver_traversal(b)) out.push_back(b);
  return out;
}

Table driver_calls_table(const std::string& title, const std::vector<std::string>& label_header,
                         const std::vector<DriverCallsCase>& cases, const std::vector<std::string>& backends,
                         RaySet set, nlohmann::json& json) {
  const std::vector<std::string> driver = driver_backends(backends);
  Table t;
  t.title = title;
  t.header = label_header;
  t.left_columns = static_cast<int>(label_header.size());
  for (const std::string& b : driver) {
    t.header.push_back(b + " calls/ray ref -> masq (ref/masq)");
    t.header.push_back(b + " Mrays/s");
  }
  json = nlohmann::json::array();
  for (const DriverCallsCase& c : cases) {
    std::vector<std::string> line = c.label;
    bool any = false;
    for (const std::string& b : driver) {
      const BenchRow* r = find_row(*c.rows, b, Method::Ref, set);
      const BenchRow* m = find_row(*c.rows, b, Method::Masq, set);
      line.push_back(r && m && m->isect_calls > 0
                         ? fmt::format("{:.2f} -> {:.2f} ({:.1f}x)", r->isect_calls, m->isect_calls,
                                       r->isect_calls / m->isect_calls)
                         : "n/a");
      std::string speeds;
      nlohmann::json j = {{"backend", b}, {"case", c.label}};
      for (const Method method : method_table.values()) {
        const BenchRow* row = find_row(*c.rows, b, method, set);
        if (!row || !row->unavailable.empty()) continue;
        speeds += fmt::format("{}{} {:.3g}", speeds.empty() ? "" : ", ", method_name(method), row->mrays_per_s());
        j["mrays_per_s"][method_name(method)] = row->mrays_per_s();
        j["isect_per_ray"][method_name(method)] = row->isect_calls;
        any = true;
      }
      line.push_back(speeds.empty() ? "n/a" : speeds);
      json.push_back(j);
    }
    if (any) t.add(line);
  }
  t.notes = {"calls/ray: rayquery counts the candidates its ray query hands the shader, rtpipeline the intersection- "
             "and any-hit-shader invocations the driver makes (both: the driver's own BVH over the same boxes); "
             "ref/masq is the paper's Fig. 10 ratio; Mrays/s of the counter-free variant per method"};
  return t;
}

} // namespace masq
