// The persisted VkPipelineCache (host/vulkan/vk_pipeline_cache.h): the file format
// refuses other devices, drivers and damaged files; on this machine's device a second
// context loads what the first saved, and a corrupt or foreign file is ignored (the
// backend still traces) and replaced. Vulkan missing fails the device test unless
// MASQ_ALLOW_MISSING_BACKENDS=1.
#include "host/vulkan/vk_context.h"
#include "host/vulkan/vk_pipeline_cache.h"
#include "masq/masq.h"
#include "tests/test_env.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using masq::vk::decode_pipeline_cache;
using masq::vk::encode_pipeline_cache;
using masq::vk::PipelineCacheKey;
namespace api = masq::api;

PipelineCacheKey test_key() {
  PipelineCacheKey k;
  k.vendor_id = 0x10de;
  k.device_id = 0x2484;
  k.driver_version = 42;
  for (unsigned i = 0; i < VK_UUID_SIZE; ++i) {
    k.device_uuid[i] = static_cast<std::uint8_t>(i);
    k.cache_uuid[i] = static_cast<std::uint8_t>(100 + i);
  }
  return k;
}

// Driver data with a valid VkPipelineCacheHeaderVersionOne for `k` and a payload.
std::vector<std::uint8_t> driver_blob(const PipelineCacheKey& k) {
  std::vector<std::uint8_t> b(32 + 40, 0xab);
  const std::uint32_t words[4] = {32, VK_PIPELINE_CACHE_HEADER_VERSION_ONE, k.vendor_id, k.device_id};
  std::memcpy(b.data(), words, sizeof words);
  std::memcpy(b.data() + 16, k.cache_uuid, VK_UUID_SIZE);
  return b;
}

std::string rejection(const PipelineCacheKey& k, const std::vector<std::uint8_t>& file) {
  std::string why;
  std::vector<std::uint8_t> data = decode_pipeline_cache(k, file, why);
  EXPECT_EQ(data.empty(), !why.empty());
  return why;
}

TEST(PipelineCacheFile, RoundTripsAndRefusesOtherDevicesAndDamage) {
  const PipelineCacheKey k = test_key();
  const std::vector<std::uint8_t> blob = driver_blob(k);
  const std::vector<std::uint8_t> file = encode_pipeline_cache(k, blob);
  std::string why;
  EXPECT_EQ(decode_pipeline_cache(k, file, why), blob);
  EXPECT_EQ(why, "");

  PipelineCacheKey other = k;
  other.device_uuid[3] ^= 1;
  EXPECT_NE(rejection(other, file).find("deviceUUID"), std::string::npos);
  other = k;
  other.driver_version += 1;
  EXPECT_NE(rejection(other, file).find("driver version"), std::string::npos);
  other = k;
  other.cache_uuid[0] ^= 1;
  EXPECT_NE(rejection(other, file).find("pipelineCacheUUID"), std::string::npos);

  std::vector<std::uint8_t> bad = file;
  bad[bad.size() - 5] ^= 0x40;
  EXPECT_NE(rejection(k, bad).find("checksum"), std::string::npos);
  bad.assign(file.begin(), file.end() - 1);
  EXPECT_NE(rejection(k, bad).find("truncated"), std::string::npos);
  EXPECT_NE(rejection(k, {}).find("shorter"), std::string::npos);
  bad = file;
  bad[0] = 'X';
  EXPECT_NE(rejection(k, bad).find("not a masq"), std::string::npos);
  // masq's header right but the driver's own header names another device.
  std::vector<std::uint8_t> foreign_blob = blob;
  foreign_blob[8] ^= 1; // vendorID
  EXPECT_NE(rejection(k, encode_pipeline_cache(k, foreign_blob)).find("driver header"), std::string::npos);
}

api::Accel one_capsule() {
  api::Scene s;
  std::vector<api::Capsule> cs = {{{0, -0.5f, 0}, {0, 0.5f, 0}, 0.1f}};
  s.add_capsules(cs);
  return api::Accel::build(s);
}

// Opens the vulkan backend (sharing the compute context), traces one ray, and returns
// whether the context loaded a cache file and why one was ignored.
struct CacheRun {
  bool ok = false;
  bool loaded = false;
  std::string rejected;
  std::string path;
};

CacheRun trace_once() {
  CacheRun r;
  std::shared_ptr<masq::vk::Context> ctx = masq::vk::Context::get("vulkan");
  r.loaded = ctx->pipeline_cache_file().loaded();
  r.rejected = ctx->pipeline_cache_file().rejected();
  r.path = ctx->pipeline_cache_file().path();
  api::Context c("vulkan");
  api::Ray ray;
  ray.org = {0, 0, -5};
  std::vector<api::Hit> hits = c.trace(one_capsule(), {&ray, 1});
  r.ok = hits.size() == 1 && hits[0].hit();
  return r; // the last holders go: the context saves its cache
}

std::vector<std::uint8_t> read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<std::uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_all(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

TEST(PipelineCacheDevice, SecondContextLoadsItAndDamagedFilesAreIgnored) {
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("masq-pipeline-cache-test-" + std::to_string(::getpid()))).string();
  std::filesystem::remove_all(dir);
  setenv("MASQ_CACHE_DIR", dir.c_str(), 1);
  CacheRun first;
  try {
    first = trace_once();
  } catch (const masq::BackendUnavailable& e) {
    if (masq::test::missing_backends_allowed()) GTEST_SKIP() << e.what();
    FAIL() << e.what();
  }
  EXPECT_TRUE(first.ok);
  EXPECT_FALSE(first.loaded);
  ASSERT_EQ(first.path.rfind(dir + "/vk-pipelines-", 0), 0u) << first.path;
  const std::vector<std::uint8_t> saved = read_all(first.path);
  // masq's 72-byte header and at least the driver's 32-byte one.
  ASSERT_GE(saved.size(), 72u + 32u) << "no cache file written at " << first.path;
  std::printf("pipeline cache: %zu bytes at %s\n", saved.size(), first.path.c_str());

  CacheRun second = trace_once();
  EXPECT_TRUE(second.ok);
  EXPECT_TRUE(second.loaded) << second.rejected;

  // Corrupt (a flipped byte in the driver data): ignored, traced anyway, replaced.
  std::vector<std::uint8_t> corrupt = saved;
  corrupt[corrupt.size() - 3] ^= 0x5a;
  write_all(first.path, corrupt);
  CacheRun third = trace_once();
  EXPECT_TRUE(third.ok);
  EXPECT_FALSE(third.loaded);
  EXPECT_NE(third.rejected.find("checksum"), std::string::npos) << third.rejected;
  EXPECT_TRUE(trace_once().loaded) << "the corrupt file was not replaced";

  // Garbage and an empty file: ignored.
  write_all(first.path, std::vector<std::uint8_t>(300, 0x37));
  CacheRun fourth = trace_once();
  EXPECT_TRUE(fourth.ok);
  EXPECT_FALSE(fourth.loaded);
  EXPECT_NE(fourth.rejected.find("not a masq"), std::string::npos) << fourth.rejected;
  write_all(first.path, {});
  CacheRun fifth = trace_once();
  EXPECT_TRUE(fifth.ok);
  EXPECT_FALSE(fifth.loaded);

  std::filesystem::remove_all(dir);
  unsetenv("MASQ_CACHE_DIR");
}

} // namespace
