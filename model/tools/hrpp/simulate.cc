// hrpp simulate: time on RT units (docs/timing_model.md). The same rays run on the GPU
// configuration with no predictor, with the oracle, and with the chosen predictor; the report
// gives cycles, speed-ups, the memory system's and the predictor's figures.
// cmd_simulate coordinates: configure_simulate (options, scene, rays, predictor), run_all (the
// runs, with progress), simulate_json and print_simulate.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <numeric>
#include <stdexcept>

#include "common.h"
#include "gpu_time.h"
#include "hrpp/hardware/rtl_config.h"
#include "hrpp/scene/scene.h"
#include "hrpp/sim/simulator.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/util/progress.h"
#include "hrpp/workload/ray_stream.h"
#include "hrpp/workload/workload.h"
#include "subcommands.h"
#ifdef HRPP_HAVE_RTL
#include "rtl_port.h"  // tb/: the Verilated RTL (library hrpp_rtl)
#endif

namespace hrpp::cli {
namespace {

struct SimulateArgs {
  std::string scene, json_path, stream, gpu = "mobile", kinds = "all", bvh = "sah";
  WorkloadArgs w;
  PredictorArgs p;
  uint64_t max_rays = 0;
  bool no_oracle = false, rtl = false, repack = false, no_per_kind = false;
  std::string repack_by = "predicted";
  // Timing of golden-model presets (docs/timing_model.md, "Presets"); < 0: the preset's.
  int lookup_latency = -1, decision_latency = -1, update_latency = -1, lookups_per_cycle = -1,
      updates_per_cycle = -1, credits = -1;
  uint32_t entry_timeout = 0;       // the preset's rays give up entering after this many cycles
  uint32_t gate = 0;                // SimOptions::gate
  int64_t gate_first = -1;          // SimOptions::gate_first; < 0: unset
  bool early_root = false;          // SimOptions::early_root
  bool replay = false;              // SimOptions::replay (golden presets and the oracle)
  std::string count = "rays";       // SimOptions::count_original_warps: "original-warps"
  uint64_t warmup_rays = 0;         // SimOptions::warmup_rays
  std::vector<std::string> meshes;  // keep only these meshes of the scene
};

/// One simulated configuration.
struct RunSpec {
  std::string name;
  sim::SimOptions opt;
  std::string timing;  // how the predictor is timed, for the report
};

struct SimulateSetup {
  Scene scene;
  Bvh bvh;
  sim::GpuConfig gpu;
  std::vector<RayRecord> rays;
  nlohmann::json workload;
  WorkloadOptions wo;
  std::vector<RunSpec> runs;  // none, [oracle], preset, [preset with repacking]
  size_t main = 0;            // the preset's run
  int repacked = -1;          // the preset's run with repacking (--repack)
  std::vector<std::vector<sim::SimStats>> per_kind;  // [kind][run]: each kind's rays alone
  std::string preset;
  PredictorConfig pcfg;
  std::string predictor_line;
  uint64_t table_bytes = 0;  // the preset's table, as the RTL stores it (unbounded: 0)
  uint64_t table_bits = 0;   // the same in bits
  // --rtl: each unit's first mismatch in each run ("RUN, unit U, cycle N: signal ..."), in the
  // order they occurred; the run being simulated.
  std::shared_ptr<std::vector<std::string>> rtl_mismatches =
      std::make_shared<std::vector<std::string>>();
  std::shared_ptr<std::string> rtl_run = std::make_shared<std::string>();
};

/// --kinds: "all" or a comma-separated list of ray kinds.
bool parse_kinds(const std::string& spec, std::array<bool, kNumRayKinds>* on, std::string* err) {
  on->fill(spec == "all");
  if (spec == "all") return true;
  size_t pos = 0;
  while (pos <= spec.size()) {
    const size_t end = std::min(spec.find(',', pos), spec.size());
    RayKind k;
    const std::string name = spec.substr(pos, end - pos);
    if (!parse_ray_kind(name, &k)) {
      *err = "--kinds: unknown ray kind '" + name +
             "' (primary, shadow, ao, reflection, refraction, diffuse, or all)";
      return false;
    }
    (*on)[int(k)] = true;
    pos = end + 1;
  }
  return true;
}

sim::TimedConfig timed_for(const SimulateArgs& a, sim::TimedConfig t) {
  auto set = [](int v, uint32_t* f) {
    if (v >= 0) *f = uint32_t(v);
  };
  set(a.lookup_latency, &t.lookup_latency);
  set(a.decision_latency, &t.decision_latency);
  set(a.update_latency, &t.update_latency);
  set(a.lookups_per_cycle, &t.lookups_per_cycle);
  set(a.updates_per_cycle, &t.updates_per_cycle);
  set(a.credits, &t.credits);
  return t;
}

/// The oracle: every ray told its baseline walk's hit leaf as it enters (a whole warp per cycle,
/// no table, no credit limit), in the preset's mode.
RunSpec oracle_run(const sim::SimOptions& base) {
  RunSpec o{"oracle", base,
            "told the baseline walk's hit leaf at no cost (no table, no port limit)"};
  o.opt.kind = sim::PredictorKind::kTimed;
  o.opt.pred.go_up = 0;
  o.opt.any_hit_only = false;  // every ray is told
  o.opt.timed.oracle = true;
  o.opt.timed.lookup_latency = 0;
  o.opt.timed.decision_latency = 0;
  o.opt.timed.lookups_per_cycle = base.gpu.warp_size;
  o.opt.timed.updates_per_cycle = base.gpu.warp_size;
  o.opt.timed.credits = 0;
  return o;
}

/// The preset's run (the last one) is the main run; --repack adds it again with repacking.
void add_repacked(const SimulateArgs& a, const RunSpec& r, SimulateSetup* s) {
  s->main = s->runs.size() - 1;
  if (!a.repack) return;
  RunSpec rr = r;
  rr.name = r.name + "+repack";
  rr.opt.repack = a.repack_by == "node"      ? sim::SimOptions::Repack::kNode
                  : a.repack_by == "micro21" ? sim::SimOptions::Repack::kMicro21
                                             : sim::SimOptions::Repack::kPredicted;
  s->runs.push_back(rr);
  s->repacked = int(s->runs.size() - 1);
}

int configure_simulate(const SimulateArgs& a, SimulateSetup* s) {
  const char* cmd = "simulate";
  std::array<bool, kNumRayKinds> kinds;
  std::string err;
  if (!parse_kinds(a.kinds, &kinds, &err)) {
    std::fprintf(stderr, "hrpp simulate: %s\n", err.c_str());
    return 2;
  }
  if (!check_workload_args(cmd, a.w)) return 2;
  if (!a.json_path.empty() && !check_output_path(cmd, "--json", a.json_path, OutputKind::kJson))
    return 2;
  if (!load_gpu(cmd, a.gpu, &s->gpu)) return 2;
  const bool rtl_preset = a.p.preset.starts_with("rtl-");
  if (a.rtl && !rtl_preset) {
    std::fprintf(stderr, "hrpp simulate: --rtl needs an RTL preset (--preset rtl-NAME), got %s\n",
                 a.p.preset.c_str());
    return 2;
  }
  PredictorConfig& cfg = s->pcfg;
  if (!parse_predictor_args(cmd, a.p, &cfg)) return 2;
  std::unique_ptr<RayStreamReader> stream;
  if (!a.stream.empty()) stream = std::make_unique<RayStreamReader>(a.stream);
  s->scene = load_scene(a.scene);
  if (!a.meshes.empty()) {
    try {
      keep_meshes(&s->scene, a.meshes);
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "hrpp simulate: --meshes: %s\n", e.what());
      return 2;
    }
  }
  s->bvh = build_bvh(s->scene.triangles, bvh_build_options(a.bvh));
  if (!finish_predictor_config(cmd, a.p, s->scene, s->bvh, &cfg)) return 2;

