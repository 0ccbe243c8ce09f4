// tb_hrpp's command line (tb/README.md): the options, their checks, and the engine's and the
// run's settings taken from them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "engine.h"
#include "tb_run.h"

namespace hrpp::tb {

struct TbOptions {
  // The ray source: exactly one of --scene, --stream, --latency.
  std::string scene_path, stream_path;
  bool latency = false;
  std::string config = "default", mode = "closest-exact", trace;
  uint64_t nrays = 100000, seed = 1;
  uint32_t go_up = 0;
  double min_throughput = 0;
  uint64_t min_in_flight = 0;
  bool skip_missing = false;
  std::string stress;  // "" or a StressKind's name (tb/stress.h)
  EngineOptions eo;    // mode, seed, go-up and p_skip_ready set from the options above
  RunOptions ro;       // resets and +verilator+... arguments
};

/// Parses argv (+verilator+... arguments go to `o->ro.plusargs`, the rest to the options).
/// Returns nothing to go on, or the exit code: a usage error (printed) or --help.
std::optional<int> parse_options(int argc, char** argv, TbOptions* o);

}  // namespace hrpp::tb
