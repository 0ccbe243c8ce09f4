// The RT-unit model's invariants (docs/timing_model.md, "Tests"): answers and work equal the
// golden walks', the compute-bound figure, monotonicity in DRAM latency and in warps per unit,
// Little's law, determinism, exactness with the cycle model, the oracle, the configuration reader.
#include <gtest/gtest.h>

#include "hrpp/hardware/rtl_config.h"
#include "hrpp/predictor/engine_side.h"
#include "hrpp/predictor/hash.h"
#include "hrpp/scene/scene.h"
#include "hrpp/sim/memory.h"
#include "hrpp/sim/simulator.h"
#include "hrpp/sim/unit_gate.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/workload/workload.h"
#include "test_util.h"

namespace hrpp {
namespace {

using sim::GpuConfig;
using sim::SimOptions;
using sim::SimStats;
using sim::UnitGate;

struct World {
  Scene scene;
  Bvh bvh;
  std::vector<RayRecord> rays;
};

/// A scene's rays at res x res: primary, shadow and AO (AO unbounded when ao_inf).
World make_world(const std::string& path, int res, float ao_distance = 0.f) {
  World w;
  w.scene = load_scene(path);
  w.bvh = build_bvh(w.scene.triangles);
  WorkloadOptions wo;
  wo.width = wo.height = res;
  wo.ao_distance = ao_distance;
  generate_rays(w.scene, w.bvh, wo, [&](const RayRecord& r, const Hit*) { w.rays.push_back(r); });
  return w;
}

std::string own(const char* name) { return std::string(HRPP_SOURCE_DIR) + "/scenes/" + name; }

GpuConfig mobile() {
  return sim::load_gpu_config(std::string(HRPP_SOURCE_DIR) + "/model/gpu/mobile.json");
}

/// Every latency 0, every bandwidth and MSHR count unbounded in effect.
GpuConfig ideal_memory(GpuConfig g) {
  g.l1.hit_latency = g.l2.hit_latency = g.dram.latency = 0;
  g.l2.bytes_per_cycle = g.dram.bytes_per_cycle = 0;
  g.l1.mshrs = g.l2.mshrs = 1 << 30;
  g.l1.requests_per_cycle = 0;
  return g;
}

uint64_t triangle_base_bytes(const Bvh& bvh) {
  return sim::triangle_base(bvh) + bvh.tris.size() * sim::kTriangleBytes;
}

SimStats run(const World& w, const SimOptions& o) { return sim::simulate(w.bvh, w.rays, o); }

// The golden walks of every valid ray: their work and answers.
struct Golden {
  Counters work;
  std::vector<Hit> answers;
  uint64_t rays = 0;
};
Golden golden(const World& w, PredictMode mode) {
  Golden g;
  g.answers.resize(w.rays.size());
  for (size_t i = 0; i < w.rays.size(); ++i) {
    const RayRecord& r = w.rays[i];
    if (validate_ray(r.ray) != RayError::kNone) continue;
    ++g.rays;
    g.answers[i] = engine_walk(w.bvh, r.ray, answers_any_hit(r.kind, mode), 0, &g.work);
  }
  return g;
}

bool same_hit(const Hit& a, const Hit& b) {
  return a.hit() == b.hit() && (!a.hit() || (a.t == b.t && a.prim == b.prim && a.leaf == b.leaf));
}

// Every valid ray's answer is its golden walk's; the first that is not is named.
::testing::AssertionResult golden_answers(const World& w, const Golden& g,
                                          const std::vector<Hit>& answers) {
  for (size_t i = 0; i < w.rays.size(); ++i)
    if (validate_ray(w.rays[i].ray) == RayError::kNone && !same_hit(answers[i], g.answers[i]))
      return ::testing::AssertionFailure() << "ray " << i << " differs from its golden walk";
  return ::testing::AssertionSuccess();
}

TEST(Sim, NoPredictorGivesTheGoldenAnswersAndWork) {
  std::vector<std::string> scenes = {own("spd_balls.glb"), own("cornell_box.glb")};
  if (const std::string b = test::shared_scene("bunny.glb"); !b.empty()) scenes.push_back(b);
  for (const std::string& path : scenes) {
    SCOPED_TRACE(path);
    const World w = make_world(path, 24);
    SimOptions o;
    o.gpu = mobile();
    std::vector<Hit> answers;
    o.answers = &answers;
    const SimStats s = run(w, o);
    const Golden g = golden(w, o.pred.mode);
    ASSERT_EQ(s.rays, g.rays);
    EXPECT_EQ(s.node_fetches, g.work.interior_tests);
    EXPECT_EQ(s.start_fetches, 0u);
    EXPECT_EQ(s.triangle_fetches, g.work.tri_tests);
    EXPECT_EQ(s.predict_total().baseline, g.work);
    EXPECT_EQ(s.predict_total().hrpp, g.work);
    for (size_t i = 0; i < w.rays.size(); ++i)
      ASSERT_TRUE(same_hit(answers[i], g.answers[i])) << "ray " << i;
  }
}

// One ray at a time (one unit, one warp of one ray) with no memory latency: every ray's cycles
// are its walk's dependent chain, node tests and triangle tests at one issue per cycle, and the
// next ray enters the cycle after.
TEST(Sim, IdealMemoryGivesTheComputeBoundFigure) {
  const World w = make_world(own("spd_balls.glb"), 16);
  SimOptions o;
  o.gpu = ideal_memory(mobile());
  o.gpu.units = 1;
  o.gpu.warps_per_unit = 1;
  o.gpu.warp_size = 1;
  o.gpu.box = {.latency = 3, .per_cycle = 1};
  o.gpu.triangle = {.latency = 5, .per_cycle = 1};
  const SimStats s = run(w, o);
  const Golden g = golden(w, o.pred.mode);
  const uint64_t expect =
      g.work.interior_tests * 3 + g.work.tri_tests + g.work.leaf_visits * (5 - 1) + g.rays;
  EXPECT_EQ(s.cycles, expect);
  EXPECT_DOUBLE_EQ(s.simd_efficiency(), 1.0);
  // Many rays at once: the box pipeline's issue rate bounds the cycles from below.
  o.gpu.warps_per_unit = 64;
  o.gpu.warp_size = 32;
  const SimStats m = run(w, o);
  EXPECT_GE(m.cycles, g.work.interior_tests);
  EXPECT_LT(m.cycles, s.cycles);
}

TEST(Sim, MoreDramLatencyNeverGivesFewerCycles) {
  const World w = make_world(own("spd_balls.glb"), 32);
  SimOptions o;
  o.gpu = mobile();
  o.gpu.l1.bytes = 4096;  // small caches, so that DRAM is reached
  o.gpu.l1.ways = 4;
  o.gpu.l2.bytes = 16384;
  o.gpu.l2.ways = 4;
  uint64_t prev = 0;
  for (uint32_t lat : {0u, 50u, 116u, 400u, 1600u}) {
    o.gpu.dram.latency = lat;
    const SimStats s = run(w, o);
    EXPECT_GE(s.cycles, prev) << "DRAM latency " << lat;
    EXPECT_GT(s.memory.dram_bytes, 0u);
    prev = s.cycles;
  }
}

// With caches that hold the scene. With smaller ones more warps can thrash them, as on GPUs
// (Rogers, O'Connor, Aamodt, "Cache-Conscious Wavefront Scheduling", MICRO 2012): spd_balls at
// 32x32 on `mobile` takes 47,013 cycles with 16 warps per unit and 51,445 with 32.
TEST(Sim, FewerWarpsPerUnitNeverGiveMoreThroughput) {
  const World w = make_world(own("spd_balls.glb"), 32);
  SimOptions o;
  o.gpu = mobile();
  o.gpu.l1.bytes = o.gpu.l2.bytes = 8 << 20;
  ASSERT_GT(o.gpu.l1.bytes, triangle_base_bytes(w.bvh));
  uint64_t prev = ~0ull;
  for (uint32_t warps : {1u, 2u, 4u, 8u, 16u, 32u}) {
    o.gpu.warps_per_unit = warps;
    const SimStats s = run(w, o);
    EXPECT_LE(s.cycles, prev) << warps << " warps per unit";
    prev = s.cycles;
  }
}

SimOptions rtl_default(const World& w, PredictMode mode, const char* config = "primary") {
  SimOptions o;
  o.gpu = mobile();
  o.kind = sim::PredictorKind::kPort;
  o.pred.mode = mode;
  EXPECT_EQ(rtl_config(config).cycle_for_scene(mode, w.scene, w.bvh, &o.cycle), "");
  return o;
}

// Rays per cycle x mean latency = mean rays in flight: two independent tallies (each ray's
// latency at its answer; the rays in the units summed cycle by cycle) that must agree exactly.
TEST(Sim, LittlesLawHolds) {
  const World w = make_world(own("cornell_box.glb"), 32);
  for (const bool pred : {false, true}) {
    SimOptions o;
    o.gpu = mobile();
    if (pred) o = rtl_default(w, PredictMode::kClosestExact);
    const SimStats s = run(w, o);
    const double lambda = double(s.rays) / s.cycles;
    EXPECT_NEAR(s.mean_in_flight(), lambda * s.mean_latency(), 1e-9 * s.mean_in_flight());
  }
}

TEST(Sim, SameInputsGiveTheSameCycles) {
  const World w = make_world(own("spd_balls.glb"), 32);
  const SimOptions o = rtl_default(w, PredictMode::kClosestExact);
  const GpuConfig g = o.gpu;
  // Everything but the wall-clock time.
  auto report = [&] {
    nlohmann::json j = run(w, o).to_json(g);
    j.erase("run_seconds");
    j.erase("rays_per_second");
    return j.dump();
  };
  EXPECT_EQ(report(), report());
}

TEST(Sim, ExactModesAnswerAsTheGoldenWalks) {
  const World w = make_world(own("cornell_box.glb"), 32, kInf);
  for (const PredictMode mode : {PredictMode::kClosestExact, PredictMode::kAnyHit}) {
    SimOptions o = rtl_default(w, mode);
    o.pred.go_up = 1;
    std::vector<Hit> answers;
    o.answers = &answers;
    const SimStats s = run(w, o);
    const Golden g = golden(w, mode);
    EXPECT_EQ(s.predict_total().exact_mismatches, 0u);
    EXPECT_GT(s.predict_total().true_positive, 0u);
    EXPECT_EQ(s.predictor.lookups, s.rays);
    for (size_t i = 0; i < w.rays.size(); ++i) {
      if (answers_any_hit(w.rays[i].kind, mode))
        ASSERT_EQ(answers[i].hit(), g.answers[i].hit()) << "ray " << i;
      else
        ASSERT_TRUE(same_hit(answers[i], g.answers[i])) << "ray " << i;
    }
  }
}

TEST(Sim, TheOracleSkipsEveryAnyHitRayThatHits) {
  const World w = make_world(own("cornell_box.glb"), 32, kInf);
  SimOptions o;
  o.gpu = mobile();
  o.kind = sim::PredictorKind::kTimed;
  o.timed.oracle = true;
  o.timed.lookup_latency = o.timed.decision_latency = 0;
  o.timed.lookups_per_cycle = 32;
  const SimStats s = run(w, o);
  const PredictStats& ao = s.predict[int(RayKind::kAo)];
  ASSERT_GT(ao.baseline_hits, 0u);
  EXPECT_EQ(ao.skipped_walks, ao.baseline_hits);
  EXPECT_EQ(ao.true_positive, ao.baseline_hits);
  EXPECT_EQ(ao.false_positive, 0u);
  SimOptions none;
  none.gpu = mobile();
  EXPECT_LT(s.cycles, run(w, none).cycles);
}

// Rays that give up entering (entry_timeout) walk from the root without the predictor: every
// ray is either looked up or bypassed, none waits longer than the timeout, and the answers stay
// the golden walks'.
TEST(Sim, RaysThatGiveUpEnteringWalkWithoutThePredictor) {
  const World w = make_world(own("cornell_box.glb"), 32, kInf);
  const Golden g = golden(w, PredictMode::kClosestExact);
  for (const uint32_t timeout : {1u, 8u}) {
    SimOptions o = rtl_default(w, PredictMode::kClosestExact);
    o.entry_timeout = timeout;
    std::vector<Hit> answers;
    o.answers = &answers;
    const SimStats s = run(w, o);
    EXPECT_GT(s.predictor.bypassed, 0u) << timeout;
    EXPECT_GT(s.predictor.lookups, 0u) << timeout;
    EXPECT_EQ(s.predictor.lookups + s.predictor.bypassed, s.rays) << timeout;
    EXPECT_EQ(s.predict_total().exact_mismatches, 0u);
    EXPECT_TRUE(golden_answers(w, g, answers)) << timeout;
  }
}

// An early root walk (SimOptions::early_root): a ray whose predicted walks found no hit walks
// from the root at once, not after its decision. With a long decision latency and ideal memory
// (root walks shorter than the latency, so outcomes wait for their decisions) every answer stays
// the golden walk's, every ray is looked up once, and the frame takes fewer cycles; the RTL's
// cycle model, which checks the order of its messages, runs it as well.
TEST(Sim, AnEarlyRootWalkDoesNotWaitForAFullWalkDecision) {
  const World w = make_world(own("cornell_box.glb"), 32, kInf);
  const Golden g = golden(w, PredictMode::kClosestExact);
  SimOptions o;
  o.gpu = ideal_memory(mobile());
  o.kind = sim::PredictorKind::kTimed;
  o.pred = rtl_config("primary").predictor();
  o.pred.mode = PredictMode::kClosestExact;
  o.pred.go_up = 1;
  o.timed.decision_latency = 300;
  uint64_t cycles[2] = {};
  for (const bool early : {false, true}) {
    o.early_root = early;
    std::vector<Hit> answers;
    o.answers = &answers;
    const SimStats s = run(w, o);
    cycles[early] = s.cycles;
    EXPECT_EQ(s.predictor.lookups, s.rays) << early;
    EXPECT_GT(s.predict_total().true_positive, 0u) << early;
    EXPECT_EQ(s.predict_total().exact_mismatches, 0u) << early;
    EXPECT_TRUE(golden_answers(w, g, answers)) << early;
  }
  EXPECT_LT(cycles[1], cycles[0]);
  SimOptions r = rtl_default(w, PredictMode::kClosestExact);
  r.pred.go_up = 1;
  r.early_root = true;
  std::vector<Hit> answers;
  r.answers = &answers;
  const SimStats s = run(w, r);
  EXPECT_EQ(s.predictor.mismatches, 0u);
  EXPECT_EQ(s.predict_total().exact_mismatches, 0u);
  EXPECT_TRUE(golden_answers(w, g, answers));
}

// The gate's counter: closed after N lookups without a predicted hit, opened by one, and then
// N more lookups before it closes again; N = 0 never closes.
TEST(Sim, TheGateCountsLookupsSinceTheLastPredictedHit) {
  UnitGate none;
  for (int i = 0; i < 10; ++i) none.on_lookup();
  EXPECT_FALSE(none.closed());
  UnitGate g(3);
  for (int round = 0; round < 2; ++round) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_FALSE(g.closed()) << round << " " << i;
      g.on_lookup();
    }
    EXPECT_TRUE(g.closed()) << round;
    g.on_lookup();  // saturates
    EXPECT_TRUE(g.closed()) << round;
    EXPECT_TRUE(g.on_predicted_hit()) << round;   // opened it
    EXPECT_FALSE(g.on_predicted_hit()) << round;  // already open
  }
  g.on_lookup();
  g.on_lookup();
  g.on_predicted_hit();  // reloads before it closed
  g.on_lookup();
  g.on_lookup();
  EXPECT_FALSE(g.closed());
  // A shorter first probe: closed after `first` lookups, then N per predicted hit as before.
  for (const uint32_t first : {0u, 2u}) {
    UnitGate f(5, first);
    for (uint32_t i = 0; i < first; ++i) {
      EXPECT_FALSE(f.closed()) << first << " " << i;
      f.on_lookup();
    }
    EXPECT_TRUE(f.closed()) << first;
    EXPECT_TRUE(f.on_predicted_hit()) << first;
    for (int i = 0; i < 5; ++i) {
      EXPECT_FALSE(f.closed()) << first << " " << i;
      f.on_lookup();
    }
    EXPECT_TRUE(f.closed()) << first;
  }
}

