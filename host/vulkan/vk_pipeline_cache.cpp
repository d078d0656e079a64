#include "host/vulkan/vk_pipeline_cache.h"
#include "host/vulkan/vk_check.h"
#include "masq/knobs.h"
#include <fmt/format.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

namespace masq::vk {
namespace {

constexpr char kCacheFileMagic[8] = {'M', 'A', 'S', 'Q', 'V', 'K', 'P', 'C'};
constexpr std::uint32_t kFormat = 1;
// magic, format, vendor, device, driver version, deviceUUID, pipelineCacheUUID, size, checksum
constexpr std::size_t kHeaderBytes = 8 + 4 * 4 + 2 * VK_UUID_SIZE + 8 + 8;
// VkPipelineCacheHeaderVersionOne: headerSize, headerVersion, vendorID, deviceID, pipelineCacheUUID
constexpr std::size_t kDriverHeaderBytes = 4 * 4 + VK_UUID_SIZE;

// FNV-1a: catches truncation and flipped bytes, which some drivers do not check for.
std::uint64_t checksum(const std::uint8_t* p, std::size_t n) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}

// Appends to a buffer sized in advance (a growing vector trips GCC 12's -Warray-bounds).
struct Writer {
  std::uint8_t* p;
  void bytes(const void* src, std::size_t n) {
    std::memcpy(p, src, n);
    p += n;
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof(T));
  }
};

template <class T>
T get(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

std::string hex(const std::uint8_t* p, std::size_t n) {
  std::string s;
  for (std::size_t i = 0; i < n; ++i) s += fmt::format("{:02x}", p[i]);
  return s;
}

} // namespace

std::vector<std::uint8_t> encode_pipeline_cache(const PipelineCacheKey& key,
                                                const std::vector<std::uint8_t>& driver_data) {
  std::vector<std::uint8_t> out(kHeaderBytes + driver_data.size());
  Writer w{out.data()};
  w.bytes(kCacheFileMagic, sizeof kCacheFileMagic);
  w.value(kFormat);
  w.value(key.vendor_id);
  w.value(key.device_id);
  w.value(key.driver_version);
  w.bytes(key.device_uuid, VK_UUID_SIZE);
  w.bytes(key.cache_uuid, VK_UUID_SIZE);
  w.value(static_cast<std::uint64_t>(driver_data.size()));
  w.value(checksum(driver_data.data(), driver_data.size()));
  if (!driver_data.empty()) w.bytes(driver_data.data(), driver_data.size());
  return out;
}

std::vector<std::uint8_t> decode_pipeline_cache(const PipelineCacheKey& key, const std::vector<std::uint8_t>& file,
                                                std::string& why) {
  why.clear();
  auto reject = [&](const char* reason) {
    why = reason;
    return std::vector<std::uint8_t>{};
  };
  if (file.size() < kHeaderBytes) return reject("shorter than its header");
  const std::uint8_t* p = file.data();
  if (std::memcmp(p, kCacheFileMagic, sizeof kCacheFileMagic) != 0) return reject("not a masq pipeline cache");
  p += sizeof kCacheFileMagic;
  if (get<std::uint32_t>(p) != kFormat) return reject("another format version");
  if (get<std::uint32_t>(p + 4) != key.vendor_id || get<std::uint32_t>(p + 8) != key.device_id)
    return reject("another device (vendor/device id)");
  if (get<std::uint32_t>(p + 12) != key.driver_version) return reject("another driver version");
  p += 16;
  if (std::memcmp(p, key.device_uuid, VK_UUID_SIZE) != 0) return reject("another device (deviceUUID)");
  if (std::memcmp(p + VK_UUID_SIZE, key.cache_uuid, VK_UUID_SIZE) != 0)
    return reject("another driver build (pipelineCacheUUID)");
  p += 2 * VK_UUID_SIZE;
  const auto size = get<std::uint64_t>(p);
  const auto sum = get<std::uint64_t>(p + 8);
  if (size != file.size() - kHeaderBytes) return reject("truncated or padded");
  const std::uint8_t* data = file.data() + kHeaderBytes;
  if (checksum(data, size) != sum) return reject("checksum mismatch (corrupt)");
  // The driver's own header (Vulkan spec, "Pipeline Cache Header").
  if (size < kDriverHeaderBytes) return reject("driver data shorter than its header");
  const auto header_size = get<std::uint32_t>(data);
  if (header_size < kDriverHeaderBytes || header_size > size) return reject("driver header size out of range");
  if (get<std::uint32_t>(data + 4) != VK_PIPELINE_CACHE_HEADER_VERSION_ONE) return reject("driver header version");
  if (get<std::uint32_t>(data + 8) != key.vendor_id || get<std::uint32_t>(data + 12) != key.device_id ||
      std::memcmp(data + 16, key.cache_uuid, VK_UUID_SIZE) != 0)
    return reject("driver header names another device");
  return std::vector<std::uint8_t>(data, data + size);
}

