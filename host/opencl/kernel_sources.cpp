#include "host/opencl/kernel_sources.h"

#include "opencl/trace_cl.h"
#include "opencl/trace_bv_cl.h"

namespace masq::opencl {
std::string trace_source() { return opencl_src::trace_cl; }
std::string trace_bv_source() { return opencl_src::trace_bv_cl; }
} // namespace masq::opencl
