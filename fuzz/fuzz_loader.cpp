// libFuzzer entry for one file loader, chosen at compile time by MASQ_FUZZ_FORMAT
// (tfx, hair, swc, trk, tck, ply, obj, nff, json). A loader may reject the input with
// masq::Error; anything else (a crash, a sanitizer report, another exception type, a
// scene that fails validation after a successful load) is a finding.
#include "fuzz/fuzz_load.h"
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>

#define MASQ_STR2(x) #x
#define MASQ_STR(x) MASQ_STR2(x)

namespace {

// A description may ask a generator for up to 2^30 strands: valid, just slow. Numbers
// of 4+ digits are skipped so the fuzzer spends its time on parsing, not on generating.
bool has_long_number(std::string_view s) {
  int run = 0;
  for (char c : s) {
    run = (c >= '0' && c <= '9') ? run + 1 : 0;
    if (run >= 4) return true;
  }
  return false;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  constexpr std::string_view format = MASQ_STR(MASQ_FUZZ_FORMAT);
  std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  if (format == "json" && has_long_number({reinterpret_cast<const char*>(data), size})) return -1;
  try {
    masq::Scene s = masq::fuzz::load(format, bytes);
    // A loader that returns must return a scene the rest of masq accepts.
    masq::validate_scene(s);
  } catch (const masq::Error&) {
    // Rejected with a message: the expected outcome for bad input.
  }
  return 0;
}
