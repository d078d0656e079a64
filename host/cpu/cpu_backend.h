#pragma once
#include "host/backend.h"

namespace masq {
// Multi-threaded on oneTBB's workers (host/cpu/trace_threads.h): MASQ_CPU_THREADS or
// every hardware thread, at most the hardware's.
std::unique_ptr<Backend> make_cpu_backend();
} // namespace masq
