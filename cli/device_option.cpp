#include "cli/device_option.h"
#include "host/backend.h"
#include "masq/error.h"

namespace masq::cli {

namespace {

// "MASQ_VK_DEVICE, MASQ_RQ_DEVICE, ...": every API's variable, from device_api_table.
std::string selector_variables() {
  std::string out;
  for (const DeviceApiRow& r : device_api_table.rows()) out += (out.empty() ? "" : ", ") + std::string(knob_name(r.knob));
  return out;
}

} // namespace

void add_device_option(CLI::App& cmd, std::string& value) {
  cmd.add_option("--device", value,
                 "Device of the GPU backends: SEL (vulkan and opencl; rayquery and rtpipeline follow vulkan) or "
                 "api=SEL[,api=SEL] with api " +
                     device_api_table.choices() +
                     "; SEL is an index of `masq info`'s list or a name substring (overrides " + selector_variables() +
                     ")")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            try {
              parse_device_option(v);
            } catch (const Error& e) {
              return e.what();
            }
            return "";
          },
          "SEL|api=SEL,..."));
}

void apply_device_option(const std::string& value, std::span<const std::string> backends) {
  if (!value.empty())
    for (const auto& [api, selector] : parse_device_option(value)) set_device_selector(api, selector, "--device");
  check_device_selectors(backends);
}

} // namespace masq::cli
