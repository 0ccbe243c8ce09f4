// hrpp_bench: the clocks of the measurements (docs/results.md, "Performance").
#pragma once

#include <chrono>
#include <ctime>

namespace hrpp::bench {

using Clock = std::chrono::steady_clock;

inline double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// One-thread measurements count the process's CPU time: on a shared machine, time spent
// descheduled is not the code's. Several-thread measurements (scaling) need the wall clock.
struct Timer {
  Clock::time_point wall = Clock::now();
  double cpu = process_cpu_seconds();
  double seconds(unsigned threads) const {
    return threads <= 1 ? process_cpu_seconds() - cpu : since(wall);
  }
};

}  // namespace hrpp::bench