  // The rays, in issue order, of the chosen kinds.
  auto take = [&](const RayRecord& r) {
    if (kinds[int(r.kind)] && (a.max_rays == 0 || s->rays.size() < a.max_rays))
      s->rays.push_back(r);
  };
  if (stream) {
    if (stream->header().scene_fingerprint != scene_fingerprint(s->scene)) {
      std::fprintf(stderr, "hrpp simulate: %s was generated from another scene\n",
                   a.stream.c_str());
      return 2;
    }
    s->workload = nlohmann::json::parse(stream->header().options, nullptr, false);
    if (s->workload.is_discarded()) s->workload = stream->header().options;
    s->workload["stream"] = a.stream;
    RayRecord r;
    while (stream->next(&r)) take(r);
  } else {
    if (!make_workload(cmd, a.w, s->scene, &s->wo)) return 2;
    s->workload = workload_json(s->scene, s->wo);
    generate_rays(s->scene, s->bvh, s->wo, [&](const RayRecord& r, const Hit*) { take(r); });
  }
  if (a.warmup_rays && a.warmup_rays >= s->rays.size()) {
    std::fprintf(stderr, "hrpp simulate: --warmup-rays %llu leaves no rays to measure (%zu rays)\n",
                 (unsigned long long)a.warmup_rays, s->rays.size());
    return 2;
  }
  s->workload["kinds"] = a.kinds;
  if (a.max_rays) s->workload["max_rays"] = a.max_rays;
  if (s->rays.empty()) {
    std::fprintf(stderr, "hrpp simulate: no rays of the kinds '%s' in the workload\n",
                 a.kinds.c_str());
    return 2;
  }

