// The loader a fuzz input goes to, by format name: shared by the libFuzzer targets
// (fuzz/fuzz_loader.cpp) and the regression replay (tests/test_fuzz_regressions.cpp), so
// a kept finding is replayed through exactly the call that found it.
#pragma once
#include "masq/error.h"
#include "scenes/loaders/load_description.h"
#include "scenes/loaders/load_hair.h"
#include "scenes/loaders/load_nff.h"
#include "scenes/loaders/load_obj.h"
#include "scenes/loaders/load_ply.h"
#include "scenes/loaders/load_swc.h"
#include "scenes/loaders/load_tracks.h"
#include "scenes/loaders/load_tressfx.h"
#include <span>
#include <string>
#include <string_view>

namespace masq::fuzz {

inline masq::Scene load(std::string_view format, std::span<const std::byte> bytes) {
  LoadOptions opt;
  // Alternate the strand primitive so both code paths are exercised.
  if (!bytes.empty() && (static_cast<unsigned>(bytes[0]) & 1)) opt.strand_type = PrimType::RoundCone;
  if (format == "tfx") return load_tressfx(bytes, "fuzz.tfx", opt);
  if (format == "hair") return load_hair(bytes, "fuzz.hair", opt);
  if (format == "swc") return load_swc(bytes, "fuzz.swc", opt);
  if (format == "trk") return load_trk(bytes, "fuzz.trk", opt);
  if (format == "tck") return load_tck(bytes, "fuzz.tck", opt);
  if (format == "ply") return load_ply(bytes, "fuzz.ply", opt);
  if (format == "obj") return load_obj(bytes, "fuzz.obj", opt);
  if (format == "nff") return load_nff(bytes, "fuzz.nff", opt);
  // json: relative file references resolve in a directory that does not exist, so a
  // description can only reach files by absolute path (non-regular files are refused).
  std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  return load_description_text(text, "fuzz.json", "/nonexistent-masq-fuzz-dir");
}


} // namespace masq::fuzz
