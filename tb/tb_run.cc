#include "tb_run.h"

#include <gtkwave/fstapi.h>
#include <verilated_fst_c.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "hrpp/util/atomic_file.h"
#include "hrpp/util/progress.h"
#include "tb_dut.h"

namespace hrpp::tb {
namespace {

constexpr uint64_t kMaxCyclesPerRay = 200;

// The waveform of --trace: FST when the file name ends in .fst, VCD otherwise. Verilator 5.006
// builds a model for one trace format (verilate() takes TRACE or TRACE_FST, not both; the model's
// trace code writes that format's buffer), and the models are Verilated with --trace-fst. A VCD is
// written as an FST beside it (FILE.tmp.fst) and converted when the run ends by the FST library's
// reader (gtkwave/fstapi.c, compiled into Verilator's FST writer), as GTKWave's fst2vcd does.
class Waveform {
 public:
  explicit Waveform(const std::string& path) : path_(path), vcd_(!ends_with_fst(path)) {
    fst_path_ = vcd_ ? path + ".tmp.fst" : path;
    hier_path_ = fst_path_ + ".hier";  // the FST writer's own temporary file
  }
  ~Waveform() {
    if (fst_.isOpen()) fst_.close();  // a run that threw: the FST as far as it got
    untrack_unfinished_output(fst_path_.c_str());
    untrack_unfinished_output(hier_path_.c_str());
    untrack_unfinished_output(path_.c_str());
  }
  template <typename M>
  void open(M* dut) {
    dut->trace(&fst_, 99);
    // Removed by an interruption (SIGINT / SIGTERM: tb_hrpp_main.cc) until the run ends.
    track_unfinished_output(fst_path_.c_str());
    track_unfinished_output(hier_path_.c_str());
    fst_.open(fst_path_.c_str());
    // Checked before the run too (tb_options.cc); a waveform that cannot be written fails the run.
    if (!fst_.isOpen())
      throw std::runtime_error("--trace " + path_ + ": cannot open the waveform for writing");
  }
  void dump(uint64_t time) { fst_.dump(time); }
  void close() {
    fst_.close();
    if (vcd_) {
      track_unfinished_output(path_.c_str());
      fst_to_vcd();
      untrack_unfinished_output(path_.c_str());
    }
    untrack_unfinished_output(fst_path_.c_str());
    untrack_unfinished_output(hier_path_.c_str());
  }

 private:
  static bool ends_with_fst(const std::string& path) {
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
    for (char& c : ext) c = char(std::tolower((unsigned char)c));
    return ext == ".fst";
  }
  void fst_to_vcd() const {
    const std::string what = "--trace " + path_ + ": converting " + fst_path_ + " to VCD: ";
    void* reader = fstReaderOpen(fst_path_.c_str());
    if (!reader) throw std::runtime_error(what + "cannot read the FST");
    FILE* out = std::fopen(path_.c_str(), "w");
    if (!out) {
      fstReaderClose(reader);
      throw std::runtime_error(what + "cannot open the VCD for writing");
    }
    const bool hier = fstReaderProcessHier(reader, out) != 0;
    fstReaderSetFacProcessMaskAll(reader);
    const bool values = hier && fstReaderIterBlocks(reader, nullptr, nullptr, out) != 0;
    fstReaderClose(reader);
    if (std::fclose(out) != 0 || !values) throw std::runtime_error(what + "failed");
    std::remove(fst_path_.c_str());
  }

