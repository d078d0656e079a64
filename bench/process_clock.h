// The process's CPU time, for timings on a shared machine: every thread's (masq's cpu
// backend, PoCL's and Embree's workers all run in this process), the figure that still
// decides when other jobs share the cores (the bench rows' cpu_seconds, the peers rounds).
#pragma once

namespace masq {

// The CPU time this process has used so far, all threads (CLOCK_PROCESS_CPUTIME_ID), in
// seconds. Throws masq::Error if the clock cannot be read.
double process_cpu_seconds();

} // namespace masq
