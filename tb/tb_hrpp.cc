// tb_hrpp: the RTL parity testbench (tb/README.md). The golden model generates real ray streams
// and plays the traversal engine; every cycle every DUT output is compared with the cycle model.
//
//   tb_hrpp --scene SCENE|--stream FILE|--latency [--rays N] [--config small|default|large|mutant]
//           [--mode anyhit|closest-exact|closest-spec] [--seed S] [--trace FILE.vcd]
//           [--reset-every N] [--stall-gap G --stall-max M] [--stress KIND] [+verilator+...]
#include <verilated.h>
#include <verilated_vcd_c.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <vector>
#include <string>

#include "Vhrpp_default.h"
#include "Vhrpp_large.h"
#include "Vhrpp_mutant.h"
#include "Vhrpp_small.h"
#include "engine.h"
#include "latency.h"
#include "stress.h"
#include "hrpp/hardware/cycle_model.h"
#include "hrpp/hardware/rtl_config.h"
#include "hrpp/workload/ray_stream.h"
#include "hrpp/scene/scene.h"
#include "hrpp/workload/workload.h"

namespace hrpp::tb {
namespace {

// Reads `w` bits at `lsb` of a Verilated signal (integral or VlWide).
template <typename T>
uint32_t bits_of(const T& v, int lsb, int w) {
  return static_cast<uint32_t>((static_cast<uint64_t>(v) >> lsb) & ((uint64_t{1} << w) - 1));
}
template <std::size_t N>
uint32_t bits_of(const VlWide<N>& v, int lsb, int w) {
  uint64_t lo = v[lsb / 32], hi = lsb / 32 + 1 < int(N) ? v[lsb / 32 + 1] : 0;
  return static_cast<uint32_t>((((hi << 32) | lo) >> (lsb % 32)) & ((uint64_t{1} << w) - 1));
}

template <typename M>
void apply(M* dut, const DutIn& in) {
  dut->ray_valid_i = in.ray_valid;
  dut->ray_id_i = in.ray_id;
  dut->ray_kind_i = in.ray_kind;
  for (int i = 0; i < 3; ++i) {
    dut->ray_org_i[i] = in.org[i];
    dut->ray_dir_i[i] = in.dir[i];
  }
  dut->pred_ready_i = in.pred_ready;
  dut->pw_valid_i = in.pw_valid;
  dut->pw_id_i = in.pw_id;
  dut->pw_hit_i = in.pw_hit;
  dut->pw_node_i = in.pw_node;
  dut->outcome_valid_i = in.outcome_valid;
  dut->outcome_id_i = in.outcome_id;
  dut->outcome_hit_i = in.outcome_hit;
  dut->outcome_node_i = in.outcome_node;
  dut->skip_ready_i = in.skip_ready;
}

template <typename M>
DutOut read(const M* dut, uint32_t k, int node_bits) {
  DutOut o;
  o.ray_ready = dut->ray_ready_o;
  o.pred_valid = dut->pred_valid_o;
  o.pred_id = dut->pred_id_o;
  o.pred_invalid = dut->pred_invalid_o;
  o.pred_count = dut->pred_count_o;
  for (uint32_t i = 0; i < k; ++i)
    o.pred_nodes[i] = bits_of(dut->pred_nodes_o, int(i) * node_bits, node_bits);
  o.pw_ready = dut->pw_ready_o;
  o.outcome_ready = dut->outcome_ready_o;
  o.skip_valid = dut->skip_valid_o;
  o.skip_id = dut->skip_id_o;
  o.skip_action = static_cast<Action>(dut->skip_action_o);
  return o;
}

// Compares every output; payloads are compared while their valid is set (a FIFO's head is
// undefined while it is empty). Returns a description of the first difference, or "".
std::string compare(const DutOut& exp, const DutOut& act, uint32_t k) {
  char buf[256];
  auto diff = [&](const char* sig, uint64_t e, uint64_t a, uint32_t id) {
    std::snprintf(buf, sizeof buf, "signal %s: expected 0x%llx, actual 0x%llx (ray id %u)", sig,
                  (unsigned long long)e, (unsigned long long)a, id);
    return std::string(buf);
  };
  if (exp.ray_ready != act.ray_ready) return diff("ray_ready_o", exp.ray_ready, act.ray_ready, 0);
  if (exp.pw_ready != act.pw_ready) return diff("pw_ready_o", exp.pw_ready, act.pw_ready, 0);
  if (exp.outcome_ready != act.outcome_ready)
    return diff("outcome_ready_o", exp.outcome_ready, act.outcome_ready, 0);
  if (exp.pred_valid != act.pred_valid)
    return diff("pred_valid_o", exp.pred_valid, act.pred_valid, exp.pred_id);
  if (exp.pred_valid) {
    if (exp.pred_id != act.pred_id) return diff("pred_id_o", exp.pred_id, act.pred_id, exp.pred_id);
    if (exp.pred_invalid != act.pred_invalid)
      return diff("pred_invalid_o", exp.pred_invalid, act.pred_invalid, exp.pred_id);
    if (exp.pred_count != act.pred_count)
      return diff("pred_count_o", exp.pred_count, act.pred_count, exp.pred_id);
    for (uint32_t i = 0; i < k; ++i)
      if (exp.pred_nodes[i] != act.pred_nodes[i])
        return diff(("pred_nodes_o[" + std::to_string(i) + "]").c_str(), exp.pred_nodes[i],
                    act.pred_nodes[i], exp.pred_id);
  }
  if (exp.skip_valid != act.skip_valid)
    return diff("skip_valid_o", exp.skip_valid, act.skip_valid, exp.skip_id);
  if (exp.skip_valid) {
    if (exp.skip_id != act.skip_id) return diff("skip_id_o", exp.skip_id, act.skip_id, exp.skip_id);
    if (exp.skip_action != act.skip_action)
      return diff("skip_action_o", uint64_t(exp.skip_action), uint64_t(act.skip_action), exp.skip_id);
  }
  return {};
}

struct Run {
  uint64_t cycles = 0, mismatches = 0;
  PredictStats stats;
  bool ok = true;
  uint64_t resets = 0, reset_cycles = 0;
  uint64_t dropped = 0;           // rays in flight when a reset hit (re-offered)
  uint64_t resets_with_rays = 0;  // resets that hit at least one ray in flight
  std::string exactly_once;       // Engine::check_exactly_once()
  std::array<StallStats, kNumStallPorts> stalls{};
  CycleStats table;               // the cycle model's table statistics
  uint64_t table_used = 0;        // valid entries at the end
};

constexpr uint64_t kMaxCyclesPerRay = 200;

// A reset begins: the engine drops the rays in flight (it offers them again); counted in `run`.
void begin_reset(Engine& eng, Run& run) {
  const uint64_t d = eng.reset();
  run.resets++;
  run.dropped += d;
  run.resets_with_rays += d > 0;
}

// Resets in the middle of the stream: the first after `every` cycles on average (uniform in
// [every/2, 3*every/2]), each 1..max_len cycles long, the next `every` cycles (again uniform)
// after the previous one ends. Seeded, so the DUT run and the cycle-model run reset at the same
// cycles.
class ResetSchedule {
 public:
  ResetSchedule(uint64_t every, uint64_t max_len, uint64_t seed)
      : every_(every), max_len_(std::max<uint64_t>(1, max_len)), rng_(seed ^ 0x5245'5345'54ull) {
    if (every_) next_ = gap();
  }
  /// Whether rst_ni is low in this cycle; *starts: a reset begins in this cycle.
  bool step(uint64_t cycle, bool* starts) {
    *starts = false;
    if (!every_) return false;
    if (cycle == next_) {
      *starts = true;
      end_ = cycle + std::uniform_int_distribution<uint64_t>(1, max_len_)(rng_);
    }
    if (cycle >= next_ && cycle < end_) return true;
    if (cycle == end_) next_ = end_ + gap();
    return false;
  }
  uint64_t max_len() const { return max_len_; }