  std::string path_, fst_path_, hier_path_;
  bool vcd_;
  VerilatedFstC fst_;
};

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

// The cycle limit of a run: a budget per ray, per ray dropped by a reset, per reset, per stall.
uint64_t cycle_limit(const CycleConfig& cc, size_t rays, const Run& run, const EngineOptions& eo,
                     uint64_t reset_max_len) {
  return cc.table.sets + kMaxCyclesPerRay * (rays + 10 + run.dropped) +
         run.resets * (cc.table.sets + reset_max_len) + 8 * eo.stall_max +
         4 * uint64_t(eo.max_latency);
}

// One engine per lane; lane l takes the stream's rays l, l + lanes, ... in order (one lane: every
// ray, the engine seeded with the run's seed).
struct LaneEngines {
  LaneEngines(const Bvh& bvh, const std::vector<RayRecord>& rays, const EngineOptions& eo,
              int lanes)
      : rays_of(size_t(lanes)) {
    for (size_t i = 0; i < rays.size(); ++i) rays_of[i % size_t(lanes)].push_back(rays[i]);
    for (int l = 0; l < lanes; ++l) {
      EngineOptions e = eo;
      e.seed = eo.seed + uint64_t(l) * 0x9E37'79B9'7F4A'7C15ull;  // independent per lane
      engines.push_back(std::make_unique<Engine>(bvh, rays_of[size_t(l)], e));
    }
  }
  bool done() const {
    return std::all_of(engines.begin(), engines.end(), [](const auto& e) { return e->done(); });
  }
  bool ok() const {
    return std::all_of(engines.begin(), engines.end(),
                       [](const auto& e) { return e->error().empty(); });
  }
  uint64_t finished() const {
    uint64_t n = 0;
    for (const auto& e : engines) n += e->rays_finished();
    return n;
  }
  // A reset begins: the engines drop the rays in flight (they offer them again); counted in `run`.
  void begin_reset(Run& run) {
    uint64_t d = 0;
    for (auto& e : engines) d += e->reset();
    run.resets++;
    run.dropped += d;
    run.resets_with_rays += d > 0;
  }
  // The engines' statistics, summed over the lanes.
  void finish(Run& run) const {
    if (engines.size() == 1) {
      const Engine& e = *engines[0];
      run.stats = e.stats();
      run.exactly_once = e.check_exactly_once();
      run.max_in_flight = e.max_in_flight();
      for (int p = 0; p < kNumStallPorts; ++p) run.stalls[p] = e.stall_stats(p);
      return;
    }
    for (size_t l = 0; l < engines.size(); ++l) {
      const Engine& e = *engines[l];
      run.stats += e.stats();
      if (const std::string x = e.check_exactly_once(); !x.empty() && run.exactly_once.empty())
        run.exactly_once = "lane " + std::to_string(l) + ": " + x;
      for (int p = 0; p < kNumStallPorts; ++p) {
        const StallStats& s = e.stall_stats(p);
        run.stalls[p].stalls += s.stalls;
        run.stalls[p].cycles += s.cycles;
        run.stalls[p].blocked += s.blocked;
        run.stalls[p].longest = std::max(run.stalls[p].longest, s.longest);
      }
    }
  }
  std::vector<std::vector<RayRecord>> rays_of;
  std::vector<std::unique_ptr<Engine>> engines;
};

// CycleModel (one lane, hrpp_top) with LanesCycleModel's interface: lane 0.
class OneLaneModel {
 public:
  explicit OneLaneModel(const CycleConfig& cc) : m_(cc) {}
  void reset() { m_.reset(); }
  DutOut outputs(int) const { return m_.outputs(); }
  void tick(const std::vector<DutIn>& in) { m_.tick(in[0]); }
  const std::string& error() const { return m_.error(); }
  const CycleStats& stats() const { return m_.stats(); }
  const PredTable& table() const { return m_.table(); }