// The unit's gate (SimOptions::gate): it closes after `gate` answered lookups without a predicted
// hit, and then the rays that cannot enter at once walk without the predictor; a predicted hit
// opens it again. Every ray is looked up or bypassed and the answers stay the golden walks'; a
// gate that never closes within the run changes nothing.
TEST(Sim, TheGateClosesWithoutPredictedHitsAndOpensOnOne) {
  const World w = make_world(own("cornell_box.glb"), 32, kInf);
  const Golden g = golden(w, PredictMode::kClosestExact);
  SimOptions open = rtl_default(w, PredictMode::kClosestExact);
  const SimStats s0 = run(w, open);
  open.gate = 1u << 24;  // more lookups than rays: never closes
  const SimStats s1 = run(w, open);
  EXPECT_EQ(s1.cycles, s0.cycles);
  EXPECT_EQ(s1.predictor.lookups, s0.predictor.lookups);
  EXPECT_EQ(s1.predictor.gate_closed_cycles, 0u);
  EXPECT_EQ(s1.predictor.bypassed, 0u);
  for (const uint32_t gate : {1u, 4u}) {
    SimOptions o = rtl_default(w, PredictMode::kClosestExact);
    o.gate = gate;
    std::vector<Hit> answers;
    o.answers = &answers;
    const SimStats s = run(w, o);
    EXPECT_GT(s.predictor.gate_closed_cycles, 0u) << gate;
    EXPECT_GT(s.predictor.gate_openings, 0u) << gate;
    EXPECT_GT(s.predictor.bypassed, 0u) << gate;
    EXPECT_LT(s.predictor.lookups, s0.predictor.lookups) << gate;
    EXPECT_EQ(s.predictor.lookups + s.predictor.bypassed, s.rays) << gate;
    EXPECT_EQ(s.predict_total().exact_mismatches, 0u);
    EXPECT_TRUE(golden_answers(w, g, answers)) << gate;
  }
  // gate_first: a gate that starts closed bypasses rays before any predicted hit, so it looks up
  // fewer rays than the same gate that starts open; a first probe as long as the gate is the
  // default.
  SimOptions o = rtl_default(w, PredictMode::kClosestExact);
  o.gate = 64;
  const SimStats open64 = run(w, o);
  o.gate_first = 64;
  EXPECT_EQ(run(w, o).cycles, open64.cycles);
  o.gate_first = 0;
  std::vector<Hit> answers;
  o.answers = &answers;
  const SimStats closed = run(w, o);
  EXPECT_GT(closed.predictor.bypassed, open64.predictor.bypassed);
  EXPECT_LT(closed.predictor.lookups, open64.predictor.lookups);
  EXPECT_EQ(closed.predictor.lookups + closed.predictor.bypassed, closed.rays);
  EXPECT_TRUE(golden_answers(w, g, answers));
}

