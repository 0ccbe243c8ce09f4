// MICRO 2021's grid-spherical hash (micro21) on hand-made rays, the any-hit-only rule, the named
// predictor presets, and unbounded AO rays (--ao-distance inf).
#include "hrpp/predictor/presets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "hrpp/hardware/rtl_config.h"
#include "hrpp/predictor/hash.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/trace/ray.h"
#include "hrpp/workload/workload.h"
#include "test_util.h"

namespace hrpp {
namespace {

// Bounds [-1, 1] x [-2, 2] x [-3, 3]: the grid has 32 cells of 1/16, 1/8, 3/16 per axis.
HashConfig micro21() {
  HashConfig c;
  c.variant = HashVariant::kMicro21;
  c.origin_bits = 5;
  c.dir_bits = 3;
  c.combine = CombineMode::kXor;
  c.index_bits = 8;
  c.bounds_lo = {-1.f, -2.f, -3.f};
  c.bounds_hi = {1.f, 2.f, 3.f};
  return c;
}

uint64_t key_of(Vec3 o, Vec3 d, const HashConfig& c = micro21()) {
  Ray r;
  r.org = o;
  r.dir = d;
  return hash_ray(r, c).key;
}

// Origin cells x, y, z packed x | y | z (5 bits each).
constexpr uint64_t cells(uint64_t x, uint64_t y, uint64_t z) { return x << 10 | y << 5 | z; }
// Direction phi | theta: theta = whole degrees of acos(d.z) >> 5, phi = whole degrees of
// atan2(d.y, d.x) + 180 >> 5.
constexpr uint64_t sphere(uint64_t phi_deg, uint64_t theta_deg) {
  return (phi_deg >> 5) << 3 | theta_deg >> 5;
}

TEST(Micro21Hash, FieldWidths) {
  const HashConfig c = micro21();
  EXPECT_EQ(c.validate(), "");
  EXPECT_EQ(c.origin_field_bits(), 5);
  EXPECT_EQ(c.dir_field_bits(), 7);  // phi 4 bits | theta 3 bits
  EXPECT_EQ(c.key_bits(), 15);       // max(15, 7) with XOR
  HashConfig cat = c;
  cat.combine = CombineMode::kConcat;
  EXPECT_EQ(cat.key_bits(), 22);
  EXPECT_EQ(key_of({1.f, 2.f, 3.f}, {0.f, 0.f, 1.f}, cat), cells(31, 31, 31) << 7 | sphere(180, 0));
  HashConfig bad = c;
  bad.dir_bits = 9;
  EXPECT_NE(bad.validate(), "");
  bad = c;
  bad.bounds_hi[1] = -3.f;
  EXPECT_NE(bad.validate(), "");
}

TEST(Micro21Hash, OriginGrid) {
  const Vec3 up{0.f, 0.f, 1.f};  // direction code sphere(180, 0) = 5 << 3 = 40
  EXPECT_EQ(sphere(180, 0), 40u);
  EXPECT_EQ(key_of({-1.f, -2.f, -3.f}, up), cells(0, 0, 0) ^ 40);  // lo: cell 0
  EXPECT_EQ(key_of({0.f, 0.f, 0.f}, up), cells(16, 16, 16) ^ 40);  // centre: 0.5 * 32 = 16
  EXPECT_EQ(key_of({0.f, 0.f, 0.f}, up), 0x4238u);                 // 0x4210 ^ 0x28
  EXPECT_EQ(key_of({1.f, 2.f, 3.f}, up), cells(31, 31, 31) ^ 40);  // hi: 32, clamped to 31
  // Truncation: 5.5 -> 5, 7.25 -> 7, 30.5 -> 30.
  EXPECT_EQ(key_of({-0.65625f, -1.09375f, 2.71875f}, up), cells(5, 7, 30) ^ 40);
  // Outside the bounds: clamped to the first and last cells.
  EXPECT_EQ(key_of({-5.f, 9.f, 0.f}, up), cells(0, 31, 16) ^ 40);
  // A flat axis (lo == hi): cell 0 (theirs divides 0 by 0).
  HashConfig flat = micro21();
  flat.bounds_lo[2] = flat.bounds_hi[2] = 0.5f;
  EXPECT_EQ(key_of({0.f, 0.f, 0.5f}, up, flat), cells(16, 16, 0) ^ 40);
}

TEST(Micro21Hash, DirectionSphere) {
  const Vec3 lo{-1.f, -2.f, -3.f};  // origin code 0: the key is the direction code
  EXPECT_EQ(key_of(lo, {0.f, 0.f, 1.f}), sphere(180, 0));     // +z: theta 0, atan2(0, 0) = 0
  EXPECT_EQ(key_of(lo, {0.f, 0.f, -1.f}), sphere(180, 180));  // -z: theta 180
  EXPECT_EQ(key_of(lo, {1.f, 0.f, 0.f}), sphere(180, 90));    // +x: phi 0 + 180
  EXPECT_EQ(key_of(lo, {-1.f, 0.f, 0.f}), sphere(360, 90));   // -x: atan2(+0, -1) = pi: 360
  EXPECT_EQ(key_of(lo, {-1.f, -0.f, 0.f}), sphere(0, 90));    // atan2(-0, -1) = -pi: 0
  EXPECT_EQ(key_of(lo, {0.f, 1.f, 0.f}), sphere(270, 90));    // +y
  EXPECT_EQ(key_of(lo, {0.f, -1.f, 0.f}), sphere(90, 90));    // -y
  const float s = 1.f / std::sqrt(3.f);
  EXPECT_EQ(key_of(lo, {s, s, s}), sphere(225, 54));  // theta 54.7 -> 54, phi 45 + 180
  EXPECT_EQ(key_of(lo, {s, s, s}), 57u);              // 7 << 3 | 1
  // Not normalised (as theirs): d.z = 0.9 gives theta 25.8 -> bucket 0 (normalised: 48 -> 1).
  EXPECT_EQ(key_of(lo, {1.f, 0.f, 0.9f}), sphere(180, 25));
  EXPECT_EQ(key_of(lo, {0.f, 0.f, 2.f}), sphere(180, 0));  // d.z clamped to 1
}

TEST(Micro21Hash, OriginXorDirectionAndSplit) {
  const HashConfig c = micro21();
  Ray r;
  r.org = {0.f, 0.f, 0.f};
  r.dir = {-1.f, 0.f, 0.f};
  const HashKey k = hash_ray(r, c);
  EXPECT_EQ(k.key, cells(16, 16, 16) ^ sphere(360, 90));  // 0x4210 ^ 0x5A
  EXPECT_EQ(k.index, (k.key & 0xFF) ^ (k.key >> 8));      // XOR fold of 8-bit chunks
  EXPECT_EQ(k.tag, k.key >> 8);
}

// A box of two triangles facing +z at z = 0 and a ray stream of primary rays (closest hit) and
// AO rays (any hit) towards it.
struct Fixture {
  Scene scene;
  Bvh bvh;
  Fixture() {
    std::vector<Triangle> t;
    for (int i = 0; i < 16; ++i) {
      const float x = -2.f + 0.25f * i;
      t.push_back({{x, -2.f, 0.f}, {x + 0.25f, -2.f, 0.f}, {x, 2.f, 0.f}});
      t.push_back({{x + 0.25f, -2.f, 0.f}, {x + 0.25f, 2.f, 0.f}, {x, 2.f, 0.f}});
    }
    scene = test::scene_from_triangles(t);
    bvh = build_bvh(scene.triangles);
  }
  RayRecord ray(RayKind kind, float x, float y) const {
    RayRecord r;
    r.kind = kind;
    r.ray.org = {x, y, 1.f};
    r.ray.dir = {0.f, 0.f, -1.f};
    r.ray.tnear = 0.f;
    r.ray.tfar = std::numeric_limits<float>::infinity();
    return r;
  }
};

PredictorConfig resolved(const Fixture& f, PredictorConfig c) {
  EXPECT_EQ(resolve_for_scene(f.scene, f.bvh, &c), "");
  return c;
}

TEST(AnyHitOnly, ClosestHitRaysNeverReachTheTable) {
  Fixture f;
  PredictorConfig c = resolved(f, apply_preset(predictor_preset("micro21")));
  ASSERT_TRUE(c.any_hit_only);
  Predictor pred(f.bvh, c);
  for (int rep = 0; rep < 3; ++rep)
    for (int i = 0; i < 8; ++i) {
      const RayResult r = pred.process(f.ray(RayKind::kPrimary, -1.5f + 0.4f * i, 0.1f));
      EXPECT_FALSE(r.predicted);
      EXPECT_EQ(r.update_node, kNoNode);  // no table write
      EXPECT_TRUE(r.answer.hit());
    }
  EXPECT_EQ(pred.table().entries_used(), 0u);
  const PredictStats& p = pred.by_kind(RayKind::kPrimary);
  EXPECT_EQ(p.rays, 24u);
  EXPECT_EQ(p.unoffered_rays, 24u);
  EXPECT_EQ(p.table_updates, 0u);
  EXPECT_EQ(p.true_positive + p.false_positive, 0u);
  EXPECT_EQ(p.false_negative, 24u);  // they hit and were not predicted
  EXPECT_EQ(p.hrpp.interior_tests, p.baseline.interior_tests);
  EXPECT_EQ(p.hrpp.tri_tests, p.baseline.tri_tests);

  // AO rays (any hit) are offered: the second and third pass are predicted and verified.
  for (int rep = 0; rep < 3; ++rep)
    for (int i = 0; i < 8; ++i) pred.process(f.ray(RayKind::kAo, -1.5f + 0.4f * i, 0.1f));
  const PredictStats& a = pred.by_kind(RayKind::kAo);
  EXPECT_EQ(a.unoffered_rays, 0u);
  EXPECT_GT(a.table_updates, 0u);
  EXPECT_GE(a.true_positive, 16u);
  EXPECT_GT(pred.table().entries_used(), 0u);

  // The same primary rays with every kind offered: predicted after the first pass.
  c.any_hit_only = false;
  Predictor all(f.bvh, c);
  for (int rep = 0; rep < 3; ++rep)
    for (int i = 0; i < 8; ++i) all.process(f.ray(RayKind::kPrimary, -1.5f + 0.4f * i, 0.1f));
  EXPECT_EQ(all.by_kind(RayKind::kPrimary).unoffered_rays, 0u);
  EXPECT_GT(all.by_kind(RayKind::kPrimary).true_positive, 0u);

  // --mode anyhit answers every ray as an any-hit query: all are offered.
  c.any_hit_only = true;
  c.mode = PredictMode::kAnyHit;
  Predictor anyhit(f.bvh, c);
  for (int i = 0; i < 8; ++i) anyhit.process(f.ray(RayKind::kPrimary, -1.5f + 0.4f * i, 0.1f));
  EXPECT_EQ(anyhit.by_kind(RayKind::kPrimary).unoffered_rays, 0u);
  EXPECT_GT(anyhit.by_kind(RayKind::kPrimary).table_updates, 0u);
}

TEST(AnyHitOnly, MissesWriteNothing) {
  Fixture f;
  Predictor pred(f.bvh, resolved(f, apply_preset(predictor_preset("micro21"))));
  for (int rep = 0; rep < 3; ++rep) {
    const RayResult r = pred.process(f.ray(RayKind::kAo, 5.f, 5.f));  // beside the plate
    EXPECT_FALSE(r.answer.hit());
    EXPECT_EQ(r.update_node, kNoNode);
  }
  EXPECT_EQ(pred.table().entries_used(), 0u);
}

TEST(Presets, Names) {
  const std::vector<std::string> n = preset_names();
  for (const std::string& r : rtl_config_names())
    EXPECT_NE(std::find(n.begin(), n.end(), "rtl-" + r), n.end());
  EXPECT_NE(std::find(n.begin(), n.end(), "micro21"), n.end());
  EXPECT_NE(std::find(n.begin(), n.end(), "study2019"), n.end());
  EXPECT_EQ(std::find(n.begin(), n.end(), "none"), n.end());  // the simulator's, not a predictor
  EXPECT_THROW(predictor_preset("none"), std::invalid_argument);
  EXPECT_THROW(predictor_preset("rtl-nonesuch"), std::invalid_argument);
}

TEST(Presets, RtlPrimaryIsTheRtlConfiguration) {
  const RtlConfig rc = rtl_config("primary");
  const PredictorPreset p = predictor_preset("rtl-primary");
  EXPECT_EQ(p.hash.variant, rc.hash.variant);
  EXPECT_EQ(p.hash.precision, rc.hash.precision);
  EXPECT_EQ(p.hash.exp_bits, rc.hash.exp_bits);
  EXPECT_EQ(p.hash.origin_bits, rc.hash.origin_bits);
  EXPECT_EQ(p.hash.dir_bits, rc.hash.dir_bits);
  EXPECT_EQ(p.hash.combine, rc.hash.combine);
  EXPECT_EQ(p.table.sets, rc.table.sets);
  EXPECT_EQ(p.table.ways, rc.table.ways);
  EXPECT_EQ(p.table.nodes_per_entry, rc.table.nodes_per_entry);
  EXPECT_EQ(p.tag_bits, rc.table.tag_bits);
  // It leaves go-up, mode and the ray kinds to the caller.
  EXPECT_FALSE(p.go_up || p.mode || p.any_hit_only);
  PredictorConfig base;
  base.go_up = 2;
  base.mode = PredictMode::kClosestSpec;
  const PredictorConfig c = apply_preset(p, base);
  EXPECT_EQ(c.go_up, 2u);
  EXPECT_EQ(c.mode, PredictMode::kClosestSpec);
  EXPECT_FALSE(c.any_hit_only);
}

// A configuration with predict_kinds "any-hit" (default) sets its preset's ray kinds; the
// others leave them to the caller (above).
TEST(Presets, RtlDefaultPredictsAnyHitRaysOnly) {
  const RtlConfig rc = rtl_config("default");
  EXPECT_TRUE(rc.any_hit_only);
  EXPECT_EQ(rc.table.conf_bits, 1);
  const PredictorPreset p = predictor_preset("rtl-default");
  ASSERT_TRUE(p.any_hit_only.has_value());
  EXPECT_TRUE(*p.any_hit_only);
  EXPECT_TRUE(apply_preset(p, PredictorConfig{}).any_hit_only);
  EXPECT_FALSE(rtl_config("mobile").any_hit_only);
}

TEST(Presets, Micro21AndStudy2019) {
  const PredictorConfig m = apply_preset(predictor_preset("micro21"));
  EXPECT_EQ(m.hash.variant, HashVariant::kMicro21);
  EXPECT_EQ(m.hash.origin_bits, 5);
  EXPECT_EQ(m.hash.dir_bits, 3);
  EXPECT_EQ(m.hash.combine, CombineMode::kXor);
  EXPECT_FALSE(m.table.unbounded);
  EXPECT_EQ(m.table.sets * m.table.ways, 1024u);
  EXPECT_EQ(m.table.ways, 4u);
  EXPECT_EQ(m.table.nodes_per_entry, 1u);
  EXPECT_EQ(predictor_preset("micro21").tag_bits, -1);  // full tags
  EXPECT_EQ(m.go_up, 3u);
  EXPECT_TRUE(m.any_hit_only);
  Fixture f;
  const PredictorConfig r = resolved(f, m);
  EXPECT_EQ(r.hash.index_bits, 8);
  EXPECT_EQ(r.table.tag_bits, 15 - 8);
  EXPECT_EQ(r.hash.bounds_lo[0], f.bvh.nodes[0].lo.x);
  EXPECT_EQ(r.hash.bounds_hi[1], f.bvh.nodes[0].hi.y);

  const PredictorConfig s = apply_preset(predictor_preset("study2019"));
  EXPECT_EQ(s.hash.variant, HashVariant::kFaithful);
  EXPECT_EQ(s.hash.precision, 6);
  EXPECT_EQ(s.hash.exp_bits, 3);
  EXPECT_EQ(s.hash.combine, CombineMode::kXor);
  EXPECT_TRUE(s.table.unbounded);
  EXPECT_EQ(s.table.nodes_per_entry, 2u);
  EXPECT_EQ(s.go_up, 0u);
  EXPECT_FALSE(s.any_hit_only);
}

TEST(AoDistance, InfiniteGivesUnboundedValidRays) {
  Fixture f;
  WorkloadOptions wo;
  wo.width = wo.height = 16;
  wo.shadow = false;
  wo.ao_distance = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(std::isinf(ao_distance_for(f.scene, wo)));
  EXPECT_EQ(workload_json(f.scene, wo)["ao_distance"], "inf");
  uint64_t ao = 0;
  generate_rays(f.scene, f.bvh, wo, [&](const RayRecord& r, const Hit*) {
    if (r.kind != RayKind::kAo) return;
    ++ao;
    EXPECT_EQ(validate_ray(r.ray), RayError::kNone);
    EXPECT_TRUE(std::isinf(r.ray.tfar) && r.ray.tfar > 0);
  });
  EXPECT_GT(ao, 0u);
  wo.ao_distance = 0.f;
  EXPECT_TRUE(workload_json(f.scene, wo)["ao_distance"].is_number());
}

}  // namespace
}  // namespace hrpp