 private:
  uint64_t gap() {
    return std::uniform_int_distribution<uint64_t>(every_ / 2, every_ * 3 / 2)(rng_);
  }
  uint64_t every_, max_len_;
  std::mt19937_64 rng_;
  uint64_t next_ = ~0ull, end_ = ~0ull;
};

struct RunOptions {
  uint64_t reset_every = 0, reset_max_len = 8;
  std::vector<std::string> plusargs;  // +verilator+... for the VerilatedContext
};

// The cycle limit of a run: a budget per ray, per ray dropped by a reset, per reset, per stall.
uint64_t cycle_limit(const CycleConfig& cc, size_t rays, const Run& run, const EngineOptions& eo,
                     uint64_t reset_max_len) {
  return cc.table.sets + kMaxCyclesPerRay * (rays + 10 + run.dropped) +
         run.resets * (cc.table.sets + reset_max_len) + 8 * eo.stall_max;
}

// DUT and cycle model in lockstep.
template <typename M>
Run run_dut(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
            const EngineOptions& eo, const RunOptions& ro, const std::string& trace_path) {
  auto ctx = std::make_unique<VerilatedContext>();
  // +verilator+rand+reset+2 +verilator+seed+N: random values in every variable without a reset
  // (they must be given before the model is constructed).
  std::vector<const char*> args{"tb_hrpp"};
  for (const std::string& a : ro.plusargs) args.push_back(a.c_str());
  ctx->commandArgs(int(args.size()), args.data());
  if (!ro.plusargs.empty())
    std::printf("verilator: rand-reset %d, seed %d (uninitialised state %s)\n", ctx->randReset(),
                ctx->randSeed(), ctx->randReset() == 2 ? "random" : "constant");
  ctx->traceEverOn(!trace_path.empty());
  auto dut = std::make_unique<M>(ctx.get());
  std::unique_ptr<VerilatedVcdC> vcd;
  if (!trace_path.empty()) {
    vcd = std::make_unique<VerilatedVcdC>();
    dut->trace(vcd.get(), 99);
    vcd->open(trace_path.c_str());
  }
  CycleModel model(cc);
  Engine eng(bvh, rays, eo);
  ResetSchedule resets(ro.reset_every, ro.reset_max_len, eo.seed);
  Run run;
  uint64_t time = 0;
  dut->cfg_mode_i = static_cast<uint8_t>(cc.mode);
  dut->cfg_cell_exp_i = static_cast<uint16_t>(cc.hash.origin_cell_exp) & 0x1FF;
  apply(dut.get(), DutIn{});
  dut->rst_ni = 0;
  for (int i = 0; i < 4; ++i) {
    dut->clk_i = i & 1;
    dut->eval();
    if (vcd) vcd->dump(time++);
  }
  dut->clk_i = 0;
  dut->rst_ni = 1;
  dut->eval();
  for (uint64_t cycle = 0; !eng.done(); ++cycle) {
    if (cycle > cycle_limit(cc, rays.size(), run, eo, ro.reset_max_len)) {
      std::printf("FAIL: no progress: %llu of %zu rays finished after %llu cycles\n",
                  (unsigned long long)eng.rays_finished(), rays.size(), (unsigned long long)cycle);
      run.ok = false;
      break;
    }
    // Reset: rst_ni goes low (asynchronously, with the clock low) at the start of the cycle and
    // rises at the start of the cycle after the last one; the cycle model is reset in every
    // cycle of it, the engine once as it begins.
    bool reset_starts = false;
    const bool in_reset = resets.step(cycle, &reset_starts);
    if (reset_starts) begin_reset(eng, run);
    if (in_reset) {
      run.reset_cycles++;
      model.reset();
    }
    dut->rst_ni = !in_reset;
    DutIn in;
    eng.drive(cycle, &in);
    apply(dut.get(), in);
    dut->clk_i = 0;
    dut->eval();
    if (vcd) vcd->dump(time++);
    const DutOut act = read(dut.get(), cc.table.nodes_per_entry, cc.table.node_bits);
    const DutOut exp = model.outputs();
    const std::string d = compare(exp, act, cc.table.nodes_per_entry);
    if (!d.empty()) {
      std::printf("MISMATCH at cycle %llu: %s\n", (unsigned long long)cycle, d.c_str());
      run.mismatches++;
      run.cycles = cycle;
      break;  // the first mismatch stops the run
    }
    eng.observe(cycle, in, act);
    if (!eng.error().empty()) {
      std::printf("FAIL at cycle %llu: %s\n", (unsigned long long)cycle, eng.error().c_str());
      run.ok = false;
      break;
    }
    dut->clk_i = 1;
    dut->eval();
    if (vcd) vcd->dump(time++);
    if (!in_reset) model.tick(in);
    if (!model.error().empty()) {
      std::printf("FAIL at cycle %llu: %s\n", (unsigned long long)cycle, model.error().c_str());
      run.ok = false;
      break;
    }
    run.cycles = cycle + 1;
    if (ctx->gotFinish()) {
      std::printf("FAIL: the simulation finished early (an assertion?) at cycle %llu\n",
                  (unsigned long long)cycle);
      run.ok = false;
      break;
    }
  }
  dut->final();
  if (vcd) vcd->close();
  run.stats = eng.stats();
  run.exactly_once = eng.check_exactly_once();
  for (int p = 0; p < kNumStallPorts; ++p) run.stalls[p] = eng.stall_stats(p);
  run.table = model.stats();
  run.table_used = model.table().entries_used();
  return run;
}

// The cycle model alone in the same closed loop.
Run run_model(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
              const EngineOptions& eo, const RunOptions& ro) {
  CycleModel model(cc);
  Engine eng(bvh, rays, eo);
  ResetSchedule resets(ro.reset_every, ro.reset_max_len, eo.seed);
  Run run;
  for (uint64_t cycle = 0;
       !eng.done() && cycle <= cycle_limit(cc, rays.size(), run, eo, ro.reset_max_len); ++cycle) {
    bool reset_starts = false;
    const bool in_reset = resets.step(cycle, &reset_starts);
    if (reset_starts) begin_reset(eng, run);
    if (in_reset) model.reset();
    DutIn in;
    eng.drive(cycle, &in);
    eng.observe(cycle, in, model.outputs());
    if (!in_reset) model.tick(in);
    run.cycles = cycle + 1;
  }
  run.ok = eng.done() && eng.error().empty() && model.error().empty();
  run.stats = eng.stats();
  run.exactly_once = eng.check_exactly_once();
  return run;
}

// Calls f.template operator()<M>() with M the Verilated model of configuration `name`.
template <typename F>
auto with_model(const std::string& name, F&& f) {
  if (name == "small") return f.template operator()<Vhrpp_small>();
  if (name == "large") return f.template operator()<Vhrpp_large>();
  if (name == "mutant") return f.template operator()<Vhrpp_mutant>();
  if (name == "default") return f.template operator()<Vhrpp_default>();
  throw std::invalid_argument("tb_hrpp has no Verilated model of configuration " + name);
}

// The latencies of the DUT, measured at its ports (tb/latency.h).
template <typename M>
Latencies measure_dut_latencies(const CycleConfig& cc, std::string* error) {
  auto ctx = std::make_unique<VerilatedContext>();
  auto dut = std::make_unique<M>(ctx.get());
  dut->cfg_mode_i = static_cast<uint8_t>(cc.mode);
  dut->cfg_cell_exp_i = static_cast<uint16_t>(cc.hash.origin_cell_exp) & 0x1FF;
  apply(dut.get(), DutIn{});
  dut->rst_ni = 0;
  for (int i = 0; i < 4; ++i) {
    dut->clk_i = i & 1;
    dut->eval();
  }
  dut->clk_i = 0;
  dut->rst_ni = 1;
  dut->eval();
  const CycleFn cycle = [&](const DutIn& in) {
    apply(dut.get(), in);
    dut->clk_i = 0;
    dut->eval();
    const DutOut o = read(dut.get(), cc.table.nodes_per_entry, cc.table.node_bits);
    dut->clk_i = 1;
    dut->eval();
    return o;
  };
  Latencies l;
  *error = measure_latencies(cycle, cc.id_bits, cc.table.sets, &l);
  if (error->empty() && ctx->gotFinish()) *error = "the simulation finished early (an assertion?)";
  dut->final();
  return l;
}

// tb_hrpp --latency: the DUT's and the cycle model's latencies against the declared ones.
int check_latencies(const RtlConfig& rc, PredictMode mode) {
  const CycleConfig cc = rc.cycle(mode);
  std::string dut_error, model_error;
  const Latencies dut = with_model(rc.name, [&]<typename M>() {
    return measure_dut_latencies<M>(cc, &dut_error);
  });
  CycleModel cm(cc);
  const CycleFn model_cycle = [&](const DutIn& in) {
    const DutOut o = cm.outputs();
    cm.tick(in);
    return o;
  };
  Latencies model;
  model_error = measure_latencies(model_cycle, cc.id_bits, cc.table.sets, &model);
  const Latencies declared = declared_latencies();
  std::printf("latency: config %s (cycles: ray accepted to pred_valid_o, predicted-walk result "
              "accepted to skip_valid_o, final outcome accepted to the first ray seeing its "
              "write)\n",
              rc.name.c_str());
  auto line = [](const char* who, const Latencies& l) {
    std::printf("  %-12s prediction %d, decision %d, update landing %d\n", who, l.prediction,
                l.decision, l.landing);
  };
  line("declared", declared);
  line("DUT", dut);
  line("cycle model", model);
  std::string e = !dut_error.empty() ? "DUT: " + dut_error
                  : !model_error.empty() ? "cycle model: " + model_error
                                         : "";
  if (e.empty()) {
    if (std::string d = compare_latencies(dut, declared); !d.empty()) e = "DUT: " + d;
    else if (std::string m = compare_latencies(model, declared); !m.empty())
      e = "cycle model: " + m;
  }
  if (!e.empty()) {
    std::printf("FAIL: %s (rtl/config/hrpp_configs.json)\n", e.c_str());
    return 1;
  }
  std::printf("PASS\n");
  return 0;
}

void print_stats(const char* who, const PredictStats& s) {
  std::printf("  %-22s rays %llu, predictions %llu, verified %llu, skipped walks %llu, "
              "interior tests %llu / baseline %llu (skipped %.2f%%), wrong %llu, exact-mismatch %llu\n",
              who, (unsigned long long)s.rays, (unsigned long long)(s.true_positive + s.false_positive),
              (unsigned long long)s.true_positive, (unsigned long long)s.skipped_walks,
              (unsigned long long)s.hrpp.interior_tests, (unsigned long long)s.baseline.interior_tests,
              100 * s.skipped_interior_fraction(), (unsigned long long)s.wrong_results,
              (unsigned long long)s.exact_mismatches);
}

bool same_stats(const PredictStats& a, const PredictStats& b) {
  return a.rays == b.rays && a.baseline == b.baseline && a.hrpp == b.hrpp &&
         a.predicted == b.predicted && a.wasted == b.wasted && a.true_positive == b.true_positive &&
         a.false_positive == b.false_positive && a.false_negative == b.false_negative &&
         a.true_negative == b.true_negative && a.skipped_walks == b.skipped_walks &&
         a.wrong_results == b.wrong_results && a.exact_mismatches == b.exact_mismatches;
}

int main_impl(int argc, char** argv) {
  CLI::App app{"HRPP RTL parity testbench: DUT against the cycle model, cycle by cycle"};
  std::string scene_path, stream_path, config = "default", mode = "closest-exact", trace;
  uint64_t nrays = 100000, seed = 1;
  uint32_t go_up = 0;
  EngineOptions eo;
  auto* src = app.add_option_group("source");
  src->add_option("--scene", scene_path, "generate the rays of this glTF scene");
  src->add_option("--stream", stream_path, "read the rays from this ray-stream file");
  bool latency = false;
  src->add_flag("--latency", latency,
                "measure the pipeline latencies at the ports and compare them with the declared "
                "ones (rtl/config/hrpp_configs.json)");
  src->require_option(1);
  app.add_option("--rays", nrays, "rays to run (at most)")->check(CLI::Range(uint64_t{1}, uint64_t{1} << 32));
  app.add_option("--config", config, "RTL configuration")
      ->check(CLI::IsMember(rtl_config_names()));
  app.add_option("--mode", mode, "how closest-hit rays use predictions")
      ->check(CLI::IsMember({"anyhit", "closest-exact", "closest-spec"}));
  app.add_option("--go-up", go_up, "go-up level of inserted nodes")->check(CLI::Range(0u, 64u));
  app.add_option("--seed", seed, "seed of the engine's latencies and back-pressure");
  app.add_option("--max-latency", eo.max_latency, "largest engine latency in cycles")
      ->check(CLI::Range(1, 1000));
  app.add_option("--p-ray", eo.p_ray, "probability the engine offers a ray in a cycle")
      ->check(CLI::Range(0.01, 1.0));
  app.add_option("--min-latency", eo.min_latency, "smallest engine latency in cycles")
      ->check(CLI::Range(1, 1000));
  app.add_option("--p-ready", eo.p_pred_ready, "probability the engine accepts an output in a cycle")
      ->check(CLI::Range(0.01, 1.0));
  app.add_option("--stall-every", eo.stall_every, "stall every output this often (cycles)");
  app.add_option("--stall-length", eo.stall_length, "... for this many cycles");
  app.add_option("--trace", trace, "write a VCD waveform to this file");
  double min_throughput = 0;
  app.add_option("--min-throughput", min_throughput,
                 "fail unless at least this many rays finish per cycle")
      ->check(CLI::Range(0.0, 1.0));
  bool skip_missing = false;
  app.add_flag("--skip-missing", skip_missing,
               "exit 77 (skipped) when the scene file does not exist (for ctest)");
  RunOptions ro;
  app.add_option("--reset-every", ro.reset_every,
                 "assert rst_ni mid-stream about every N cycles (uniform in [N/2, 3N/2]; 0: never)")
      ->check(CLI::Range(uint64_t{0}, uint64_t{1} << 40));
  app.add_option("--reset-max-length", ro.reset_max_len, "each reset lasts 1..L cycles")
      ->check(CLI::Range(1, 1000));
  app.add_option("--stall-gap", eo.stall_gap,
                 "random stalls on every interface: one starts with probability 1/G per cycle");
  app.add_option("--stall-max", eo.stall_max, "... and lasts 1..M cycles");
  app.add_option("--engine-fault", eo.fault,
                 "test only: 1 = a reset re-offers each dropped ray twice, 2 = a ray stall loses "
                 "the ray on offer (the exactly-once check must fail)")
      ->check(CLI::Range(0, 2));
  std::string stress;
  app.add_option("--stress", stress,
                 "synthetic rays of the scene instead of its camera rays: set-burst (bursts of one "
                 "table set), one-key (every ray one key), evict (many keys: continuous eviction)")
      ->check(CLI::IsMember({"set-burst", "one-key", "evict"}));
  // +verilator+... arguments go to the VerilatedContext, the rest to the options above.
  std::vector<char*> cli_args;
  for (int i = 0; i < argc; ++i) {
    if (i > 0 && argv[i][0] == '+') ro.plusargs.push_back(argv[i]);
    else cli_args.push_back(argv[i]);
  }
  try {
    app.parse(int(cli_args.size()), cli_args.data());
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (ro.reset_every && ro.reset_every < 16) {
    std::fprintf(stderr, "tb_hrpp: --reset-every must be 0 or at least 16\n");
    return 2;
  }
  if (eo.stall_gap && !eo.stall_max) {
    std::fprintf(stderr, "tb_hrpp: --stall-gap needs --stall-max\n");
    return 2;
  }
  if (!stress.empty() && scene_path.empty()) {
    std::fprintf(stderr, "tb_hrpp: --stress needs --scene\n");
    return 2;
  }
  if (eo.min_latency > eo.max_latency) {
    std::fprintf(stderr, "tb_hrpp: --min-latency %d exceeds --max-latency %d\n", eo.min_latency,
                 eo.max_latency);
    return 2;
  }
  eo.p_skip_ready = eo.p_pred_ready;
  eo.seed = seed;
  eo.go_up = go_up;
  parse_predict_mode(mode, &eo.mode);
  if (latency) return check_latencies(rtl_config(config), eo.mode);

  if (skip_missing && !scene_path.empty() && !std::filesystem::exists(scene_path)) {
    std::printf("SKIP: %s is absent\n", scene_path.c_str());
    return 77;
  }
  const RtlConfig spec = rtl_config(config);  // rtl/config/hrpp_configs.json
  std::vector<RayRecord> rays;
  std::string scene_file = scene_path;
  std::unique_ptr<RayStreamReader> reader;
  if (!stream_path.empty()) {
    reader = std::make_unique<RayStreamReader>(stream_path);
    // The stream's options name its scene.
    const auto opts = nlohmann::json::parse(reader->header().options, nullptr, false);
    if (opts.is_object() && opts.contains("scene") && opts["scene"].is_string())
      scene_file = opts["scene"].get<std::string>();
    if (scene_file.empty()) {
      std::fprintf(stderr, "tb_hrpp: %s does not name its scene\n", stream_path.c_str());
      return 2;
    }
  }
  const Scene scene = load_scene(scene_file);
  const Bvh bvh = build_bvh(scene.triangles);
  uint64_t invalid = 0;
  auto take = [&](const RayRecord& r) {
    if (rays.size() >= nrays) return;
    if (validate_ray(r.ray) != RayError::kNone) {
      ++invalid;  // the engine never issues invalid rays (counted, reported)
      return;
    }
    rays.push_back(r);
  };
  if (reader) {
    if (reader->header().scene_fingerprint != scene_fingerprint(scene)) {
      std::fprintf(stderr, "tb_hrpp: %s was not generated from %s (scene fingerprint differs)\n",
                   stream_path.c_str(), scene_file.c_str());
      return 2;
    }
    RayRecord r;
    while (rays.size() < nrays && reader->next(&r)) take(r);
  } else {
    WorkloadOptions wo;
    resolution_for(scene.camera, std::max<uint64_t>(1, nrays / 2), 1, &wo.width, &wo.height);
    if (stress.empty())
      generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit*) { take(r); });
  }