// The multi-lane RTL configurations (hrpp_lanes' cycle model behind each lane's ports): every
// ray is looked up on some lane and its messages go back on that lane (a message on another
// lane would name an id that lane does not hold: an error), the answers stay the golden walks',
// and with the RT units' rays spread over more lanes the rays wait fewer cycles to enter.
TEST(Sim, LanesTakeEveryRayAndAnswerAsTheGoldenWalks) {
  const World w = make_world(own("cornell_box.glb"), 32, kInf);
  const Golden g = golden(w, PredictMode::kClosestExact);
  uint64_t wait_one_lane = 0;
  for (const char* config : {"primary", "primary_x2", "primary_x4"}) {
    SimOptions o = rtl_default(w, PredictMode::kClosestExact, config);
    std::vector<Hit> answers;
    o.answers = &answers;
    const SimStats s = run(w, o);
    EXPECT_EQ(s.predictor.lookups, s.rays) << config;
    EXPECT_EQ(s.predict_total().exact_mismatches, 0u) << config;
    EXPECT_GT(s.predict_total().true_positive, 0u) << config;
    EXPECT_TRUE(golden_answers(w, g, answers)) << config;
    if (o.cycle.lanes == 1)
      wait_one_lane = s.predictor.entry_wait;
    else
      EXPECT_LT(s.predictor.entry_wait, wait_one_lane) << config;
  }
}