 private:
  CycleModel m_;
};

// DUT and cycle model in lockstep: one lane (M an hrpp_top model, CM OneLaneModel) or 2 or 4
// (hrpp_lanes, LanesCycleModel), every lane's outputs compared on every cycle.
template <typename M, typename CM>
Run run_dut(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
            const EngineOptions& eo, const RunOptions& ro, const std::string& trace_path) {
  constexpr bool kOneLane = std::is_same_v<CM, OneLaneModel>;
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
  std::unique_ptr<Waveform> wave;
  if (!trace_path.empty()) {
    wave = std::make_unique<Waveform>(trace_path);
    wave->open(dut.get());
  }
  const int lanes = cc.lanes;
  const LaneWidths w{cc.id_bits, cc.table.node_bits, cc.table.nodes_per_entry};
  // Lane l's inputs and outputs (one lane: hrpp_top's ports).
  auto apply_in = [&](const DutIn& in, int l) {
    if constexpr (kOneLane)
      apply(dut.get(), in);
    else
      apply_lane(dut.get(), in, l, w);
  };
  auto read_out = [&](int l) {
    if constexpr (kOneLane)
      return read(dut.get(), cc.table.nodes_per_entry, cc.table.node_bits);
    else
      return read_lane(dut.get(), l, w);
  };
  auto lane_name = [&](int l) {
    return kOneLane ? std::string() : "lane " + std::to_string(l) + ": ";
  };
  CM model(cc);
  LaneEngines eng(bvh, rays, eo, lanes);
  ResetSchedule resets(ro.reset_every, ro.reset_max_len, eo.seed);
  Run run;
  uint64_t time = 0;
  auto dump = [&] {
    if (wave) wave->dump(time++);
  };
  // The start of the run (as reset_dut, tb_dut.h): every lane idle, two cycles in reset.
  dut->cfg_mode_i = static_cast<uint8_t>(cc.mode);
  dut->cfg_cell_exp_i = static_cast<uint16_t>(cc.hash.origin_cell_exp) & 0x1FF;
  for (int l = 0; l < lanes; ++l) apply_in(DutIn{}, l);
  dut->rst_ni = 0;
  for (int i = 0; i < 4; ++i) {
    dut->clk_i = i & 1;
    dut->eval();
    dump();
  }
  dut->clk_i = 0;
  dut->rst_ni = 1;
  dut->eval();
  // Progress on standard error for long runs (hrpp/util/progress.h): after 2 s, then in place
  // on a terminal or every 5 s when piped.
  Progress progress(stderr, "tb_hrpp", "rays", rays.size());
  std::vector<DutIn> in(static_cast<size_t>(lanes));
  std::vector<DutOut> act(static_cast<size_t>(lanes));
  for (uint64_t cycle = 0; !eng.done(); ++cycle) {
    if ((cycle & 0xFFF) == 0) progress.update(eng.finished());
    if (cycle > cycle_limit(cc, rays.size(), run, eo, ro.reset_max_len)) {
      std::printf("FAIL: no progress: %llu of %zu rays finished after %llu cycles\n",
                  (unsigned long long)eng.finished(), rays.size(), (unsigned long long)cycle);
      run.ok = false;
      break;
    }
    // Reset: rst_ni goes low (asynchronously, with the clock low) at the start of the cycle and
    // rises at the start of the cycle after the last one; the cycle model is reset in every
    // cycle of it, the engines once as it begins.
    bool reset_starts = false;
    const bool in_reset = resets.step(cycle, &reset_starts);
    if (reset_starts) eng.begin_reset(run);
    if (in_reset) {
      run.reset_cycles++;
      model.reset();
    }
    dut->rst_ni = !in_reset;
    for (int l = 0; l < lanes; ++l) {
      eng.engines[size_t(l)]->drive(cycle, &in[size_t(l)]);
      apply_in(in[size_t(l)], l);
    }
    dut->clk_i = 0;
    dut->eval();
    dump();
    bool stop = false;
    for (int l = 0; l < lanes && !stop; ++l) {
      act[size_t(l)] = read_out(l);
      const std::string d = compare_outputs(model.outputs(l), act[size_t(l)], w.k);
      if (!d.empty()) {
        std::printf("MISMATCH at cycle %llu: %s%s\n", (unsigned long long)cycle,
                    lane_name(l).c_str(), d.c_str());
        run.mismatches++;
        run.cycles = cycle;
        stop = true;  // the first mismatch stops the run
      }
    }
    if (stop) break;
    for (int l = 0; l < lanes && !stop; ++l) {
      Engine& e = *eng.engines[size_t(l)];
      e.observe(cycle, in[size_t(l)], act[size_t(l)]);
      if (!e.error().empty()) {
        std::printf("FAIL at cycle %llu: %s%s\n", (unsigned long long)cycle, lane_name(l).c_str(),
                    e.error().c_str());
        run.ok = false;
        stop = true;
      }
    }
    if (stop) break;
    if constexpr (!kOneLane) {
      uint64_t in_flight = 0;  // all lanes' rays in flight at once
      for (const auto& e : eng.engines) in_flight += e->in_flight();
      run.max_in_flight = std::max(run.max_in_flight, in_flight);
    }
    dut->clk_i = 1;
    dut->eval();
    dump();
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
  if (wave) wave->close();
  eng.finish(run);  // one lane: the engine's own count of rays in flight
  run.table = model.stats();
  if constexpr (!kOneLane) run.lanes = model.lanes_stats();
  run.table_used = model.table().entries_used();
  return run;
}

// The cycle model alone in the same closed loop.
template <typename CM>
Run run_model_alone(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
                    const EngineOptions& eo, const RunOptions& ro) {
  CM model(cc);
  LaneEngines eng(bvh, rays, eo, cc.lanes);
  ResetSchedule resets(ro.reset_every, ro.reset_max_len, eo.seed);
  Run run;
  std::vector<DutIn> in(static_cast<size_t>(cc.lanes));
  for (uint64_t cycle = 0;
       !eng.done() && cycle <= cycle_limit(cc, rays.size(), run, eo, ro.reset_max_len); ++cycle) {
    bool reset_starts = false;
    const bool in_reset = resets.step(cycle, &reset_starts);
    if (reset_starts) eng.begin_reset(run);
    if (in_reset) model.reset();
    for (int l = 0; l < cc.lanes; ++l) {
      Engine& e = *eng.engines[size_t(l)];
      e.drive(cycle, &in[size_t(l)]);
      e.observe(cycle, in[size_t(l)], model.outputs(l));
    }
    if (!in_reset) model.tick(in);
    run.cycles = cycle + 1;
  }
  run.ok = eng.done() && eng.ok() && model.error().empty();
  eng.finish(run);
  run.table = model.stats();
  if constexpr (!std::is_same_v<CM, OneLaneModel>) run.lanes = model.lanes_stats();
  return run;
}

}  // namespace

Run run_lockstep(const std::string& config, const CycleConfig& cc, const Bvh& bvh,
                 const std::vector<RayRecord>& rays, const EngineOptions& eo, const RunOptions& ro,
                 const std::string& trace) {
  return with_model(
      config, [&]<typename M>() { return run_dut<M, OneLaneModel>(cc, bvh, rays, eo, ro, trace); });
}

Run run_model(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
              const EngineOptions& eo, const RunOptions& ro) {
  return run_model_alone<OneLaneModel>(cc, bvh, rays, eo, ro);
}

PredictStats run_untimed(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
                         uint32_t go_up, PredictMode mode) {
  PredictorConfig pc;
  pc.hash = cc.hash;
  pc.table = cc.table;
  pc.go_up = go_up;
  pc.mode = mode;
  Predictor untimed(bvh, pc);
  for (const RayRecord& ray : rays) untimed.process(ray);
  return untimed.total();
}

// More than one lane (rtl/hrpp_lanes.sv, LanesCycleModel): the same loops.
Run run_lockstep_lanes(const std::string& config, const CycleConfig& cc, const Bvh& bvh,
                       const std::vector<RayRecord>& rays, const EngineOptions& eo,
                       const RunOptions& ro) {
  return with_lanes_model(
      config, [&]<typename M>() { return run_dut<M, LanesCycleModel>(cc, bvh, rays, eo, ro, ""); });
}

Run run_model_lanes(const CycleConfig& cc, const Bvh& bvh, const std::vector<RayRecord>& rays,
                    const EngineOptions& eo, const RunOptions& ro) {
  return run_model_alone<LanesCycleModel>(cc, bvh, rays, eo, ro);
}

}  // namespace hrpp::tb