  CycleConfig cc = spec.cycle(eo.mode);
  eo.id_bits = cc.id_bits;
  std::string cfg_err =
      resolve_for_scene(scene, bvh, &cc.hash, &cc.table,
                        {.node_bits = spec.node_id_width, .tag_bits = spec.table.tag_bits});
  if (cfg_err.empty()) cfg_err = cc.validate();
  if (!cfg_err.empty()) {
    std::fprintf(stderr, "tb_hrpp: configuration %s: %s\n", spec.name.c_str(), cfg_err.c_str());
    return 2;
  }
  StressKind stress_kind{};
  if (!stress.empty()) {
    // Synthetic rays of the scene, keyed with the RTL's hash configuration; the stream must do
    // what it claims.
    parse_stress(stress, &stress_kind);
    StressStream ss = make_stress_stream(stress_kind, scene, cc.hash, nrays, seed);
    std::printf("stress %s: %zu rays (%llu distinct), %llu distinct keys in %llu sets; "
                "set %u: %llu rays, %llu keys; longest run of one set %llu rays\n",
                stress.c_str(), ss.rays.size(), (unsigned long long)ss.distinct_rays,
                (unsigned long long)ss.distinct_keys,
                (unsigned long long)ss.distinct_sets, ss.target_set,
                (unsigned long long)ss.target_set_rays, (unsigned long long)ss.target_set_keys,
                (unsigned long long)ss.longest_set_run);
    const std::string e = check_stress_stream(stress_kind, ss, spec.table.sets, spec.table.ways);
    if (!e.empty()) {
      std::printf("FAIL: the %s stream is not what it claims: %s\n", stress.c_str(), e.c_str());
      return 1;
    }
    rays = std::move(ss.rays);
  }
  std::printf("tb_hrpp: config %s (%s hash, %u sets x %u ways x %u nodes, %d-bit tags, %d-bit ids), "
              "mode %s, %zu rays of %s%s, seed %llu\n",
              spec.name.c_str(), hash_variant_name(cc.hash.variant), spec.table.sets,
              spec.table.ways, spec.table.nodes_per_entry, spec.table.tag_bits, spec.id_width,
              mode.c_str(), rays.size(),
              reader ? stream_path.c_str() : scene_file.c_str(),
              invalid ? (" (" + std::to_string(invalid) + " invalid rays not issued)").c_str() : "",
              (unsigned long long)seed);