std::string masq_cache_dir() {
  if (std::optional<std::string> d = knob_text(Knob::CacheDir)) return *d; // "" turns persistence off
  if (std::optional<std::string> x = system_env("XDG_CACHE_HOME"); x && !x->empty()) return *x + "/masq";
  if (std::optional<std::string> h = system_env("HOME"); h && !h->empty()) return *h + "/.cache/masq";
  return "";
}

PipelineCache::PipelineCache(VkPhysicalDevice physical, VkDevice device)
    : device_(device), cache_(device, vkDestroyPipelineCache) {
  VkPhysicalDeviceIDProperties id{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES};
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &id};
  vkGetPhysicalDeviceProperties2(physical, &p2);
  key_.vendor_id = p2.properties.vendorID;
  key_.device_id = p2.properties.deviceID;
  key_.driver_version = p2.properties.driverVersion;
  std::memcpy(key_.device_uuid, id.deviceUUID, VK_UUID_SIZE);
  std::memcpy(key_.cache_uuid, p2.properties.pipelineCacheUUID, VK_UUID_SIZE);

  std::vector<std::uint8_t> initial;
  if (std::string dir = masq_cache_dir(); !dir.empty()) {
    path_ = dir + "/vk-pipelines-" + hex(key_.device_uuid, VK_UUID_SIZE) + ".bin";
    std::ifstream in(path_, std::ios::binary);
    if (in) {
      std::vector<std::uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      initial = decode_pipeline_cache(key_, file, why_);
    }
  }
  VkPipelineCacheCreateInfo ci{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
  ci.initialDataSize = initial.size();
  ci.pInitialData = initial.empty() ? nullptr : initial.data();
  VkResult r = vkCreatePipelineCache(device_, &ci, nullptr, cache_.put());
  if (r != VK_SUCCESS) cache_.release();
  if (r != VK_SUCCESS && !initial.empty()) { // the driver refused the data: start empty
    why_ = fmt::format("vkCreatePipelineCache refused it ({})", result_name(r));
    initial.clear();
    ci.initialDataSize = 0;
    ci.pInitialData = nullptr;
    r = vkCreatePipelineCache(device_, &ci, nullptr, cache_.put());
    if (r != VK_SUCCESS) cache_.release();
  }
  if (r != VK_SUCCESS) throw_vk_error("vkCreatePipelineCache", r, __FILE__, __LINE__);
  loaded_ = !initial.empty();
  loaded_bytes_ = initial.size();
  loaded_sum_ = checksum(initial.data(), initial.size());
}

PipelineCache::~PipelineCache() {
  try {
    save();
  } catch (...) { // a cache that cannot be written costs the next run a compile, nothing more
  }
}

void PipelineCache::save() {
  if (path_.empty() || !cache_) return;
  std::size_t n = 0;
  if (vkGetPipelineCacheData(device_, cache_.get(), &n, nullptr) != VK_SUCCESS || n == 0) return;
  std::vector<std::uint8_t> data(n);
  if (vkGetPipelineCacheData(device_, cache_.get(), &n, data.data()) != VK_SUCCESS) return;
  data.resize(n);
  if (n == loaded_bytes_ && checksum(data.data(), n) == loaded_sum_) return; // nothing new
  const std::vector<std::uint8_t> file = encode_pipeline_cache(key_, data);
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(path_).parent_path(), ec);
  // Another process may save the same file at the same time: each writes its own
  // temporary and renames it, so a reader sees one whole file or the other.
  const std::string tmp = fmt::format("{}.{}.tmp", path_, static_cast<long>(::getpid()));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return;
    out.write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
    if (!out) {
      std::remove(tmp.c_str());
      return;
    }
  }
  std::filesystem::rename(tmp, path_, ec);
  if (ec) {
    std::remove(tmp.c_str());
    return;
  }
  loaded_bytes_ = n;
  loaded_sum_ = checksum(data.data(), n);
}

} // namespace masq::vk
