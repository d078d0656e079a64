#include "host/device_choice.h"
#include "masq/error.h"
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>
#include <mutex>

namespace masq {

namespace {

bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

const std::string& need_gap(const DeviceInfo& d, DeviceNeed need) {
  // A device that cannot run the compute kernels cannot run the driver's traversal either.
  if (need == DeviceNeed::Compute || !d.unusable.empty()) return d.unusable;
  return need == DeviceNeed::RayQuery ? d.no_ray_query : d.no_ray_pipeline;
}

std::mutex g_override_mutex;
std::map<DeviceApi, DeviceSelector> g_overrides;

} // namespace

int device_rank(DeviceType type) {
  const auto rows = device_type_table.rows();
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (rows[i].value == type) return static_cast<int>(i);
  return static_cast<int>(rows.size());
}

std::vector<std::size_t> ranked_devices(std::span<const DeviceInfo> devices) {
  std::vector<std::size_t> order(devices.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return device_rank(devices[a].type) < device_rank(devices[b].type);
  });
  return order;
}

bool selector_matches(const DeviceInfo& device, std::string_view selector) {
  if (all_digits(selector)) return selector.size() < 10 && std::stoi(std::string(selector)) == device.index;
  return lower(device.name).find(lower(selector)) != std::string::npos;
}

std::string device_list_text(std::span<const DeviceInfo> devices) {
  if (devices.empty()) return "none";
  std::string out;
  for (const DeviceInfo& d : devices)
    out += (out.empty() ? "" : ", ") + std::to_string(d.index) + " '" + d.name + "' (" +
           device_type_table.name(d.type) + ")";
  return out;
}

DeviceChoice choose_device(std::span<const DeviceInfo> devices, const DeviceSelector& selector,
                           std::string_view api_label, DeviceNeed need) {
  DeviceChoice out;
  bool named_any = false;
  for (std::size_t pos : ranked_devices(devices)) {
    const DeviceInfo& d = devices[pos];
    if (!selector.empty() && !selector_matches(d, selector.value)) continue;
    named_any = true;
    const std::string& gap = need_gap(d, need);
    if (gap.empty()) {
      out.position = static_cast<int>(pos);
      out.why.clear();
      return out;
    }
    // The best-ranked device's reason: the one a user would have expected to run.
    if (out.why.empty()) out.why = "device '" + d.name + "' " + gap;
  }
  if (!named_any && !selector.empty())
    throw Error(selector.source + "='" + selector.value + "' matches no " + std::string(api_label) +
                " device (index or name substring; devices: " + device_list_text(devices) + ")");
  if (out.why.empty()) out.why = "no " + std::string(api_label) + " device";
  return out;
}

DeviceChoice choose_traversal_device(std::span<const DeviceInfo> devices, const DeviceSelector& vulkan,
                                     const DeviceSelector& own, DeviceNeed need, DeviceApi api) {
  if (!own.empty()) return choose_device(devices, own, "Vulkan", need);
  DeviceChoice c = choose_device(devices, vulkan, "Vulkan", DeviceNeed::Compute);
  if (c.position < 0) return c;
  const DeviceInfo& d = devices[static_cast<std::size_t>(c.position)];
  const std::string& gap = need_gap(d, need);
  if (gap.empty()) return c;
  const DeviceApiRow& row = device_api_table.row(api);
  return {-1, "device '" + d.name + "' " + gap + " (" + row.name + " runs on the vulkan backend's device; " + knob_name(row.knob) +
                  " names another)"};
}

DeviceSelector device_selector(DeviceApi api) {
  {
    std::lock_guard<std::mutex> lock(g_override_mutex);
    if (auto it = g_overrides.find(api); it != g_overrides.end()) return it->second;
  }
  const Knob knob = device_api_table.row(api).knob;
  return {knob_text(knob).value_or(""), knob_name(knob)};
}

void set_device_selector(DeviceApi api, std::string value, std::string source) {
  std::lock_guard<std::mutex> lock(g_override_mutex);
  if (value.empty()) g_overrides.erase(api);
  else g_overrides[api] = {std::move(value), std::move(source)};
}

std::vector<std::pair<DeviceApi, std::string>> parse_device_option(std::string_view value) {
  auto bad = [&](const std::string& why) {
    return Error("--device '" + std::string(value) + "': " + why + " (expected SEL, or api=SEL[,api=SEL] with api " +
                 device_api_table.choices() + ")");
  };
  // "api=..." at the start of a segment: the api, else nullptr.
  auto keyed = [](std::string_view seg) -> const DeviceApiRow* {
    std::size_t eq = seg.find('=');
    return eq == std::string_view::npos ? nullptr : device_api_table.find(seg.substr(0, eq));
  };
  std::vector<std::pair<DeviceApi, std::string>> out;
  if (value.empty()) throw bad("empty");
  if (value.find('=') == std::string_view::npos) {
    out.emplace_back(DeviceApi::Vulkan, std::string(value));
    out.emplace_back(DeviceApi::OpenCl, std::string(value));
    return out;
  }
  std::size_t start = 0;
  while (start <= value.size()) {
    std::size_t comma = value.find(',', start);
    std::string_view seg = value.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    if (const DeviceApiRow* row = keyed(seg)) {
      for (const auto& [api, sel] : out)
        if (api == row->value) throw bad(std::string("names ") + row->name + " twice");
      out.emplace_back(row->value, std::string(seg.substr(seg.find('=') + 1)));
    } else if (!out.empty()) {
      out.back().second.append(1, ',').append(seg); // a comma inside a device name
    } else {
      throw bad("'" + std::string(seg.substr(0, seg.find('='))) + "' is no device API");
    }
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  for (const auto& [api, sel] : out)
    if (sel.empty()) throw bad(std::string("no selector after ") + device_api_table.name(api) + "=");
  return out;
}

} // namespace masq
