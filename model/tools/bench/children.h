// hrpp_bench: the measured child processes (hrpp_bench --child WHAT), one measurement each, its
// JSON on stdout:
//   ours     our BVH build and traversal;
//   embree   the same with Embree ("embree-mxcsr-default": without FTZ/DAZ);
//   predict  the predictor (the RTL's `primary` configuration), one core and 8 cores;
//   big-ours, big-embree  the big procedural scene;
//   embree-verbose  what Embree reports about the CPU and its ISA (parsed by the driver).
#pragma once

#include <cstdint>
#include <string>

namespace hrpp::bench {

struct ChildArgs {
  std::string what, stream, scene;
  unsigned threads = 1;
  uint64_t big_tris = 0;
  uint64_t big_rays = 0;
};

// Embree's default configuration: every ISA it was compiled for that the CPU has (it picks the
// best), default scene flags, default build quality (medium), one build thread.
constexpr const char* kEmbreeBenchConfig = "threads=1";

// The RTL configuration the predictor, co-simulation and simulate measurements run (its preset:
// "rtl-" + this): `primary`, the default configuration before issue 17's winner, whose figures
// the bench has published.
constexpr const char* kBenchRtlConfig = "primary";

// The predictor's cores (tables) in the several-core measurements.
constexpr uint32_t kBenchCores = 8;

// Runs the measurement a.what and prints its JSON; 2 on an unknown one.
int child_main(const ChildArgs& a);

// A one-triangle scene on a verbose device with the bench's settings: Embree prints the CPU, its
// targets and, at the commit, the builder (and so the ISA) it dispatched to.
int embree_verbose();

}  // namespace hrpp::bench
