// hrpp_bench: the benchmark of `make bench` (docs/results.md, "Performance"). Not a test.
//
// For every scene it writes one ray stream (primary, shadow and ambient-occlusion rays, Morton
// order) to out/bench/, then runs, R times and interleaved (ours, Embree, predictor, co-simulation;
// the order of ours and Embree alternates between repetitions), each measurement in a fresh
// process of its own so that its peak RSS (wait4's ru_maxrss) is its own:
//   ours     our BVH build (one thread), closest_hit on the primary rays and any_hit on the shadow
//            and AO rays, on one thread and on all threads;
//   embree   the same with Embree 3 as a user gets it: its default ISA for this CPU, default scene
//            flags and build quality, rtcIntersect1 / rtcOccluded1, a device with threads=1,
//            flush-to-zero and denormals-are-zero set as Embree asks (and, as
//            "embree-mxcsr-default", once more without them: the *_mxcsr_default ratios);
//   predict  the predictor (the RTL's `primary` configuration) on all the rays: one core on one
//            thread, and 8 cores (8 tables) on one thread and on all threads;
//   cosim    tb_hrpp --stream (the RTL and the cycle model in lockstep, parity checked on every
//            cycle) on the first --cosim-rays rays, with the testbench's default random
//            handshakes and again at full rate;
//   simulate `hrpp simulate` (with --hrpp) on a 256x256 AO frame as MICRO 2021 (unbounded AO
//            rays, --gpu mobile, --preset rtl-primary, no oracle, no per-kind runs), with the
//            predictor's cycle model and again with --rtl on the same frame: the simulated rays
//            per second of the preset's run and of the baseline's (each run's wall clock, from
//            the command's report), the whole command's seconds (and CPU seconds); the
//            benchmark fails when the command fails or --rtl reports a mismatch.
// One-thread figures are process CPU time (the machine may be shared); all-thread figures are wall
// time. Ratios are taken within a repetition (ours / Embree, above 1: ours faster) and reported as
// the median with the min and max over the repetitions. A big procedural scene (10 million
// triangles by default) is built and traced last, by ours and by Embree, each in its own process.
//
// The driver (driver.h) runs the measurements (children.h) in processes of their own (process.h)
// and writes the report (report.h).
//
//   hrpp_bench [--shared DIR] [--scenes a,b,...] [--samples N] [--reps R] [--threads N]
//              [--out FILE] [--tb PATH] [--cosim-rays N] [--big-tris N]
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "children.h"
#include "driver.h"
#include "hrpp/scene/scene.h"
#include "hrpp/util/cli.h"
#include "hrpp/workload/ray_stream.h"

int main(int argc, char** argv) {
  using namespace hrpp::bench;
  CLI::App app{
      "HRPP benchmark: our BVH build, traversal and predictor against Embree, and the "
      "RTL co-simulation (make bench)"};
  hrpp::cli::add_version_flag(app, "hrpp_bench");
  DriverArgs d;
  ChildArgs c;
  app.add_option("--shared", d.shared, "the shared folder (its scenes/*.glb are benchmarked)");
  app.add_option("--scenes", d.scenes, "comma-separated scene names or .glb paths (default: all)");
  app.add_option("--samples", d.samples, "camera samples per scene (shadow and AO rays on top)")
      ->check(CLI::Range(uint64_t{64}, uint64_t{1} << 26));
  app.add_option("--reps", d.reps, "repetitions (interleaved; medians and spread)")
      ->check(CLI::Range(1, 100));
  app.add_option("--threads", d.threads, "threads of the all-core runs (default: all)");
  app.add_option("--out", d.out, "JSON report");
  app.add_option("--tb", d.tb, "the Verilator testbench binary");
  app.add_option("--hrpp", d.hrpp,
                 "the hrpp tool (memory check and simulator speed; empty: skip them)");
  app.add_option("--cosim-rays", d.cosim_rays, "rays of each co-simulation run")
      ->check(CLI::Range(uint64_t{1000}, uint64_t{1} << 32));
  app.add_option("--big-tris", d.big_tris, "triangles of the procedural scene (0: skip it)");
  app.add_option("--big-rays", d.big_rays, "primary rays traced in the procedural scene")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 30));
  app.add_option("--child", c.what, "(internal) run one measurement and print it as JSON");
  app.add_option("--stream", c.stream, "(internal)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return hrpp::cli::usage_exit(app, e);  // 0 after --help or --version, 2 for a usage error
  }
  c.threads = d.threads;
  c.big_tris = d.big_tris;
  c.big_rays = d.big_rays;
  try {
    if (c.what == "embree-verbose") return embree_verbose();
    if (!c.what.empty()) return child_main(c);
    return driver_main(d);
  } catch (const hrpp::SceneError& e) {
    std::fprintf(stderr, "hrpp_bench: %s\n", e.what());
    return 2;
  } catch (const hrpp::StreamError& e) {
    std::fprintf(stderr, "hrpp_bench: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrpp_bench: %s\n", e.what());
    return 1;
  }
}
