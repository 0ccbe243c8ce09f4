// tb_hrpp's report (tb/README.md): the run's header line, the lockstep run's parity, timing,
// resets, stalls, table and exactly-once lines and the checks that the stress asked for
// happened, then the statistics of the three runs (DUT, cycle model alone, untimed model) and
// PASS or the first FAIL.
#pragma once

#include <chrono>
#include <ctime>

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/hardware/rtl_config.h"
#include "hrpp/predictor/predictor.h"
#include "stress.h"
#include "tb_options.h"
#include "tb_rays.h"
#include "tb_run.h"

namespace hrpp::tb {

/// "tb_hrpp: config ..., mode ..., N rays of SOURCE, seed S".
void print_header(const RtlConfig& spec, const CycleConfig& cc, const TbOptions& o,
                  const TbRays& rays);

/// The lockstep run's "parity:" line and its "timing:" line (the run began at `t_sim`, CPU time
/// `cpu_sim`; hrpp_bench reads it).
void print_parity(const Run& r, std::chrono::steady_clock::time_point t_sim, std::clock_t cpu_sim);

/// The rest of the lockstep run's report and its checks: parity, exactly once, and that the
/// resets, stalls and stress stream (`stress_kind` when o.stress is set) the options ask for
/// happened. Returns 0, or 1 after printing FAIL.
int report_lockstep(const Run& r, const TbOptions& o, const RtlConfig& spec, StressKind stress_kind,
                    size_t nrays);

/// The statistics of the DUT run `r`, the cycle model alone `m` and the untimed model; the cycle
/// model alone must agree with the DUT run, the throughput (rays per cycle after the table's
/// reset clear of `clear_cycles` cycles) reach --min-throughput, exact modes give the baseline's
/// answers. Returns 0 after printing PASS, or 1 after printing FAIL.
int report_statistics(const Run& r, const Run& m, const PredictStats& untimed, const TbOptions& o,
                      uint64_t clear_cycles);

}  // namespace hrpp::tb
