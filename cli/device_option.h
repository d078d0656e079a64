// --device, one definition shared by bench, render and stress: which device the GPU
// backends open (host/device_choice.h). "SEL" sets the vulkan and opencl selectors
// (rayquery follows vulkan); "vulkan=SEL,rayquery=SEL,opencl=SEL" sets each. SEL is an
// index of `masq info`'s listing or a case-insensitive substring of a device name. It
// overrides MASQ_VK_DEVICE / MASQ_RQ_DEVICE / MASQ_CL_DEVICE.
#pragma once
#include <CLI/CLI.hpp>
#include <span>
#include <string>

namespace masq::cli {

// Registers --device on `cmd`, stored in `value` (a malformed value is a usage error).
void add_device_option(CLI::App& cmd, std::string& value);

// Applies `value` (if any) to the selectors, then checks that every selector in force
// names a device of the API `backends` run on: one that names none throws masq::Error
// (exit 1) naming it and the devices there are, before any work starts.
void apply_device_option(const std::string& value, std::span<const std::string> backends);

} // namespace masq::cli
