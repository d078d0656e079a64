#pragma once
#include "host/backend.h"

namespace masq {
// Multi-threaded: MASQ_CPU_THREADS or the hardware concurrency.
std::unique_ptr<Backend> make_cpu_backend();
} // namespace masq
