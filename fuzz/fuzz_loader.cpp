// libFuzzer entry for one file loader, chosen at compile time by MASQ_FUZZ_FORMAT
// (tfx, hair, swc, trk, tck, ply, obj, nff, json). A loader may reject the input with
// masq::Error; anything else (a crash, a sanitizer report, another exception type, a
// scene that fails validation after a successful load) is a finding.
#include "fuzz/fuzz_load.h"
#include <nlohmann/json.hpp>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>

#define MASQ_STR2(x) #x
#define MASQ_STR(x) MASQ_STR2(x)

namespace {

// A description may ask a generator for up to 2^30 strands: valid, just slow. Inputs
// whose size parameters exceed 100 are skipped so the fuzzer spends its time on parsing
// and checking, not on generating; every other number reaches the loader unchanged.
bool asks_for_big_generator(const nlohmann::json& j) {
  static const char* const kSizes[] = {"count", "strands", "points", "lines", "steps", "subdiv"};
  if (j.is_array()) {
    for (const auto& e : j)
      if (asks_for_big_generator(e)) return true;
  } else if (j.is_object()) {
    for (const auto& [key, value] : j.items()) {
      for (const char* k : kSizes)
        if (key == k && value.is_number() && !(value.get<double>() <= 100.0)) return true;
      if (asks_for_big_generator(value)) return true;
    }
  }
  return false;
}

bool skip_json(const std::uint8_t* data, std::size_t size) {
  try {
    return asks_for_big_generator(nlohmann::json::parse(data, data + size));
  } catch (const nlohmann::json::exception&) {
    return false; // not JSON the harness can read: the loader must reject it cleanly
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  constexpr std::string_view format = MASQ_STR(MASQ_FUZZ_FORMAT);
  std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  if (format == "json" && skip_json(data, size)) return -1;
  try {
    masq::Scene s = masq::fuzz::load(format, bytes);
    // A loader that returns must return a scene the rest of masq accepts.
    masq::validate_scene(s);
  } catch (const masq::Error&) {
    // Rejected with a message: the expected outcome for bad input.
  }
  return 0;
}
