// The cost of accuracy (docs/cost_model.md): the cycle cost model on hand-made counters, the
// predictor's update delay, the RTL's update delay from the cycle model, and the speculative
// image error.
#include "hrpp/timing/cost_model.h"

#include <gtest/gtest.h>

#include "hrpp/hardware/rtl_update_delay.h"
#include "hrpp/report/spec_image.h"
#include "test_util.h"

namespace hrpp {
namespace {

TEST(CostModel, CyclesFromHandMadeCounters) {
  CostModel m;  // 32 fetch, 8 box, 20 triangle, 4 mispredict; the RTL's lookup and decision
  EXPECT_EQ(m.lookup, uint32_t(rtl::kPredictionLatency));
  EXPECT_EQ(m.decision, uint32_t(rtl::kDecisionLatency));
  PredictStats s;
  s.rays = 3;
  s.invalid_rays = 1;
  // Baseline: 10 interior nodes (21 boxes: the root's own box too), 2 leaves, 5 triangles.
  s.baseline = {.interior_tests = 10, .box_tests = 21, .leaf_visits = 2, .tri_tests = 5};
  // HRPP: 4 interior nodes, 10 boxes (two walks), 1 leaf, 2 triangles.
  s.hrpp = {.interior_tests = 4, .box_tests = 10, .leaf_visits = 1, .tri_tests = 2};
  s.true_positive = 1;
  s.false_positive = 1;
  const CycleCost c = cycle_cost(s, m);
  EXPECT_DOUBLE_EQ(c.baseline, 12 * 32 + 11 * 8 + 5 * 20);  // 572
  // walks 5*32 + 6*8 + 2*20 = 248; 2 valid lookups, 2 decisions, 1 mispredict
  const double hrpp = 248 + 2 * m.lookup + 2 * m.decision + 1 * 4;
  EXPECT_DOUBLE_EQ(c.hrpp, hrpp);
  EXPECT_NEAR(c.saved_fraction(), 1.0 - hrpp / 572.0, 1e-12);
  const auto j = cycle_cost_json(s, m);
  EXPECT_DOUBLE_EQ(j["baseline_cycles_per_ray"].get<double>(), 572.0 / 3);
}

PredictorConfig small_config(const Scene& s, const Bvh& bvh, uint32_t delay) {
  PredictorConfig c;
  c.mode = PredictMode::kClosestExact;
  c.hash.origin_cell_exp = cell_exp_for(s.bounds, c.hash.origin_bits);
  c.table.unbounded = true;
  c.table.nodes_per_entry = 2;
  c.hash.index_bits = 0;
  c.table.node_bits = node_bits_for(bvh.nodes.size());
  c.table.tag_bits = 0;
  c.table.key_bits = c.hash.key_bits();
  c.update_delay = delay;
  return c;
}

// The same ray, again and again: with delay D the first D + 1 rays find nothing; every later
// one finds the first ray's write.
TEST(CostModel, UpdateDelayHidesRecentWrites) {
  Scene s = test::scene_from_triangles({{Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0)}});
  Bvh bvh = build_bvh(s.triangles);
  RayRecord r;
  r.ray.org = Vec3(0, 0, -1);
  r.ray.dir = Vec3(0, 0, 1);
  for (uint32_t delay : {0u, 1u, 5u}) {
    Predictor pred(bvh, small_config(s, bvh, delay));
    for (uint32_t i = 0; i < 10; ++i) {
      const RayResult res = pred.process(r);
      ASSERT_TRUE(res.baseline.hit());
      EXPECT_EQ(res.predicted, i > delay) << "delay " << delay << ", ray " << i;
    }
    EXPECT_EQ(pred.total().table_updates, 10u);
  }
}

TEST(CostModel, MeasureTimeFillsTheTimes) {
  Scene s = test::scene_from_triangles(test::random_soup(2000, 0.1f, 3));
  Bvh bvh = build_bvh(s.triangles);
  PredictorConfig c = small_config(s, bvh, 0);
  c.measure_time = true;
  Predictor pred(bvh, c);
  WorkloadOptions wo;
  wo.width = wo.height = 16;
  generate_rays(s, bvh, wo, [&](const RayRecord& r, const Hit*) { pred.process(r); });
  EXPECT_GT(pred.total().baseline_ns, 0u);
  EXPECT_GT(pred.total().hrpp_ns, 0u);
  c.measure_time = false;
  Predictor untimed(bvh, c);
  generate_rays(s, bvh, wo, [&](const RayRecord& r, const Hit*) { untimed.process(r); });
  EXPECT_EQ(untimed.total().baseline_ns, 0u);
  EXPECT_EQ(untimed.total().skipped_walks, pred.total().skipped_walks);
}

// The RTL pipeline's delay: every cycle the engine takes adds one ray looked up before the write
// lands, until the 64 ray ids of the default configuration are all in flight.
TEST(CostModel, RtlUpdateDelayFollowsTheWalkLatency) {
  const uint32_t d0 = rtl_update_delay(0);
  EXPECT_GT(d0, 6u);  // at least a ray's way through hash and lookup, one ray per cycle
  EXPECT_LT(d0, 40u);
  for (uint32_t l : {1u, 7u, 20u}) EXPECT_EQ(rtl_update_delay(l), std::min(63u, d0 + l)) << l;
  EXPECT_EQ(rtl_update_delay(500), 63u);
}

TEST(CostModel, SpecImageCountsDifferingPixels) {
  Scene s = test::scene_from_triangles({{Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0)}});
  SpecImage img(s, 4, 2, 1);
  RayRecord r;
  r.ray.org = Vec3(0, 0, -1);
  r.ray.dir = Vec3(0, 0, 1);
  RayResult same, wrong;
  same.baseline.prim = same.answer.prim = 0;
  same.baseline.t = same.answer.t = 1.f;
  wrong.baseline = same.baseline;  // the answer: a miss
  for (uint32_t p = 0; p < 8; ++p) {
    r.pixel = p;
    img.add(r, p == 5 ? wrong : same);
  }
  r.kind = RayKind::kShadow;  // ignored
  img.add(r, wrong);
  const auto j = img.finish("");
  EXPECT_EQ(j["primary_samples"].get<uint64_t>(), 8u);
  EXPECT_EQ(j["wrong_primary_samples"].get<uint64_t>(), 1u);
  EXPECT_DOUBLE_EQ(j["differing_pixel_fraction"].get<double>(), 1.0 / 8);
  EXPECT_GT(j["mean_abs_error"].get<double>(), 0.0);
  SpecImage clean(s, 4, 2, 1);
  r.kind = RayKind::kPrimary;
  for (uint32_t p = 0; p < 8; ++p) {
    r.pixel = p;
    clean.add(r, same);
  }
  EXPECT_DOUBLE_EQ(clean.finish("")["mean_abs_error"].get<double>(), 0.0);
}

}  // namespace
}  // namespace hrpp