// MICRO 2021's timing (docs/timing_model.md, "MICRO 2021's timing"): each switch alone.

// A sectored cache fetches only the sectors read: two sectors of one line are two misses and
// two sectors' bytes from DRAM, where an unsectored cache fetches the line once.
TEST(Sim, SectoredCachesFetchOnlyTheSectorsRead) {
  for (const uint32_t sector : {0u, 32u}) {
    GpuConfig g = mobile();
    g.l1.sector_bytes = g.l2.sector_bytes = sector;
    sim::MemorySystem m(g);
    m.load(0, 0, 32, 0);
    m.load(0, 32, 32, 1000);
    m.load(0, 0, 32, 2000);
    const sim::MemoryStats s = m.stats();
    EXPECT_EQ(s.l1.accesses, 3u) << sector;
    EXPECT_EQ(s.l1.misses, sector ? 2u : 1u) << sector;
    EXPECT_EQ(s.l1.hits, sector ? 1u : 2u) << sector;
    EXPECT_EQ(s.dram_bytes, sector ? 64u : 128u) << sector;
  }
  // A line's eviction takes all its sectors: one set of one way, two sectors of line 0, then
  // line 1 in its place: its second sector is a miss too.
  GpuConfig g = mobile();
  g.l1.sector_bytes = g.l2.sector_bytes = 32;
  g.l1.bytes = g.l1.line_bytes = 128;
  g.l1.ways = 1;
  sim::MemorySystem m(g);
  for (const uint64_t addr : {0, 32, 128, 160}) m.load(0, addr, 32, addr * 100);
  EXPECT_EQ(m.stats().l1.misses, 4u);
}