  // The runs: no predictor, the oracle, the preset.
  sim::SimOptions base;
  base.gpu = s->gpu;
  base.pred = cfg;
  base.any_hit_only = cfg.any_hit_only;
  base.early_root = a.early_root;  // the oracle's run and the preset's (none predicts nothing)
  base.count_original_warps = a.count == "original-warps";  // every run
  base.warmup_rays = a.warmup_rays;                         // every run
  s->runs.push_back({"none", base, "no predictor"});
  s->preset = a.p.label;
  if (s->preset != "none" && s->preset != "oracle" && !a.no_oracle) {
    s->runs.push_back(oracle_run(base));
    s->runs.back().opt.replay = a.replay;
  }
  if (s->preset == "none") {
    if (a.repack) {
      std::fprintf(stderr, "hrpp simulate: --repack needs a predictor (--preset none has none)\n");
      return 2;
    }
    return 0;
  }
  RunSpec r{s->preset, base, ""};
  if (s->preset == "oracle") {
    r = oracle_run(base);
    r.opt.replay = a.replay;
    s->runs.push_back(r);
    add_repacked(a, r, s);
    return 0;
  }
  // An RTL preset whose table and hash options were not overridden runs the RTL's cycle model.
  std::string rtl_name;
  if (!predictor_sim_options(cmd, a.p, cfg, s->scene, s->bvh, &r.opt, &r.timing, &rtl_name))
    return 2;
  if (r.opt.kind == sim::PredictorKind::kPort) {
    if (a.rtl) {
#ifdef HRPP_HAVE_RTL
      const CycleConfig& cc = r.opt.cycle;
      // The Verilated RTL of the configuration in every unit, in lockstep with the cycle model.
      const std::string config = rtl_name;
      try {
        tb::make_rtl_port_model(config, cc);  // a configuration without a Verilated model
      } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "hrpp simulate: --rtl: %s\n", e.what());
        return 2;
      }
      auto log = s->rtl_mismatches;
      auto run = s->rtl_run;
      r.opt.port_model = [config, cc, log, run](uint32_t unit) {
        return tb::make_rtl_port_model(config, cc, [log, run, unit](const std::string& d) {
          log->push_back(*run + ", unit " + std::to_string(unit) + ", " + d);
          std::fprintf(stderr, "hrpp simulate --rtl: MISMATCH in %s\n", log->back().c_str());
        });
      };
      const RtlConfig rc = rtl_config(config);
      r.timing = "the Verilated RTL (configuration " + config +
                 ") at its ports, compared with its cycle model on every cycle (" +
                 rtl_lanes_text(cc) + std::to_string(1 << cc.id_bits) + " ray ids, prediction " +
                 std::to_string(rc.prediction_latency()) + " cycles, decision " +
                 std::to_string(rc.decision_latency()) + ")";
#else
      std::fprintf(stderr,
                   "hrpp simulate: --rtl: this hrpp was built without the Verilated RTL "
                   "(cmake -DHRPP_TB=OFF)\n");
      return 2;
#endif
    }
  } else {
    if (a.rtl) {
      std::fprintf(stderr,
                   "hrpp simulate: --rtl runs an RTL configuration as it is; drop the options "
                   "that override %s's hash or table\n",
                   a.p.preset.c_str());
      return 2;
    }
    r.opt.timed = timed_for(a, r.opt.timed);
    r.opt.replay = a.replay;
    r.timing = "the golden predictor behind a timing wrapper " + r.opt.timed.to_json().dump();
    if (a.replay) r.timing += "; fetch lists settled at the prediction (MICRO 2021's replay)";
  }
  if (a.replay && r.opt.kind != sim::PredictorKind::kTimed) {
    std::fprintf(stderr,
                 "hrpp simulate: --replay settles the golden predictor's fetch lists; %s runs the "
                 "RTL's cycle model, whose decisions come from its ports (the oracle and golden "
                 "presets take --replay)\n",
                 a.p.preset.c_str());
    return 2;
  }
  r.opt.entry_timeout = a.entry_timeout;
  if (a.entry_timeout > 0)
    r.timing += "; rays give up entering after " + std::to_string(a.entry_timeout) + " cycles";
  r.opt.gate = a.gate;
  if (a.gate_first >= 0) r.opt.gate_first = static_cast<uint32_t>(a.gate_first);
  if (a.gate > 0)
    r.timing += "; the unit's gate closes after " + std::to_string(a.gate) +
                " lookups without a predicted hit" +
                (a.gate_first >= 0 ? " (" + std::to_string(a.gate_first) + " before the first)"
                                   : std::string());
  if (a.early_root) r.timing += "; the root walk starts at a predicted-walk miss";
  if (base.count_original_warps)
    r.timing += "; cycles counted until the last admitted warp retires";
  s->runs.push_back(r);
  add_repacked(a, r, s);
  return 0;
}

double speedup(uint64_t base, uint64_t cycles) { return cycles ? double(base) / cycles : 0; }

/// --rtl: the cycles in which the RTL's outputs differed from the cycle model's, over every run
/// (the preset's, with repacking, each kind alone).
uint64_t rtl_mismatch_count(const SimulateSetup& s, const std::vector<sim::SimStats>& st) {
  uint64_t n = 0;
  for (const sim::SimStats& x : st) n += x.predictor.mismatches;
  for (const auto& v : s.per_kind)
    for (const sim::SimStats& x : v) n += x.predictor.mismatches;
  return n;
}

