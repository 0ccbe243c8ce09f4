// tb_hrpp: the RTL parity testbench (tb/README.md). The golden model generates real ray streams
// and plays the traversal engine; every cycle every DUT output is compared with the cycle model.
//
//   tb_hrpp --scene SCENE|--stream FILE [--rays N] [--config small|default|large|mutant]
//           [--mode anyhit|closest-exact|closest-spec] [--seed S] [--trace FILE.vcd]
#include <verilated.h>
#include <verilated_vcd_c.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "Vhrpp_default.h"
#include "Vhrpp_large.h"
#include "Vhrpp_mutant.h"
#include "Vhrpp_small.h"
#include "engine.h"
#include "hrpp/cycle_model.h"
#include "hrpp/ray_stream.h"
#include "hrpp/scene.h"
#include "hrpp/workload.h"

namespace hrpp::tb {
namespace {

constexpr int kNodeIdWidth = 20;  // every Verilated configuration uses 20-bit node ids

struct Spec {
  const char* name;
  HashConfig hash;
  uint32_t sets, ways, k;
  int tag_bits, id_bits;
};

Spec spec_for(const std::string& name) {
  HashConfig faithful;
  faithful.variant = HashVariant::kFaithful;
  faithful.precision = 6;
  faithful.exp_bits = 3;
  faithful.combine = CombineMode::kXor;
  HashConfig improved;
  improved.variant = HashVariant::kImproved;
  improved.origin_bits = 5;
  improved.dir_bits = 3;
  improved.combine = CombineMode::kConcat;
  // Keep in sync with the verilate() parameters in tb/CMakeLists.txt.
  if (name == "small") return {"small", faithful, 64, 2, 1, 12, 4};
  if (name == "large") return {"large", faithful, 4096, 4, 4, 16, 8};
  return {name == "mutant" ? "mutant" : "default", improved, 128, 8, 2, 8, 6};
}

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
  dut->upd_valid_i = in.upd_valid;
  dut->upd_id_i = in.upd_id;
  dut->upd_hit_i = in.upd_hit;
  dut->upd_node_i = in.upd_node;
  dut->skip_ready_i = in.skip_ready;
}

template <typename M>
DutOut read(const M* dut, uint32_t k) {
  DutOut o;
  o.ray_ready = dut->ray_ready_o;
  o.pred_valid = dut->pred_valid_o;
  o.pred_id = dut->pred_id_o;
  o.pred_invalid = dut->pred_invalid_o;
  o.pred_count = dut->pred_count_o;
  for (uint32_t i = 0; i < k; ++i) o.pred_nodes[i] = bits_of(dut->pred_nodes_o, i * kNodeIdWidth, kNodeIdWidth);
  o.pw_ready = dut->pw_ready_o;
  o.upd_ready = dut->upd_ready_o;
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
  if (exp.upd_ready != act.upd_ready) return diff("upd_ready_o", exp.upd_ready, act.upd_ready, 0);
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
};

constexpr uint64_t kMaxCyclesPerRay = 200;

// DUT and cycle model in lockstep.
template <typename M>
Run run_dut(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
            const EngineOptions& eo, const std::string& trace_path) {
  auto ctx = std::make_unique<VerilatedContext>();
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
  const uint64_t limit = cc.table.sets + kMaxCyclesPerRay * (rays.size() + 10);
  for (uint64_t cycle = 0; !eng.done(); ++cycle) {
    if (cycle > limit) {
      std::printf("FAIL: no progress: %llu of %zu rays finished after %llu cycles\n",
                  (unsigned long long)eng.rays_finished(), rays.size(), (unsigned long long)cycle);
      run.ok = false;
      break;
    }
    DutIn in;
    eng.drive(cycle, &in);
    apply(dut.get(), in);
    dut->clk_i = 0;
    dut->eval();
    if (vcd) vcd->dump(time++);
    const DutOut act = read(dut.get(), cc.table.nodes_per_entry);
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
    model.tick(in);
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
  return run;
}

// The cycle model alone in the same closed loop.
Run run_model(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
              const EngineOptions& eo) {
  CycleModel model(cc);
  Engine eng(bvh, rays, eo);
  Run run;
  for (uint64_t cycle = 0; !eng.done() && cycle <= cc.table.sets + kMaxCyclesPerRay * (rays.size() + 10); ++cycle) {
    DutIn in;
    eng.drive(cycle, &in);
    eng.observe(cycle, in, model.outputs());
    model.tick(in);
    run.cycles = cycle + 1;
  }
  run.ok = eng.done() && eng.error().empty();
  run.stats = eng.stats();
  return run;
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
  src->require_option(1);
  app.add_option("--rays", nrays, "rays to run (at most)")->check(CLI::Range(uint64_t{1}, uint64_t{1} << 32));
  app.add_option("--config", config, "RTL configuration")
      ->check(CLI::IsMember({"small", "default", "large", "mutant"}));
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
  CLI11_PARSE(app, argc, argv);
  if (eo.min_latency > eo.max_latency) {
    std::fprintf(stderr, "tb_hrpp: --min-latency %d exceeds --max-latency %d\n", eo.min_latency,
                 eo.max_latency);
    return 2;
  }
  eo.p_skip_ready = eo.p_pred_ready;
  eo.seed = seed;
  eo.go_up = go_up;
  parse_predict_mode(mode, &eo.mode);

  if (skip_missing && !scene_path.empty() && !std::filesystem::exists(scene_path)) {
    std::printf("SKIP: %s is absent\n", scene_path.c_str());
    return 77;
  }
  const Spec spec = spec_for(config);
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
  if (bvh.nodes.size() > (size_t{1} << kNodeIdWidth)) {
    std::fprintf(stderr, "tb_hrpp: the BVH has %zu nodes; the RTL configurations have %d-bit node ids\n",
                 bvh.nodes.size(), kNodeIdWidth);
    return 2;
  }
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
    generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit*) { take(r); });
  }

  CycleConfig cc;
  cc.hash = spec.hash;
  cc.hash.index_bits = std::countr_zero(spec.sets);
  cc.hash.origin_cell_exp = cell_exp_for(scene.bounds, cc.hash.origin_bits);
  cc.table.sets = spec.sets;
  cc.table.ways = spec.ways;
  cc.table.nodes_per_entry = spec.k;
  cc.table.node_bits = kNodeIdWidth;
  cc.table.tag_bits = spec.tag_bits;
  cc.table.key_bits = cc.hash.key_bits();
  cc.mode = eo.mode;
  cc.id_bits = spec.id_bits;
  eo.id_bits = spec.id_bits;
  if (const std::string e = cc.validate(); !e.empty()) {
    std::fprintf(stderr, "tb_hrpp: configuration %s: %s\n", spec.name, e.c_str());
    return 2;
  }
  std::printf("tb_hrpp: config %s (%s hash, %u sets x %u ways x %u nodes, %d-bit tags, %d-bit ids), "
              "mode %s, %zu rays of %s%s, seed %llu\n",
              spec.name, hash_variant_name(cc.hash.variant), spec.sets, spec.ways, spec.k,
              spec.tag_bits, spec.id_bits, mode.c_str(), rays.size(),
              reader ? stream_path.c_str() : scene_file.c_str(),
              invalid ? (" (" + std::to_string(invalid) + " invalid rays not issued)").c_str() : "",
              (unsigned long long)seed);

  Run r;
  const auto t_sim = std::chrono::steady_clock::now();
  const std::clock_t cpu_sim = std::clock();
  if (config == "small") r = run_dut<Vhrpp_small>(cc, bvh, rays, eo, trace);
  else if (config == "large") r = run_dut<Vhrpp_large>(cc, bvh, rays, eo, trace);
  else if (config == "mutant") r = run_dut<Vhrpp_mutant>(cc, bvh, rays, eo, trace);
  else r = run_dut<Vhrpp_default>(cc, bvh, rays, eo, trace);
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

  // The same closed loop with the cycle model alone must give the same statistics.
  const Run m = run_model(cc, bvh, rays, eo);
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
  if (!m.ok || !same_stats(r.stats, m.stats) || m.cycles != r.cycles) {
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
