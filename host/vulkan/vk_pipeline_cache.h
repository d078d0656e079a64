// A VkPipelineCache per Context, persisted across runs so that a pipeline's compile time
// does not depend on the driver's own disk cache. The file lives in masq's cache
// directory (MASQ_CACHE_DIR, else $XDG_CACHE_HOME/masq, else $HOME/.cache/masq: beside
// Mesa's and PoCL's kernel caches; MASQ_CACHE_DIR="" turns persistence off), one file per
// device named by its deviceUUID. The file is masq's header (magic, format, vendor,
// device, driver version, deviceUUID, pipelineCacheUUID, size, checksum) followed by the
// driver's data, whose own VkPipelineCacheHeaderVersionOne is checked too: a file from
// another device or driver version, truncated or corrupt, is ignored (and replaced when
// the context ends), never handed to the driver.
#pragma once
#include "host/vulkan/vk_owned.h"
#include <vulkan/vulkan.h>
#include <cstdint>
#include <string>
#include <vector>

namespace masq::vk {

// The identity a cache file must match: what the Vulkan spec says invalidates pipeline
// cache data (vendor, device, pipelineCacheUUID) plus the driver version and the device.
struct PipelineCacheKey {
  std::uint32_t vendor_id = 0;
  std::uint32_t device_id = 0;
  std::uint32_t driver_version = 0;
  std::uint8_t device_uuid[VK_UUID_SIZE] = {};
  std::uint8_t cache_uuid[VK_UUID_SIZE] = {};
};

// The file's bytes for `driver_data` (vkGetPipelineCacheData), and back: the driver data
// when `file` is a valid cache for `key`, else empty with `why` saying what was wrong.
std::vector<std::uint8_t> encode_pipeline_cache(const PipelineCacheKey& key, const std::vector<std::uint8_t>& driver_data);
std::vector<std::uint8_t> decode_pipeline_cache(const PipelineCacheKey& key, const std::vector<std::uint8_t>& file,
                                                std::string& why);

// masq's cache directory ("" when persistence is off or no home is known).
std::string masq_cache_dir();

class PipelineCache {
 public:
  // Loads the device's file if valid; always creates the VkPipelineCache.
  PipelineCache(VkPhysicalDevice physical, VkDevice device);
  // Saves (when the driver's data changed since the load) and destroys.
  ~PipelineCache();
  PipelineCache(const PipelineCache&) = delete;
  PipelineCache& operator=(const PipelineCache&) = delete;

  VkPipelineCache handle() const { return cache_.get(); }
  const std::string& path() const { return path_; }  // "" when not persisted
  bool loaded() const { return loaded_; } // a valid file was handed to the driver
  const std::string& rejected() const { return why_; } // why a file present was ignored

  // Writes the cache file now (atomically: a temporary file renamed over it).
  void save();

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  DeviceOwned<VkPipelineCache> cache_;
  PipelineCacheKey key_;
  std::string path_;
  std::string why_;
  bool loaded_ = false;
  std::size_t loaded_bytes_ = 0; // the driver data loaded or last saved, to skip an unchanged save
  std::uint64_t loaded_sum_ = 0;
};

} // namespace masq::vk