// rt.request_bytes: every record fetch is one request (a node pair, each triangle of a leaf).
TEST(Sim, RecordRequestsReadOneBlockPerRecord) {
  const World w = make_world(own("spd_balls.glb"), 16);
  SimOptions o;
  o.gpu = mobile();
  o.gpu.l1.sector_bytes = o.gpu.l2.sector_bytes = 32;
  const SimStats lines = run(w, o);
  EXPECT_GT(lines.memory.l1.accesses, lines.node_fetches + lines.triangle_fetches);
  o.gpu.rt.request_bytes = 32;
  const SimStats s = run(w, o);
  EXPECT_EQ(s.memory.l1.accesses, s.node_fetches + s.triangle_fetches);
  EXPECT_EQ(s.node_fetches, lines.node_fetches);
}

// rt.triangle_records: a leaf's triangles are fetched and tested one after the other, each
// paying the test latency (the compute-bound figure of IdealMemoryGivesTheComputeBoundFigure).
TEST(Sim, TriangleRecordsAreTestedOneAfterAnother) {
  const World w = make_world(own("spd_balls.glb"), 16);
  SimOptions o;
  o.gpu = ideal_memory(mobile());
  o.gpu.units = o.gpu.warps_per_unit = o.gpu.warp_size = 1;
  o.gpu.box = {.latency = 3, .per_cycle = 1};
  o.gpu.triangle = {.latency = 5, .per_cycle = 1};
  o.gpu.rt.triangle_records = true;
  const Golden g = golden(w, o.pred.mode);
  ASSERT_GT(g.work.tri_tests, g.work.leaf_visits);  // leaves of several triangles
  EXPECT_EQ(run(w, o).cycles, g.work.interior_tests * 3 + g.work.tri_tests * 5 + g.rays);
  // The layout's sizes move addresses, not the work.
  o.gpu = mobile();
  o.gpu.rt.triangle_records = true;
  o.gpu.rt.triangle_bytes = 48;
  o.gpu.rt.leaf_end_bytes = 16;
  const SimStats s = run(w, o);
  EXPECT_EQ(s.triangle_fetches, g.work.tri_tests);
  EXPECT_EQ(s.node_fetches, g.work.interior_tests);
}

