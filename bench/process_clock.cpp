#include "bench/process_clock.h"
#include "masq/error.h"
#include <time.h>

namespace masq {

double process_cpu_seconds() {
  timespec ts{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) throw Error("bench: clock_gettime(CLOCK_PROCESS_CPUTIME_ID) failed");
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

} // namespace masq
