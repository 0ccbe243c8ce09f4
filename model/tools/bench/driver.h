// hrpp_bench: the driver. For every scene it writes the ray stream, runs the repetitions (each
// measurement in a process of its own, children.h; the co-simulation in tb_hrpp), then the
// memory check with hrpp predict and the big procedural scene, and writes the report (report.h).
#pragma once

#include <cstdint>
#include <string>

namespace hrpp::bench {

struct DriverArgs {
  std::string shared = "../shared", scenes, out = "out/bench.json", tb = "build/tb_hrpp",
              hrpp = "build/hrpp";
  uint64_t samples = 262144, cosim_rays = 300000, big_tris = 10000000, big_rays = 1000000;
  int reps = 5;
  unsigned threads = 0;
};

// Runs the benchmark and writes the report; 2 on bad input.
int driver_main(const DriverArgs& a);

}  // namespace hrpp::bench