/// The loss breakdown against the oracle (docs/timing_model.md, "Losses against the oracle"):
/// the cycles the oracle saves over no predictor, shared among the rays it skips by their
/// baseline walks' node tests (cycles_per_test); each class of the design's rays that hit loses
/// its share, except those it captured; its predicted walks cost as many tests' cycles (right
/// ones too: the oracle's walk is the leaf alone); `timing`, what is left of the difference
/// between the oracle's cycles and the design's (latency, ports, caches, order).
nlohmann::json loss_json(uint64_t base, uint64_t oracle, uint64_t design, const sim::LossTally& t) {
  uint64_t hit_tests = 0;
  for (uint64_t x : t.tests) hit_tests += x;
  const double saved = double(base) - double(oracle);
  const double k = hit_tests ? saved / double(hit_tests) : 0.0;
  nlohmann::json classes = nlohmann::json::object();
  double lost = 0;
  for (int c = 0; c < sim::LossTally::kNumClasses; ++c) {
    const auto cl = static_cast<sim::LossTally::Class>(c);
    const double cyc = k * double(t.tests[c]);
    classes[sim::LossTally::name(cl)] = {
        {"rays", t.rays[c]}, {"tests", t.tests[c]}, {"cycles", cyc}};
    if (cl != sim::LossTally::kCaptured) lost += cyc;
  }
  const double wrong = k * double(t.wrong_tests), right = k * double(t.right_tests);
  return {
      {"oracle_saved_cycles", saved},
      {"saved_cycles", double(base) - double(design)},
      {"cycles_per_test", k},
      {"hit_rays", std::accumulate(t.rays.begin(), t.rays.end(), uint64_t(0))},
      {"classes", classes},
      {"wrong_predictions", {{"rays", t.wrong_rays}, {"tests", t.wrong_tests}, {"cycles", wrong}}},
      {"right_prediction_walks", {{"tests", t.right_tests}, {"cycles", right}}},
      {"timing", {{"cycles", double(design) - double(oracle) - lost - wrong - right}}}};
}

nlohmann::json simulate_json(const SimulateSetup& s, const std::vector<sim::SimStats>& st,
                             const SimulateArgs& a) {
  const sim::SimStats& b = st.front();
  const sim::SimStats& p = st[s.main];
  nlohmann::json j = p.to_json(s.gpu);
  j["baseline_cycles"] = b.cycles;
  j["speedup"] = speedup(b.cycles, p.cycles);
  if (s.main > 0) {  // the preset's loss tally (loss_json shares the oracle's cycles by it)
    nlohmann::json classes = nlohmann::json::object();
    for (int c = 0; c < sim::LossTally::kNumClasses; ++c)
      classes[sim::LossTally::name(static_cast<sim::LossTally::Class>(c))] = {
          {"rays", p.loss.rays[c]}, {"tests", p.loss.tests[c]}};
    j["loss_tally"] = {{"classes", classes},
                       {"wrong_rays", p.loss.wrong_rays},
                       {"wrong_tests", p.loss.wrong_tests},
                       {"right_tests", p.loss.right_tests}};
  }
  j["baseline"] = b.to_json(s.gpu);
  for (auto& [kind, v] : j["by_kind"].items()) {
    const double bl = j["baseline"]["by_kind"][kind]["mean_latency"].get<double>();
    v["baseline_mean_latency"] = bl;
    const double l = v["mean_latency"].get<double>();
    v["latency_speedup"] = l > 0 ? bl / l : 0.0;
    RayKind k;
    parse_ray_kind(kind, &k);
    // The kind alone: its own runs' cycles (the mixed run's, when it is the only kind).
    const std::vector<sim::SimStats>& alone = s.per_kind[int(k)].empty() ? st : s.per_kind[int(k)];
    const uint64_t base = alone.front().cycles;
    v["baseline_cycles"] = base;
    v["cycles"] = alone[s.main].cycles;
    v["speedup"] = speedup(base, alone[s.main].cycles);
    for (size_t i = 0; i < alone.size(); ++i) {
      if (s.runs[i].name == "oracle") v["oracle_speedup"] = speedup(base, alone[i].cycles);
      if (int(i) == s.repacked) v["repacked_speedup"] = speedup(base, alone[i].cycles);
    }
  }
  for (size_t i = 0; i < st.size(); ++i)
    if (s.runs[i].name == "oracle") {
      j["oracle"] = st[i].to_json(s.gpu);
      const double og = speedup(b.cycles, st[i].cycles) - 1;
      j["oracle"]["speedup"] = speedup(b.cycles, st[i].cycles);
      // Meaningful only when the oracle gains (null otherwise).
      j["fraction_of_oracle"] =
          og > 0 ? nlohmann::json((speedup(b.cycles, p.cycles) - 1) / og) : nlohmann::json();
      if (s.main != i) j["loss"] = loss_json(b.cycles, st[i].cycles, p.cycles, p.loss);
    }
  if (s.repacked >= 0) {
    j["repacked"] = st[s.repacked].to_json(s.gpu);
    j["repacked"]["speedup"] = speedup(b.cycles, st[s.repacked].cycles);
    j["repacked"]["by"] = a.repack_by;
  }
  j["scene"] = s.scene.path;
  j["bvh"] = bvh_json(s.bvh);
  j["workload"] = s.workload;
  j["gpu"] = s.gpu.to_json();
  nlohmann::json pr = {{"name", s.preset}, {"timing", s.runs[s.main].timing}};
  const sim::SimOptions& o = s.runs[s.main].opt;
  pr["kind"] = o.kind == sim::PredictorKind::kNone   ? "none"
               : o.kind == sim::PredictorKind::kPort ? "cycle-model"
                                                     : "golden";
  if (o.kind == sim::PredictorKind::kTimed) pr["timed"] = o.timed.to_json();
  pr["mode"] = predict_mode_name(s.pcfg.mode);
  pr["go_up"] = o.pred.go_up;
  pr["any_hit_only"] = o.any_hit_only;
  if (s.preset != "none" && s.preset != "oracle") {
    pr["line"] = s.predictor_line;
    pr["table_bytes"] = s.table_bytes;
    pr["table_bits"] = s.table_bits;
  }
  j["preset"] = pr;
  j["rtl"] = a.rtl;
  if (a.rtl) {
    j["rtl_mismatches"] = rtl_mismatch_count(s, st);
    j["rtl_first_mismatch"] = s.rtl_mismatches->empty() ? "" : s.rtl_mismatches->front();
  }
  j["repack"] = a.repack;
  if (a.replay) j["replay"] = true;
  if (a.count != "rays") j["cycles_until"] = a.count;
  if (a.warmup_rays) j["warmup_rays"] = a.warmup_rays;
  if (!a.meshes.empty()) j["meshes"] = a.meshes;
  return j;
}

