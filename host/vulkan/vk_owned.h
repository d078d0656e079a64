// A Vulkan object that destroys itself: the handle, the instance or device it came from
// (none for an instance or a device) and the vkDestroy* / vkFree* function, called when
// the owner goes, is reset or is assigned another. Every Vulkan object masq creates is
// held in one, so a constructor that throws halfway frees what it made without a
// catch block, and members declared after the device they came from go first.
//
// masq's own rather than vulkan_raii.hpp: vk::raii objects are made from a
// vk::raii::Device (its dispatch table), so the headers that hold them (vk_buffer.h,
// vk_pipeline.h, ...) and every test that includes those would include vulkan.hpp:
// 25 s to compile a file holding only vulkan_raii.hpp on the 2-core build machine
// (other builds running), against 0.5 s for vulkan.h. Its device calls would also go
// through vkGetDeviceProcAddr entry points, not the loader's, which masq calls.
#pragma once
#include <vulkan/vulkan.h>
#include <tuple>
#include <utility>

namespace masq::vk {

// Owned<VkBuffer, VkDevice> buffer(device, vkDestroyBuffer);
// MASQ_VK_CHECK(vkCreateBuffer(device, &info, nullptr, buffer.put()));
template <typename Handle, typename... Parent>
class Owned {
 public:
  using Destroy = void(VKAPI_PTR*)(Parent..., Handle, const VkAllocationCallbacks*);

  Owned() = default;
  Owned(Parent... parent, Destroy destroy) : parent_(parent...), destroy_(destroy) {}
  ~Owned() { reset(); }
  Owned(Owned&& o) noexcept : parent_(o.parent_), handle_(o.release()), destroy_(o.destroy_) {}
  Owned& operator=(Owned&& o) noexcept {
    if (this != &o) {
      reset();
      parent_ = o.parent_;
      destroy_ = o.destroy_;
      handle_ = o.release();
    }
    return *this;
  }
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;

  Handle get() const { return handle_; }
  explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }
  // Where a vkCreate* call writes the new handle (what was held is destroyed first). A
  // failed call that leaves a value there must be followed by release().
  Handle* put() {
    reset();
    return &handle_;
  }
  // Gives the handle up without destroying it (a device still running work is left
  // alone, host/vulkan/vk_context.cpp).
  Handle release() noexcept { return std::exchange(handle_, Handle(VK_NULL_HANDLE)); }
  void reset() noexcept {
    if (handle_ != VK_NULL_HANDLE && destroy_ != nullptr)
      std::apply([&](Parent... parent) { destroy_(parent..., handle_, nullptr); }, parent_);
    handle_ = VK_NULL_HANDLE;
  }

 private:
  std::tuple<Parent...> parent_;
  Handle handle_ = VK_NULL_HANDLE;
  Destroy destroy_ = nullptr;
};

// The objects of one device.
template <typename Handle>
using DeviceOwned = Owned<Handle, VkDevice>;

} // namespace masq::vk
