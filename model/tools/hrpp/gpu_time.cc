// hrpp CLI: time on RT units (gpu_time.h).
#include "gpu_time.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "hrpp/hardware/rtl_config.h"
#include "hrpp/util/progress.h"

namespace hrpp::cli {
namespace {

/// --gpu NAME (model/gpu/NAME.json) or a file.
std::string gpu_path(const std::string& g) {
  if (g.find('/') != std::string::npos || g.ends_with(".json")) return g;
  return std::string(HRPP_SOURCE_DIR) + "/model/gpu/" + g + ".json";
}

}  // namespace

bool load_gpu(const char* cmd, const std::string& gpu, sim::GpuConfig* out) {
  try {
    *out = sim::load_gpu_config(gpu_path(gpu));
  } catch (const sim::GpuConfigError& e) {
    std::vector<std::string> names;  // the configurations model/gpu/ holds
    std::error_code ec;
    for (const auto& f :
         std::filesystem::directory_iterator(std::string(HRPP_SOURCE_DIR) + "/model/gpu", ec))
      if (f.path().extension() == ".json") names.push_back(f.path().stem().string());
    std::sort(names.begin(), names.end());
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    std::fprintf(stderr, "hrpp %s: --gpu %s: %s (known: %s; or a JSON file)\n", cmd, gpu.c_str(),
                 e.what(), known.c_str());
    return false;
  }
  return true;
}

bool predictor_sim_options(const char* cmd, const PredictorArgs& p, const PredictorConfig& cfg,
                           const Scene& scene, const Bvh& bvh, sim::SimOptions* opt,
                           std::string* timing, std::string* rtl_name) {
  opt->pred = cfg;
  opt->any_hit_only = cfg.any_hit_only;
  if (p.preset.starts_with("rtl-") && !table_option_set(p)) {
    const RtlConfig rc = rtl_config(p.preset.substr(4));
    CycleConfig cc;
    const std::string err = rc.cycle_for_scene(cfg.mode, scene, bvh, &cc);
    if (!err.empty()) {
      std::fprintf(stderr, "hrpp %s: configuration %s: %s\n", cmd, rc.name.c_str(), err.c_str());
      return false;
    }
    opt->kind = sim::PredictorKind::kPort;
    opt->cycle = cc;
    *timing = "the RTL's cycle model at its ports (" + rtl_lanes_text(cc) +
              std::to_string(1 << cc.id_bits) + " ray ids, prediction " +
              std::to_string(rtl::kPredictionLatency) + " cycles, decision " +
              std::to_string(rc.decision_latency()) + ")";
    if (rtl_name) *rtl_name = rc.name;
    return true;
  }
  opt->kind = sim::PredictorKind::kTimed;
  opt->timed = sim::preset_timing(p.preset);  // a preset file: its base preset's
  *timing = "the golden predictor behind a timing wrapper " + opt->timed.to_json().dump();
  return true;
}

void add_timing_options(CLI::App* app, TimingArgs& a) {
  app->add_option("--timing", a.timing,
                  "the time figure the report leads with: simulate (hrpp simulate's RT units, "
                  "with no predictor and with this one: docs/timing_model.md) or cost-model "
                  "(the additive cost model only: docs/cost_model.md)")
      ->check(CLI::IsMember({"simulate", "cost-model"}))
      ->capture_default_str();
  a.gpu_option = app->add_option("--gpu", a.gpu,
                                 "--timing simulate: the GPU configuration (model/gpu/NAME.json: "
                                 "mobile, desktop; or a JSON file)")
                     ->capture_default_str();
}

bool check_timing_args(const char* cmd, const TimingArgs& a, sim::GpuConfig* gpu) {
  if (a.timing != "simulate") {
    if (a.gpu_option && a.gpu_option->count()) {
      std::fprintf(stderr,
                   "hrpp %s: --gpu applies only to --timing simulate; this run uses "
                   "--timing %s\n",
                   cmd, a.timing.c_str());
      return false;
    }
    return true;
  }
  return load_gpu(cmd, a.gpu, gpu);
}

nlohmann::json GpuTime::to_json() const {
  return {{"timing", "simulate"},
          {"gpu", gpu_name},
          {"gpu_config", gpu.to_json()},
          {"predictor_timing", timing},
          {"rays", none.rays},
          {"baseline_cycles", none.cycles},
          {"cycles", pred.cycles},
          {"speedup", speedup()},
          {"time_saved_fraction",
           pred.cycles && none.cycles ? 1.0 - double(pred.cycles) / double(none.cycles) : 0.0},
          {"stall_cycles", pred.predictor.stall_cycles}};
}

bool simulate_time(const char* cmd, const TimingArgs& t, const sim::GpuConfig& gpu,
                   const PredictorArgs& p, const PredictorConfig& cfg, const Scene& scene,
                   const Bvh& bvh, const std::vector<RayRecord>& rays, GpuTime* out) {
  out->gpu_name = t.gpu;
  out->gpu = gpu;
  sim::SimOptions none;
  none.gpu = gpu;
  none.pred = cfg;
  none.any_hit_only = cfg.any_hit_only;
  sim::SimOptions pred = none;
  if (!predictor_sim_options(cmd, p, cfg, scene, bvh, &pred, &out->timing)) return false;
  const auto t0 = std::chrono::steady_clock::now();
  auto run = [&](sim::SimOptions o, const std::string& name) {
    Progress progress(stderr, std::string(cmd) + ": time on " + t.gpu + ", " + name, "rays",
                      rays.size(), t0);
    o.progress = [&](const sim::SimProgress& pr) { progress.update(pr.finished); };
    return sim::simulate(bvh, rays, o);
  };
  out->none = run(none, "no predictor");
  out->pred = run(pred, p.label);
  return true;
}

std::string time_words(double speedup) {
  if (!(speedup > 0)) return "no time measured";
  const double change = 1.0 / speedup - 1.0;  // the time with the predictor, relative
  char b[64];
  if (std::abs(change) < 5e-4) return "no change in time";
  std::snprintf(b, sizeof b, "%s %.1f%% time", change < 0 ? "saves" : "COSTS",
                100 * std::abs(change));
  return b;
}

std::string time_lines(const GpuTime* t, double cost_baseline, double cost_hrpp, uint64_t rays) {
  std::string s;
  char b[512];
  if (t) {
    std::snprintf(b, sizeof b,
                  "  time on %s RT units (%u units, each with its own table; %s): %llu -> %llu "
                  "cycles, speed-up %.3fx: %s\n",
                  t->gpu_name.c_str(), t->gpu.units, t->timing.c_str(),
                  (unsigned long long)t->none.cycles, (unsigned long long)t->pred.cycles,
                  t->speedup(), time_words(t->speedup()).c_str());
    s += b;
  }
  const double n = double(std::max<uint64_t>(1, rays));
  std::snprintf(b, sizeof b,
                "  %s (additive, no caches or competing rays: docs/cost_model.md): %.1f -> %.1f "
                "cycles per ray, speed-up %.3fx: %s\n",
                t ? "cost model" : "time by the cost model", cost_baseline / n, cost_hrpp / n,
                cost_hrpp > 0 ? cost_baseline / cost_hrpp : 0.0,
                time_words(cost_hrpp > 0 ? cost_baseline / cost_hrpp : 0.0).c_str());
  s += b;
  return s;
}

nlohmann::json time_json(const GpuTime* t, double cost_baseline, double cost_hrpp) {
  nlohmann::json cost = {
      {"timing", "cost-model"},
      {"baseline_cycles", cost_baseline},
      {"cycles", cost_hrpp},
      {"speedup", cost_hrpp > 0 ? cost_baseline / cost_hrpp : 0.0},
      {"time_saved_fraction", cost_baseline > 0 ? 1.0 - cost_hrpp / cost_baseline : 0.0}};
  if (!t) return cost;
  nlohmann::json j = t->to_json();
  j["cost_model"] = cost;
  return j;
}

}  // namespace hrpp::cli