/// The report's head, printed before the runs: the rays, the GPU, the predictor.
void print_simulate_head(const SimulateSetup& s, const SimulateArgs& a) {
  const sim::GpuConfig& g = s.gpu;
  if (!a.stream.empty())
    std::printf("simulate %s: %zu rays from %s (kinds %s)\n", s.scene.path.c_str(), s.rays.size(),
                a.stream.c_str(), a.kinds.c_str());
  else
    std::printf("simulate %s: %s; %zu rays (kinds %s)\n", s.scene.path.c_str(),
                workload_line(s.wo).c_str(), s.rays.size(), a.kinds.c_str());
  std::printf("%s", bvh_line(s.bvh).c_str());
  std::printf(
      "  gpu %s: %u RT units x %u warps x %u rays; L1 %llu KB %u-way %u B lines, %u cycles; L2 "
      "%llu KB, +%u cycles, %.0f B/cycle; DRAM +%u cycles, %.1f B/cycle; box %u/cycle, triangle "
      "%u/cycle\n",
      g.name.c_str(), g.units, g.warps_per_unit, g.warp_size,
      (unsigned long long)(g.l1.bytes / 1024), g.l1.ways, g.l1.line_bytes, g.l1.hit_latency,
      (unsigned long long)(g.l2.bytes / 1024), g.l2.hit_latency, g.l2.bytes_per_cycle,
      g.dram.latency, g.dram.bytes_per_cycle, g.box.per_cycle, g.triangle.per_cycle);
  if (!g.rt.is_default() || g.l1.sector_bytes || g.l2.sector_bytes) {
    std::string t;
    auto add = [&](const std::string& x) { t += (t.empty() ? "" : ", ") + x; };
    if (g.l1.sector_bytes || g.l2.sector_bytes)
      add("L1 / L2 sectors " + std::to_string(g.l1.sector_bytes) + " / " +
          std::to_string(g.l2.sector_bytes) + " B");
    if (g.rt.request_bytes)
      add("one " + std::to_string(g.rt.request_bytes) + "-byte request per record");
    if (g.rt.triangle_records) add("triangles one record at a time");
    if (g.rt.triangle_bytes) add(std::to_string(g.rt.triangle_bytes) + "-byte triangles");
    if (g.rt.leaf_end_bytes) add(std::to_string(g.rt.leaf_end_bytes) + " bytes after each leaf");
    if (g.rt.launch_latency) add(std::to_string(g.rt.launch_latency) + "-cycle launch");
    std::printf("  rt unit: %s\n", t.c_str());
  }
  if (s.preset != "none" && s.preset != "oracle")
    std::printf("  predictor %s: %s\n    timing: %s\n", s.preset.c_str(), s.predictor_line.c_str(),
                s.runs[s.main].timing.c_str());
  std::fflush(stdout);  // before the runs, also when piped
}

