// The OpenCL C programs, embedded at build time by cmake/embed_opencl.cmake with their
// #includes resolved and #line kept (build logs name kernels/<file>:<line>).
#pragma once
#include <string>

namespace masq::opencl {
std::string trace_source();    // kernels/trace.cl
std::string trace_bv_source(); // kernels/trace_bv.cl
} // namespace masq::opencl