  Run r;
  const auto t_sim = std::chrono::steady_clock::now();
  const std::clock_t cpu_sim = std::clock();
  r = with_model(config, [&]<typename M>() { return run_dut<M>(cc, bvh, rays, eo, ro, trace); });
  const uint64_t finished = r.stats.rays;
  std::printf("parity: %llu rays, %llu cycles, %llu mismatches\n", (unsigned long long)finished,
              (unsigned long long)r.cycles, (unsigned long long)r.mismatches);
  // The lockstep run alone (engine walks, DUT, cycle model, comparison of every output on every
  // cycle); hrpp_bench reads this line.
  const double sim_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_sim).count();
  const double cpu_s = double(std::clock() - cpu_sim) / CLOCKS_PER_SEC;
  std::printf("timing: lockstep run %.3f s (CPU %.3f s): %.0f rays/s, %.0f cycles/s of CPU time "
              "with parity checking\n",
              sim_s, cpu_s, finished / std::max(cpu_s, 1e-9), r.cycles / std::max(cpu_s, 1e-9));
  if (r.mismatches || !r.ok) return 1;
  if (ro.reset_every)
    std::printf("resets: %llu (%llu cycles in reset), %llu hit rays in flight: %llu rays dropped "
                "and offered again\n",
                (unsigned long long)r.resets, (unsigned long long)r.reset_cycles,
                (unsigned long long)r.resets_with_rays, (unsigned long long)r.dropped);
  if (eo.stall_gap) {
    std::printf("stalls (count, cycles, longest, cycles a handshake was held back):");
    for (int p = 0; p < kNumStallPorts; ++p)
      std::printf("%s %s %llu, %llu, %llu, %llu", p ? ";" : "", stall_port_name(p),
                  (unsigned long long)r.stalls[p].stalls, (unsigned long long)r.stalls[p].cycles,
                  (unsigned long long)r.stalls[p].longest, (unsigned long long)r.stalls[p].blocked);
    std::printf("\n");
  }
  std::printf("table: %llu updates, %llu evictions, %llu cycles of same-set interlock, %llu of %u "
              "entries valid at the end\n",
              (unsigned long long)r.table.updates, (unsigned long long)r.table.evictions,
              (unsigned long long)r.table.interlock_cycles, (unsigned long long)r.table_used,
              spec.table.sets * spec.table.ways);
  // Every ray of the stream got exactly one final result, resets or not.
  if (!r.exactly_once.empty()) {
    std::printf("FAIL: not every ray got exactly one final result: %s\n", r.exactly_once.c_str());
    return 1;
  }
  std::printf("exactly once: each of the %zu rays got one final result\n", rays.size());
  // The stress the options ask for really happened.
  if (ro.reset_every && (r.resets == 0 || r.dropped == 0)) {
    std::printf("FAIL: --reset-every %llu: %llu resets, %llu rays in flight hit\n",
                (unsigned long long)ro.reset_every, (unsigned long long)r.resets,
                (unsigned long long)r.dropped);
    return 1;
  }
  for (int p = 0; eo.stall_gap && p < kNumStallPorts; ++p)
    if (r.stalls[p].blocked == 0) {
      std::printf("FAIL: the random stalls never held back a handshake on %s\n",
                  stall_port_name(p));
      return 1;
    }
  if (!stress.empty()) {
    std::string e;
    const uint64_t entries = uint64_t{spec.table.sets} * spec.table.ways;
    if (stress_kind == StressKind::kSetBurst &&
        (r.table.interlock_cycles == 0 || r.table.evictions == 0))
      e = "no same-set interlock or no eviction";
    if (stress_kind == StressKind::kOneKey &&
        (r.table.updates == 0 || r.table.evictions != 0 || r.table_used > 1))
      e = "one key must give updates, no eviction and at most one valid entry";
    if (stress_kind == StressKind::kEvict &&
        (r.table.evictions < entries || (r.resets == 0 && r.table_used != entries)))
      e = "fewer evictions than table entries, or the table not full at the end";
    if (!e.empty()) {
      std::printf("FAIL: the %s run did not stress the table as claimed: %s\n", stress.c_str(),
                  e.c_str());
      return 1;
    }
  }