void print_simulate(const SimulateSetup& s, const std::vector<sim::SimStats>& st,
                    const SimulateArgs& a, double secs) {
  const sim::GpuConfig& g = s.gpu;
  // The time figure first: the preset's speed-up over no predictor, in words.
  if (s.preset != "none" && st.size() > 1) {
    const uint64_t b = st.front().cycles, c = st[s.main].cycles;
    std::printf("  time: %s on %s: %llu -> %llu cycles, speed-up %.3fx: %s\n", s.preset.c_str(),
                g.name.c_str(), (unsigned long long)b, (unsigned long long)c, speedup(b, c),
                time_words(speedup(b, c)).c_str());
  }
  std::printf("  %-20s %11s %8s %9s %9s %9s %7s %7s %9s %6s %11s %11s\n", "run", "cycles",
              "speed-up", "rays/kcyc", "latency", "in flight", "L1 hit", "L2 hit", "DRAM KB",
              "SIMD", "node fetch", "tri fetch");
  const uint64_t base = st.front().cycles;
  for (size_t i = 0; i < st.size(); ++i) {
    const sim::SimStats& x = st[i];
    std::printf(
        "  %-20s %11llu %7.3fx %9.2f %9.1f %9.1f %6.1f%% %6.1f%% %9.1f %5.1f%% %11llu %11llu\n",
        s.runs[i].name.c_str(), (unsigned long long)x.cycles, speedup(base, x.cycles),
        1000.0 * x.rays / std::max<uint64_t>(1, x.cycles), x.mean_latency(), x.mean_in_flight(),
        100 * x.memory.l1.hit_rate(), 100 * x.memory.l2.hit_rate(), x.memory.dram_bytes / 1e3,
        100 * x.simd_efficiency(), (unsigned long long)x.node_fetches,
        (unsigned long long)x.triangle_fetches);
  }
  const sim::SimStats& p = st[s.main];
  if (a.rtl) {
    const uint64_t n = rtl_mismatch_count(s, st);
    std::printf(
        "  rtl: the Verilated RTL in each of the %u units of every run of the preset, in "
        "lockstep with the cycle model: %llu mismatching cycles%s%s\n",
        g.units, (unsigned long long)n, s.rtl_mismatches->empty() ? "" : "; the first: ",
        s.rtl_mismatches->empty() ? "" : s.rtl_mismatches->front().c_str());
  }
  if (st.size() > 1 && s.preset != "oracle") {
    const PredictStats t = p.predict_total();
    std::string bypass;
    if (a.entry_timeout || a.gate)
      bypass = ", " + std::to_string(p.predictor.bypassed) + " rays gave up entering";
    if (a.gate) {
      char b[64];
      std::snprintf(
          b, sizeof b, ", gate closed %.1f%% of unit cycles",
          100.0 * p.predictor.gate_closed_cycles / std::max<uint64_t>(1, p.cycles * g.units));
      bypass += b;
    }
    std::printf(
        "  %s: precision %.4f, recall %.4f, %.2f%% of interior tests skipped, %llu lookups, %llu "
        "stall cycles (%.2f%% of unit cycles), %.1f cycles per predicted ray waiting to enter, "
        "%llu wrong results%s\n",
        s.preset.c_str(), t.precision(), t.recall(), 100 * t.skipped_interior_fraction(),
        (unsigned long long)p.predictor.lookups, (unsigned long long)p.predictor.stall_cycles,
        100.0 * p.predictor.stall_cycles / std::max<uint64_t>(1, p.cycles * g.units),
        double(p.predictor.entry_wait) / std::max<uint64_t>(1, p.predictor.lookups),
        (unsigned long long)t.wrong_results, bypass.c_str());
    for (size_t i = 0; i < st.size(); ++i)
      if (s.runs[i].name == "oracle" && s.main != i) {
        const double og = speedup(base, st[i].cycles) - 1, pg = speedup(base, p.cycles) - 1;
        if (og > 0) {
          std::printf("  %s's gain (speed-up - 1) is %.1f%% of the oracle's\n", s.preset.c_str(),
                      100 * pg / og);
          // The oracle's saved cycles the preset loses, by cause (loss_json).
          const nlohmann::json l = loss_json(base, st[i].cycles, p.cycles, p.loss);
          std::string line;
          for (const auto& [name, v] : l["classes"].items())
            if (name != "captured" && v["rays"].get<uint64_t>() > 0)
              line += ", " + name + " " + std::to_string(std::llround(v["cycles"].get<double>()));
          line +=
              ", wrong predictions " +
              std::to_string(std::llround(l["wrong_predictions"]["cycles"].get<double>())) +
              ", right predictions' walks " +
              std::to_string(std::llround(l["right_prediction_walks"]["cycles"].get<double>())) +
              ", timing " + std::to_string(std::llround(l["timing"]["cycles"].get<double>()));
          std::printf(
              "  of the oracle's %lld saved cycles %s loses (docs/timing_model.md, \"Losses "
              "against the oracle\"): %s\n",
              std::llround(l["oracle_saved_cycles"].get<double>()), s.preset.c_str(),
              line.substr(2).c_str());
        } else
          std::printf("  the oracle gains nothing on these rays (speed-up %.3fx)\n", og + 1);
      }
  }
  std::printf("  %-10s %9s %12s", "kind", "rays", "latency none");
  for (size_t i = 1; i < st.size(); ++i) std::printf(" %12s", s.runs[i].name.c_str());
  std::printf("\n");
  for (int k = 0; k < kNumRayKinds; ++k) {
    const sim::KindTime& kb = st.front().by_kind[k];
    if (!kb.rays) continue;
    std::printf("  %-10s %9llu %12.1f", std::string(ray_kind_name(RayKind(k))).c_str(),
                (unsigned long long)kb.rays, double(kb.latency) / kb.rays);
    for (size_t i = 1; i < st.size(); ++i)
      std::printf(" %12.1f",
                  double(st[i].by_kind[k].latency) / std::max<uint64_t>(1, st[i].by_kind[k].rays));
    std::printf("\n");
  }
  std::printf("  (latency: mean cycles from a ray's warp entering a unit to its answer)\n");
  bool alone = false;
  for (const auto& v : s.per_kind) alone = alone || !v.empty();
  if (alone) {
    std::printf("  each kind alone: %-10s %9s %12s", "kind", "rays", "cycles none");
    for (size_t i = 1; i < st.size(); ++i) std::printf(" %20s", s.runs[i].name.c_str());
    std::printf("\n");
    for (int k = 0; k < kNumRayKinds; ++k) {
      const std::vector<sim::SimStats>& v = s.per_kind[k];
      if (v.empty()) continue;
      std::printf("                   %-10s %9llu %12llu",
                  std::string(ray_kind_name(RayKind(k))).c_str(),
                  (unsigned long long)v.front().rays, (unsigned long long)v.front().cycles);
      for (size_t i = 1; i < v.size(); ++i)
        std::printf(" %19.3fx", speedup(v.front().cycles, v[i].cycles));
      std::printf("\n");
    }
  }
  std::printf("  %.1f s\n", secs);
}

