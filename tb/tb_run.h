// tb_hrpp's runs (tb/README.md, "What tb_hrpp checks"): the DUT (the Verilated model of a
// configuration) and the cycle model in lockstep in a closed loop with the engine, with resets
// in the middle of the stream; the cycle model alone in the same loop; the untimed model.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "engine.h"
#include "hrpp/hardware/cycle_model.h"
#include "hrpp/hardware/cycle_model_lanes.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/workload/workload.h"

namespace hrpp::tb {

struct Run {
  uint64_t cycles = 0, mismatches = 0;
  PredictStats stats;
  bool ok = true;
  uint64_t resets = 0, reset_cycles = 0;
  uint64_t dropped = 0;           // rays in flight when a reset hit (re-offered)
  uint64_t resets_with_rays = 0;  // resets that hit at least one ray in flight
  std::string exactly_once;       // Engine::check_exactly_once()
  std::array<StallStats, kNumStallPorts> stalls{};
  CycleStats table;            // the cycle model's table statistics
  LanesStats lanes;            // the crossbars' (more than one lane)
  uint64_t table_used = 0;     // valid entries at the end
  uint64_t max_in_flight = 0;  // the most rays in flight at once (Engine::max_in_flight)
};

struct RunOptions {
  uint64_t reset_every = 0, reset_max_len = 8;
  std::vector<std::string> plusargs;  // +verilator+... for the VerilatedContext
};

/// DUT and cycle model in lockstep; the DUT is the Verilated model of configuration `config`.
/// A mismatch, a protocol error or an early finish is printed and stops the run; `trace`: the
/// waveform to write (FST if the name ends in .fst, VCD otherwise), or "".
Run run_lockstep(const std::string& config, const CycleConfig& cc, const Bvh& bvh,
                 const std::vector<RayRecord>& rays, const EngineOptions& eo, const RunOptions& ro,
                 const std::string& trace);

/// The cycle model alone in the same closed loop.
Run run_model(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
              const EngineOptions& eo, const RunOptions& ro);

/// More than one lane (cc.lanes 2 or 4; tb_run_lanes.cc): one engine per lane, lane l taking the
/// stream's rays l, l + lanes, l + 2 lanes, ... in order (its ids its own); DUT (the multi-lane
/// Verilated model of `config`) and LanesCycleModel in lockstep, every lane's outputs compared
/// every cycle. The statistics are the sum over the lanes.
Run run_lockstep_lanes(const std::string& config, const CycleConfig& cc, const Bvh& bvh,
                       const std::vector<RayRecord>& rays, const EngineOptions& eo,
                       const RunOptions& ro);
/// LanesCycleModel alone in the same closed loop.
Run run_model_lanes(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
                    const EngineOptions& eo, const RunOptions& ro);

/// The untimed golden model on the same rays in the same order (no pipeline latency).
PredictStats run_untimed(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
                         uint32_t go_up, PredictMode mode);

}  // namespace hrpp::tb