// An oracle on unbounded AO rays (every ray that hits is told its leaf), timed for replay.
SimOptions oracle_ao(const GpuConfig& g) {
  SimOptions o;
  o.gpu = g;
  o.kind = sim::PredictorKind::kTimed;
  o.timed.oracle = true;
  o.timed.lookup_latency = o.timed.decision_latency = 0;
  o.timed.lookups_per_cycle = 32;
  return o;
}

// Replay: a correct prediction's fetches replace the walk (the predicted walk only, from the
// predicted node's own pair: no start fetch), a wrong one's precede the root walk, and the
// fetch list goes on without waiting for the decision, so its latency does not count.
TEST(Sim, ReplaySettlesTheFetchListAtThePrediction) {
  const World w = make_world(own("cornell_box.glb"), 32, kInf);
  const Golden g = golden(w, PredictMode::kClosestExact);
  uint64_t cycles[2][2] = {};
  for (const bool replay : {false, true})
    for (const uint32_t decision : {0u, 300u}) {
      SimOptions o = oracle_ao(mobile());
      o.replay = replay;
      o.timed.decision_latency = decision;
      std::vector<Hit> answers;
      o.answers = &answers;
      const SimStats s = run(w, o);
      cycles[replay][decision > 0] = s.cycles;
      EXPECT_TRUE(golden_answers(w, g, answers));
      const PredictStats p = s.predict_total();
      ASSERT_GT(p.skipped_walks, 0u);
      if (replay) {
        EXPECT_EQ(s.start_fetches, 0u);
        // Every node fetched is a test the golden model counts: the predicted walks, and the
        // root walks of the rays they did not answer.
        EXPECT_EQ(s.node_fetches, p.hrpp.interior_tests);
      } else {
        EXPECT_GT(s.start_fetches, 0u);
      }
    }
  EXPECT_EQ(cycles[1][0], cycles[1][1]);  // replay: the decision's latency is not waited for
  EXPECT_LT(cycles[0][0], cycles[0][1]);
  EXPECT_LT(cycles[1][0], cycles[0][0]);
}

// MICRO 2021's repacking: only rays given a prediction leave their warps (for one pool), a warp
// waits in the predictor for the timer, and every answer stays the golden walk's.
TEST(Sim, Micro21RepackingPoolsOnlyPredictedRays) {
  const World w = make_world(own("cornell_box.glb"), 32, kInf);
  const Golden g = golden(w, PredictMode::kClosestExact);
  uint64_t cycles_by_timer[2] = {};
  for (const uint32_t timer : {20u, 200u}) {
    SimOptions o = oracle_ao(mobile());
    o.repack = SimOptions::Repack::kMicro21;
    o.repack_timer = timer;
    std::vector<Hit> answers;
    o.answers = &answers;
    const SimStats s = run(w, o);
    EXPECT_TRUE(golden_answers(w, g, answers));
    const PredictStats p = s.predict_total();
    ASSERT_GT(p.true_positive, 0u);
    ASSERT_LT(p.true_positive, s.rays);  // some rays miss: no prediction, they stay
    EXPECT_EQ(s.pooled_rays, p.true_positive + p.false_positive);
    EXPECT_GE(s.repacked_warps * 32, s.pooled_rays);
    cycles_by_timer[timer > 20] = s.cycles;
    if (timer == 20) {  // the project's repacking pools every ray
      o.repack = SimOptions::Repack::kPredicted;
      EXPECT_EQ(run(w, o).pooled_rays, s.rays);
    }
  }
  EXPECT_LT(cycles_by_timer[0], cycles_by_timer[1]);
  // One warp per unit: the pool outgrows the unit's warp slots, as theirs may.
  SimOptions o = oracle_ao(mobile());
  o.gpu.warps_per_unit = 1;
  o.repack = SimOptions::Repack::kMicro21;
  std::vector<Hit> answers;
  o.answers = &answers;
  const SimStats s = run(w, o);
  EXPECT_TRUE(golden_answers(w, g, answers));
  EXPECT_GT(s.pooled_rays, 2u * 32);
}

// Counting cycles until the admitted warps retire: no predictor, the same cycles; with MICRO
// 2021's repacking, a warp whose rays all left retires when released, so the count ends before
// the last pooled ray's answer.
TEST(Sim, CountingOriginalWarpsStopsAtTheirRetirement) {
  const World w = make_world(own("cornell_box.glb"), 32, kInf);
  SimOptions none;
  none.gpu = mobile();
  const uint64_t all = run(w, none).cycles;
  none.count_original_warps = true;
  EXPECT_EQ(run(w, none).cycles, all);
  SimOptions o = oracle_ao(mobile());
  o.repack = SimOptions::Repack::kMicro21;
  o.repack_timer = 200;  // the pool's last rays leave 200 cycles after the last warp's release
  const uint64_t rays = run(w, o).cycles;
  o.count_original_warps = true;
  EXPECT_LT(run(w, o).cycles, rays);
}

