// masq info: which backends run here, on what device and driver, and why not.
#include "cli/commands.h"
#include "host/backend.h"
#include <fmt/format.h>

namespace masq::cli {

Action add_info(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("info", "List backends, devices and driver versions (and why any is unavailable)");
  cmd->footer("Backends: " + backend_table.help() + ".\n\nExamples:\n"
              "  masq info                                    exit 0 when at least one backend runs here, else 1\n"
              "  VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.json masq info   pick the Vulkan driver");
  return [] {
    int available = 0;
    for (const BackendRow& r : backend_table.rows()) {
      try {
        std::unique_ptr<Backend> be = r.make();
        fmt::print("{:<9} available    {}\n", r.name, be->device_name());
        ++available;
      } catch (const std::exception& e) {
        fmt::print("{:<9} unavailable  {}\n", r.name, e.what());
      }
    }
    return available > 0 ? 0 : 1;
  };
}

} // namespace masq::cli