  // The same closed loop with the cycle model alone must give the same statistics.
  const Run m = run_model(cc, bvh, rays, eo, ro);
  // The untimed golden model on the same rays in the same order (no pipeline latency).
  PredictorConfig pc;
  pc.hash = cc.hash;
  pc.table = cc.table;
  pc.go_up = go_up;
  pc.mode = eo.mode;
  Predictor untimed(bvh, pc);
  for (const RayRecord& ray : rays) untimed.process(ray);
  std::printf("statistics:\n");
  print_stats("DUT run", r.stats);
  print_stats("cycle model alone", m.stats);
  print_stats("untimed model", untimed.total());
  std::printf("  throughput: %.3f rays per cycle; pipeline latency costs %.2f points of skipped "
              "interior tests against the untimed model\n",
              double(finished) / std::max<uint64_t>(1, r.cycles),
              100 * (untimed.total().skipped_interior_fraction() - r.stats.skipped_interior_fraction()));
  if (!m.ok || !same_stats(r.stats, m.stats) || m.cycles != r.cycles || m.resets != r.resets ||
      m.dropped != r.dropped || !m.exactly_once.empty()) {
    std::printf("FAIL: the cycle model alone gives different statistics or cycle count (%llu cycles)\n",
                (unsigned long long)m.cycles);
    return 1;
  }
  const double throughput = double(finished) / std::max<uint64_t>(1, r.cycles);
  if (throughput < min_throughput) {
    std::printf("FAIL: %.3f rays per cycle, below the required %.3f\n", throughput, min_throughput);
    return 1;
  }
  if (r.stats.exact_mismatches) {
    std::printf("FAIL: %llu rays answered differently from the baseline in an exact mode\n",
                (unsigned long long)r.stats.exact_mismatches);
    return 1;
  }
  std::printf("PASS\n");
  return 0;
}

}  // namespace
}  // namespace hrpp::tb

int main(int argc, char** argv) {
  try {
    return hrpp::tb::main_impl(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tb_hrpp: %s\n", e.what());
    return 2;
  }
}