// A warm-up kernel's cycles are not counted; a launch latency is added to every run.
TEST(Sim, WarmupRaysAndTheLaunchLatency) {
  const World w = make_world(own("cornell_box.glb"), 32, kInf);
  const Golden g = golden(w, PredictMode::kClosestExact);
  SimOptions o;
  o.gpu = mobile();
  const uint64_t all = run(w, o).cycles;
  o.gpu.rt.launch_latency = 5000;
  EXPECT_EQ(run(w, o).cycles, all + 5000);
  o.gpu.rt.launch_latency = 0;
  o.warmup_rays = w.rays.size() / 2 + 7;  // not a whole number of warps
  std::vector<Hit> answers;
  o.answers = &answers;
  const SimStats s = run(w, o);
  EXPECT_TRUE(golden_answers(w, g, answers));
  EXPECT_EQ(s.rays, g.rays);
  EXPECT_LT(s.cycles, all * 3 / 4);
  EXPECT_GT(s.cycles, all / 4);
}

// The loss breakdown against the oracle (LossTally) on a hand-built stream where each class
// occurs: one unit, one ray at a time, a table of one entry, three quads in separate leaves, rays
// along +z whose keys are their origin cells (4 units wide).
struct LossWorld {
  Scene scene;
  Bvh bvh;
  std::vector<RayRecord> rays;
};

LossWorld loss_world(const std::vector<std::pair<float, RayKind>>& origins) {
  LossWorld w;
  auto quad = [&](float x0, float x1, float z) {
    w.scene.triangles.push_back({Vec3(x0, -1, z), Vec3(x1, -1, z), Vec3(x1, 1, z)});
    w.scene.triangles.push_back({Vec3(x0, -1, z), Vec3(x1, 1, z), Vec3(x0, 1, z)});
  };
  quad(-8, -7, 10);     // A1: hit from x = -7.5
  quad(-5, -4, 1000);   // A2: hit from x = -4.5, the same origin cell
  quad(4, 5, 10);       // B: hit from x = 4.5, another cell
  quad(100, 101, 500);  // far away: the quads split into their own leaves
  w.bvh = build_bvh(w.scene.triangles);
  for (const auto& [x, kind] : origins) {
    RayRecord r;
    r.ray.org = Vec3(x, 0, 0);
    r.ray.dir = Vec3(0, 0, 1);
    r.ray.tnear = 0;
    r.ray.tfar = kInf;
    r.kind = kind;
    r.id = w.rays.size();
    w.rays.push_back(r);
  }
  return w;
}

SimOptions loss_options(const LossWorld& w) {
  SimOptions o;
  o.gpu = ideal_memory(mobile());
  o.gpu.units = o.gpu.warps_per_unit = o.gpu.warp_size = 1;
  o.kind = sim::PredictorKind::kTimed;
  o.pred.hash.variant = HashVariant::kImproved;
  o.pred.hash.origin_bits = 4;
  o.pred.hash.origin_cell_exp = 2;
  o.pred.hash.dir_bits = 1;
  o.pred.hash.combine = CombineMode::kConcat;
  o.pred.hash.index_bits = 0;
  o.pred.table.sets = o.pred.table.ways = o.pred.table.nodes_per_entry = 1;
  o.pred.table.tag_bits = o.pred.hash.tag_bits();
  o.pred.go_up = 0;
  o.timed = {.lookup_latency = 1,
             .decision_latency = 0,
             .update_latency = 0,
             .lookups_per_cycle = 1,
             .updates_per_cycle = 1,
             .credits = 0};
  EXPECT_EQ(o.pred.hash.validate(), "");
  return o;
}

