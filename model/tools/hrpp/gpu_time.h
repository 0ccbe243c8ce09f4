// hrpp CLI: time on RT units for the tools that lead their reports with it (predict, render) and
// the parts of `hrpp simulate` they share: the GPU configuration by name or file, and the
// predictor's simulated run (the RTL's cycle model for an RTL preset, else the golden predictor
// behind its preset's timing). docs/timing_model.md.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common.h"
#include "hrpp/sim/simulator.h"

namespace hrpp::cli {

/// --gpu NAME (model/gpu/NAME.json) or FILE.json: loads it; prints "hrpp CMD: --gpu G: why
/// (known: ...)" and returns false.
bool load_gpu(const char* cmd, const std::string& gpu, sim::GpuConfig* out);

/// The predictor's simulated run on top of `opt` (its gpu set): an rtl-NAME preset whose hash and
/// table options were not overridden runs the RTL's cycle model at its ports (`*rtl_name` set to
/// the configuration's name); anything else the golden predictor behind its preset's timing
/// (sim::preset_timing). `timing` describes it. Prints the error and returns false.
bool predictor_sim_options(const char* cmd, const PredictorArgs& p, const PredictorConfig& cfg,
                           const Scene& scene, const Bvh& bvh, sim::SimOptions* opt,
                           std::string* timing, std::string* rtl_name = nullptr);

/// "2 lanes, " for a multi-lane RTL configuration (its ray ids are per lane), else "".
inline std::string rtl_lanes_text(const CycleConfig& cc) {
  return cc.lanes > 1 ? std::to_string(cc.lanes) + " lanes, " : "";
}

/// predict's and render's time options: --timing simulate|cost-model and --gpu.
struct TimingArgs {
  std::string timing = "simulate", gpu = "mobile";
  CLI::Option* gpu_option = nullptr;
};
void add_timing_options(CLI::App* app, TimingArgs& a);

/// Checks the time options (--gpu goes with --timing simulate) and loads the GPU; prints the
/// error and returns false.
bool check_timing_args(const char* cmd, const TimingArgs& a, sim::GpuConfig* gpu);

/// The rays on the GPU with no predictor and with the predictor: the time figure.
struct GpuTime {
  std::string gpu_name, timing;
  sim::GpuConfig gpu;
  sim::SimStats none, pred;
  double speedup() const { return pred.cycles ? double(none.cycles) / double(pred.cycles) : 0; }
  nlohmann::json to_json() const;
};

/// Simulates the rays twice (progress on standard error every 2 s); prints the error and returns
/// false.
bool simulate_time(const char* cmd, const TimingArgs& t, const sim::GpuConfig& gpu,
                   const PredictorArgs& p, const PredictorConfig& cfg, const Scene& scene,
                   const Bvh& bvh, const std::vector<RayRecord>& rays, GpuTime* out);

/// What a speed-up means in time, in words: "saves 12.3% time", "costs 14.2% time" (capitals
/// when it costs: "COSTS"), "no change in time".
std::string time_words(double speedup);

/// The report's first line of results: the simulated time (when simulated) and the cost model's,
/// each with its verdict in words. `cost_baseline` and `cost_hrpp` are the cost model's cycles.
std::string time_lines(const GpuTime* t, double cost_baseline, double cost_hrpp, uint64_t rays);

/// The "time" object of a JSON report: {"timing", "speedup", "time_saved_fraction", ...}.
nlohmann::json time_json(const GpuTime* t, double cost_baseline, double cost_hrpp);

}  // namespace hrpp::cli
