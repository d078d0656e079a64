// masq info: which backends run here, on what device and driver, and why not; then
// every device of every GPU API and which one each backend takes. With --env: the
// environment variables masq reads, with their values (cli/knob_table.h).
#include "cli/commands.h"
#include "cli/knob_table.h"
#include "host/backend.h"
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <memory>
#include <set>

namespace masq::cli {

namespace {

std::string gib(std::uint64_t bytes) { return fmt::format("{:.1f} GiB", double(bytes) / (1024.0 * 1024.0 * 1024.0)); }

void print_api(const ApiDevices& a) {
  fmt::print("\n{} devices (choose with {} or --device: an index or a name substring)\n", a.api, a.selectors);
  if (!a.unavailable.empty()) {
    fmt::print("  none: {}\n", a.unavailable);
    return;
  }
  const bool vulkan = a.api == "Vulkan";
  fmt::print("  {:<4}{:<16}{:<12}{:<10}{:<11}{:<13}{:<29}{}\n", "idx", "type", "memory", "subgroup", "ray query",
             "rt pipeline", "masq picks for", "name [driver]");
  std::set<std::string> sources;
  for (std::size_t i = 0; i < a.devices.size(); ++i) {
    const DeviceInfo& d = a.devices[i];
    std::string picked;
    for (const auto& [backend, choice] : a.picks)
      if (choice.position == static_cast<int>(i)) picked += (picked.empty() ? "" : ",") + backend;
    sources.insert(d.subgroup_source);
    fmt::print("  {:<4}{:<16}{:<12}{:<10}{:<11}{:<13}{:<29}{}{}\n", d.index, device_type_table.name(d.type),
               gib(d.memory_bytes), d.subgroup_size ? std::to_string(d.subgroup_size) : "-",
               vulkan ? (d.no_ray_query.empty() ? "yes" : "no") : "-",
               vulkan ? (d.no_ray_pipeline.empty() ? "yes" : "no") : "-", picked.empty() ? "-" : picked, d.name,
               d.driver.empty() ? "" : " [" + d.driver + "]");
    if (!d.unusable.empty()) fmt::print("      unusable: {}\n", d.unusable);
  }
  fmt::print("  memory: {}; subgroup: {}\n",
             vulkan ? "the largest DEVICE_LOCAL heap" : "CL_DEVICE_GLOBAL_MEM_SIZE",
             fmt::join(sources, "; "));
  for (const auto& [backend, choice] : a.picks)
    if (choice.position < 0) fmt::print("  {}: no device: {}\n", backend, choice.why);
}

} // namespace

Action add_info(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("info", "List backends, devices and driver versions (and why any is unavailable)");
  cmd->footer("Backends: " + backend_table.help() +
              ".\nDevices: best first discrete GPU > integrated > virtual > accelerator > cpu (ties: the driver's "
              "order); MASQ_VK_DEVICE, MASQ_RQ_DEVICE, MASQ_RT_DEVICE, MASQ_CL_DEVICE or --device choose another.\n\nExamples:\n"
              "  masq info                                    exit 0 when at least one backend runs here, else 1\n"
              "  VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.json masq info   pick the Vulkan driver\n"
              "  MASQ_VK_DEVICE=1 masq info                   which device each backend takes with that selector\n"
              "  masq info --env                              every MASQ_* variable: value, default, meaning");
  auto env = std::make_shared<bool>(false);
  auto markdown = std::make_shared<bool>(false);
  cmd->add_flag("--env", *env, "List the environment variables masq reads (its knobs) with their values, not the devices");
  cmd->add_flag("--markdown", *markdown, "With --env: the table as docs/knobs.md has it, without the values")
      ->needs(cmd->get_option("--env"));
  return [env, markdown] {
    if (*env) {
      fmt::print("{}", *markdown ? knob_table_markdown() : knob_table_text());
      return 0;
    }
    int available = 0;
    for (const BackendRow& r : backend_table.rows()) {
      try {
        std::unique_ptr<Backend> be = r.make();
        fmt::print("{:<11} available    {}\n", r.name, be->device_name());
        ++available;
      } catch (const std::exception& e) {
        fmt::print("{:<11} unavailable  {}\n", r.name, e.what());
      }
    }
    std::vector<std::string> order = best_backend_order();
    fmt::print("best (the API's and Python's default Context) tries: {} (a GPU backend on a device that runs on "
               "the host's cores comes after cpu)\n",
               fmt::join(order, ", "));
    for (const ApiDevices& a : list_devices()) print_api(a);
    return available > 0 ? 0 : 1;
  };
}

} // namespace masq::cli