TEST(Sim, LossTallyClassifiesEveryHittingRay) {
  using L = sim::LossTally;
  // A1 (compulsory), A1 again (captured), A2's ray with A1's key (aliased: the entry holds A1),
  // B (compulsory: its write evicts the key of A1 and A2), A2 again (evicted).
  const LossWorld w = loss_world({{-7.5f, RayKind::kAo},
                                  {-7.5f, RayKind::kAo},
                                  {-4.5f, RayKind::kAo},
                                  {4.5f, RayKind::kAo},
                                  {-4.5f, RayKind::kAo}});
  Counters c;
  const Hit a1 = engine_walk(w.bvh, w.rays[0].ray, true, 0, &c),
            a2 = engine_walk(w.bvh, w.rays[2].ray, true, 0, &c),
            b = engine_walk(w.bvh, w.rays[3].ray, true, 0, &c);
  ASSERT_TRUE(a1.hit() && a2.hit() && b.hit());
  ASSERT_NE(a1.leaf, a2.leaf);
  SimOptions o = loss_options(w);
  const HashKey k0 = hash_ray(w.rays[0].ray, o.pred.hash),
                k2 = hash_ray(w.rays[2].ray, o.pred.hash),
                k3 = hash_ray(w.rays[3].ray, o.pred.hash);
  ASSERT_EQ(k0.key, k2.key);
  ASSERT_NE(k0.key, k3.key);
  SimStats s = sim::simulate(w.bvh, w.rays, o);
  const L& t = s.loss;
  EXPECT_EQ(t.rays[L::kCompulsory], 2u);
  EXPECT_EQ(t.rays[L::kCaptured], 1u);
  EXPECT_EQ(t.rays[L::kAliased], 1u);
  EXPECT_EQ(t.rays[L::kEvicted], 1u);
  EXPECT_EQ(t.wrong_rays, 1u);
  uint64_t all = 0;
  for (uint64_t n : t.rays) all += n;
  EXPECT_EQ(all, 5u);
  // A write not yet landed: the second A1 ray finds it in flight.
  o.timed.update_latency = 100000;
  s = sim::simulate(w.bvh, std::vector<RayRecord>(w.rays.begin(), w.rays.begin() + 2), o);
  EXPECT_EQ(s.loss.rays[L::kCompulsory], 1u);
  EXPECT_EQ(s.loss.rays[L::kStale], 1u);
  // Confidence: the entry the first ray wrote is below the threshold for the second.
  o.timed.update_latency = 0;
  o.pred.table.conf_bits = 1;
  s = sim::simulate(w.bvh, std::vector<RayRecord>(w.rays.begin(), w.rays.begin() + 2), o);
  EXPECT_EQ(s.loss.rays[L::kSuppressed], 1u);
  // The gate closed from the start: of two rays entering together the second, which finds no
  // credit (one ray held at a time), walks without.
  o.pred.table.conf_bits = 0;
  o.timed.credits = 1;
  o.gpu.warp_size = 2;
  o.gate = 1;
  o.gate_first = 0;
  s = sim::simulate(w.bvh, std::vector<RayRecord>(w.rays.begin(), w.rays.begin() + 2), o);
  EXPECT_EQ(s.loss.rays[L::kGated], 1u);
  EXPECT_EQ(s.loss.rays[L::kCompulsory], 1u);
  // A kind the design does not predict.
  const LossWorld p = loss_world({{-7.5f, RayKind::kPrimary}, {-7.5f, RayKind::kAo}});
  SimOptions q = loss_options(p);
  q.any_hit_only = true;
  s = sim::simulate(p.bvh, p.rays, q);
  EXPECT_EQ(s.loss.rays[L::kNotOffered], 1u);
  EXPECT_EQ(s.loss.rays[L::kCompulsory], 1u);
}

TEST(Sim, GpuConfigurationErrorsNameTheKey) {
  nlohmann::json j = mobile().to_json();
  EXPECT_NO_THROW(sim::gpu_config_from_json(j, "mobile"));
  auto error = [](nlohmann::json bad) {
    try {
      sim::gpu_config_from_json(bad, "f.json");
    } catch (const sim::GpuConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  nlohmann::json bad = j;
  bad["l1"]["lines"] = 4;
  EXPECT_NE(error(bad).find("unknown key \"lines\""), std::string::npos) << error(bad);
  bad = j;
  bad["l2"]["line_bytes"] = 96;
  EXPECT_NE(error(bad).find("power of two"), std::string::npos) << error(bad);
  bad = j;
  bad.erase("units");
  EXPECT_NE(error(bad).find("\"units\""), std::string::npos) << error(bad);
  bad = j;
  bad["dram"]["latency"] = -1;
  EXPECT_NE(error(bad).find("latency"), std::string::npos) << error(bad);
  bad = j;
  bad["l1"]["sector_bytes"] = 48;
  EXPECT_NE(error(bad).find("sector_bytes"), std::string::npos) << error(bad);
  bad = j;
  bad["rt_unit"] = {{"request_bytes", 32}, {"triangle_record", true}};
  EXPECT_NE(error(bad).find("unknown key \"triangle_record\""), std::string::npos) << error(bad);
  bad = j;
  bad["rt_unit"] = {{"request_bytes", 256}};
  EXPECT_NE(error(bad).find("request_bytes"), std::string::npos) << error(bad);
  const GpuConfig m21 =
      sim::load_gpu_config(std::string(HRPP_SOURCE_DIR) + "/model/gpu/micro21-sim.json");
  EXPECT_EQ(m21.rt.request_bytes, 32u);
  EXPECT_TRUE(m21.rt.triangle_records);
  EXPECT_EQ(sim::gpu_config_from_json(m21.to_json(), "again").to_json(), m21.to_json());
}

}  // namespace
}  // namespace hrpp