int cmd_simulate(const SimulateArgs& a) {
  SimulateSetup s;
  if (const int rc = configure_simulate(a, &s)) return rc;
  if (s.preset != "none" && s.preset != "oracle") {
    const sim::SimOptions& o = s.runs[s.main].opt;
    PredictorConfig shown = o.pred;
    if (o.kind == sim::PredictorKind::kPort) {
      shown.hash = o.cycle.hash;
      shown.table = o.cycle.table;
    }
    s.table_bits = shown.table.unbounded ? 0 : shown.table.total_bits();
    s.table_bytes = (s.table_bits + 7) / 8;
    s.predictor_line = predictor_line(a.p, shown, s.table_bytes, kUnknownEntries);
  }
  print_simulate_head(s, a);
  const auto t0 = std::chrono::steady_clock::now();
  // Every run on a set of rays, with a progress line every 2 s.
  bool rtl_failed = false;
  auto run_all = [&](const std::vector<RayRecord>& rays, const std::string& label) {
    std::vector<sim::SimStats> out;
    for (RunSpec& r : s.runs) {
      sim::SimOptions o = r.opt;
      *s.rtl_run = r.name + label;
      Progress progress(stderr, "simulate " + r.name + label, "rays", rays.size(), t0);
      o.progress = [&](const sim::SimProgress& p) { progress.update(p.finished); };
      try {
        out.push_back(sim::simulate(s.bvh, rays, o));
      } catch (const std::exception& e) {
        if (!o.port_model) throw;
        // --rtl: an error of the RTL (or of the run it drives) fails the run.
        std::fprintf(stderr, "hrpp simulate --rtl: FAIL: %s%s: %s\n", r.name.c_str(), label.c_str(),
                     e.what());
        rtl_failed = true;
        break;
      }
    }
    return out;
  };
  const std::vector<sim::SimStats> st = run_all(s.rays, "");
  if (rtl_failed) return 1;
  // Each ray kind alone (its own rays, an empty table), when the rays have several kinds.
  std::vector<std::vector<sim::SimStats>>& per_kind = s.per_kind;
  per_kind.assign(kNumRayKinds, {});
  int kinds_present = 0;
  for (int k = 0; k < kNumRayKinds; ++k) kinds_present += st.front().by_kind[k].rays > 0;
  if (kinds_present > 1 && !a.no_per_kind)
    for (int k = 0; k < kNumRayKinds; ++k) {
      if (!st.front().by_kind[k].rays) continue;
      std::vector<RayRecord> rays;
      for (const RayRecord& r : s.rays)
        if (int(r.kind) == k) rays.push_back(r);
      per_kind[k] = run_all(rays, " (" + std::string(ray_kind_name(RayKind(k))) + " alone)");
      if (rtl_failed) return 1;
    }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  print_simulate(s, st, a, secs);
  auto write_json = [&] {
    if (a.json_path.empty()) return true;
    nlohmann::json j = {{"tool", tool_json()}};
    j.update(simulate_json(s, st, a));
    j["seconds"] = secs;
    return write_json_file(a.json_path, j);
  };
  // --rtl: a mismatch comes first (it explains any wrong answer after it); the report is written.
  if (a.rtl && rtl_mismatch_count(s, st)) {
    std::fprintf(stderr,
                 "hrpp simulate --rtl: FAIL: the RTL's outputs differed from the cycle model's in "
                 "%llu cycles; the first: %s\n",
                 (unsigned long long)rtl_mismatch_count(s, st), s.rtl_mismatches->front().c_str());
    write_json();
    return 1;
  }
  for (size_t i = 0; i < st.size(); ++i)
    if (st[i].predict_total().exact_mismatches) {
      std::fprintf(stderr,
                   "hrpp simulate: BUG: %s answered %llu rays differently from the "
                   "baseline in an exact mode\n",
                   s.runs[i].name.c_str(),
                   (unsigned long long)st[i].predict_total().exact_mismatches);
      return 1;
    }
  if (!write_json()) return 2;
  return 0;
}

}  // namespace

Subcommand add_simulate(CLI::App& app) {
  auto sa = std::make_shared<SimulateArgs>();
  auto* sc = app.add_subcommand(
      "simulate",
      "Time the rays on RT units with caches, DRAM and warps (docs/timing_model.md), with no "
      "predictor, the oracle and the chosen predictor");
  sc->add_option("scene", sa->scene, "glTF scene (.glb or .gltf)")->required();
  add_predictor_options(sc, sa->p, {"none", "oracle"});
  std::vector<CLI::Option*> wopts = add_workload_options(sc, sa->w, "shadow,ao");
  auto* stream_opt = sc->add_option("--stream", sa->stream,
                                    "read the rays from this ray-stream file (hrpp trace)");
  for (CLI::Option* o : wopts) stream_opt->excludes(o);
  sc->add_option("--kinds", sa->kinds,
                 "ray kinds to simulate: all, or a comma-separated list (e.g. ao); the others "
                 "are generated (to spawn their children) but not simulated")
      ->capture_default_str();
  sc->add_option("--max-rays", sa->max_rays, "simulate only the first N rays (0: all)");
  sc->add_option("--gpu", sa->gpu,
                 "GPU configuration: mobile, desktop, micro21-sim (model/gpu/) or a JSON file")
      ->capture_default_str();
  sc->add_option("--json", sa->json_path,
                 "write the report as JSON to this file ('-': to standard output, the text report "
                 "then to standard error)");
  add_bvh_option(sc, sa->bvh);
  sc->add_flag("--no-oracle", sa->no_oracle, "do not run the oracle");
  sc->add_flag("--no-per-kind", sa->no_per_kind,
               "do not run each ray kind alone (by default, when the rays have several kinds, "
               "every run is repeated on each kind's rays alone for its cycles and speed-up)");
  sc->add_flag("--rtl", sa->rtl,
               "run the Verilated RTL in every unit, in lockstep with the cycle model");
  sc->add_flag("--repack", sa->repack,
               "also run the predictor with warp repacking: rays regrouped into warps after "
               "their predictions (docs/timing_model.md)");
  CLI::Option* repack_by =
      sc->add_option("--repack-by", sa->repack_by,
                     "repacking categories: predicted (predicted or not), node (by first predicted "
                     "node) or micro21 (MICRO 2021's simulator: a warp waits in the predictor, its "
                     "predicted rays leave for one pool; docs/timing_model.md)")
          ->check(CLI::IsMember({"predicted", "node", "micro21"}))
          ->capture_default_str();
  sc->add_option("--lookup-latency", sa->lookup_latency,
                 "golden presets: cycles from a ray's entry to its prediction")
      ->check(CLI::Range(0, 100000));
  sc->add_option("--decision-latency", sa->decision_latency,
                 "golden presets: cycles from a predicted-walk result to the skip decision")
      ->check(CLI::Range(0, 100000));
  sc->add_option("--update-latency", sa->update_latency,
                 "golden presets: cycles from an outcome to its table write's visibility")
      ->check(CLI::Range(0, 100000));
  sc->add_option("--lookups-per-cycle", sa->lookups_per_cycle,
                 "golden presets: rays taken per cycle")
      ->check(CLI::Range(1, 1024));
  sc->add_option("--updates-per-cycle", sa->updates_per_cycle,
                 "golden presets: outcomes taken per cycle")
      ->check(CLI::Range(1, 1024));
  sc->add_option("--credits", sa->credits, "golden presets: rays held at once (0: unlimited)")
      ->check(CLI::Range(0, 1 << 24));
  sc->add_option("--entry-timeout", sa->entry_timeout,
                 "a ray that has waited this many cycles to enter its unit's predictor (no "
                 "credit, port busy) walks from the root without it: no lookup, no table write "
                 "(0: rays wait until they enter)")
      ->check(CLI::Range(0, 1 << 24))
      ->capture_default_str();
  sc->add_option("--gate", sa->gate,
                 "the unit's gate: after this many answered lookups without a predicted hit, "
                 "the unit's rays enter its predictor only in their first cycle (else walk "
                 "without it) until a predicted hit (0: no gate; docs/timing_model.md)")
      ->check(CLI::Range(0, 1 << 24))
      ->capture_default_str();
  sc->add_option("--gate-first", sa->gate_first,
                 "with --gate: the lookups the gate allows before the unit's first predicted hit "
                 "(default: --gate; 0: the gate starts closed)")
      ->check(CLI::Range(0, 1 << 24));
  sc->add_flag("--early-root", sa->early_root,
               "the RT unit starts a ray's walk from the root as soon as its predicted walks "
               "found no hit (the decision can then only be the full walk) instead of waiting "
               "for the skip decision");
  sc->add_flag("--replay", sa->replay,
               "MICRO 2021's replay: a ray's fetch list is settled at its prediction (the "
               "predicted walk from the predicted node's own pair, then at once the root walk "
               "or nothing); the oracle and golden presets (docs/timing_model.md)");
  sc->add_option("--cycles-until", sa->count,
                 "count a run's cycles until its last ray's answer (rays) or its last admitted "
                 "warp's retirement (original-warps: MICRO 2021's simulator's kernel end, which "
                 "does not wait for rays its predictor moved into warps of its own)")
      ->check(CLI::IsMember({"rays", "original-warps"}))
      ->capture_default_str();
  sc->add_option("--meshes", sa->meshes,
                 "keep only these meshes (glTF node names, comma-separated) of the scene")
      ->delimiter(',');
  sc->add_option("--warmup-rays", sa->warmup_rays,
                 "run the first N rays as a warm-up kernel (MICRO 2021's benchmark's -w): the "
                 "others enter when they are answered, and cycles count from then")
      ->check(CLI::Range(uint64_t(0), uint64_t(1) << 40));
  return {sc, [sa, repack_by] {
            // No preset: the RTL's default configuration, unless hash or table options are
            // given (then the golden model's defaults with those options).
            if (!resolve_preset("simulate", sa->p)) return 2;
            if (repack_by->count() > 0 && !sa->repack) {
              std::fprintf(stderr,
                           "hrpp simulate: --repack-by chooses how --repack regroups rays; add "
                           "--repack\n");
              return 2;
            }
            if (sa->gate_first >= 0 && sa->gate == 0) {
              std::fprintf(stderr, "hrpp simulate: --gate-first needs a gate (--gate N, N > 0)\n");
              return 2;
            }
            return cmd_simulate(*sa);
          }};
}

}  // namespace hrpp::cli
