// The Embree cross-check on every shared scene and on the project's own scenes.
#include "hrpp/reference/crosscheck.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "hrpp/trace/traverse.h"
#include "test_util.h"

namespace hrpp {
namespace {

void check_scene(const std::string& path, uint64_t rays) {
  Scene s = load_scene(path);
  Bvh bvh = build_bvh(s.triangles);
  CrossCheckOptions opt;
  opt.rays = rays;
  CrossCheckResult r = cross_check(s, bvh, opt);
  SCOPED_TRACE(path);
  EXPECT_TRUE(r.passed()) << r.failure() << "\n" << r.to_json().dump(2);
  EXPECT_GE(double(r.total.compared), kMinComparedFraction * double(r.total.rays));
  EXPECT_EQ(r.total.outside_embree, 0u);
  EXPECT_EQ(r.total.hit_mismatches, 0u);
  EXPECT_EQ(r.total.t_mismatches, 0u);
  EXPECT_EQ(r.total.prim_mismatches, 0u);
  EXPECT_GE(r.by_kind[int(RayKind::kPrimary)].compared, rays * 9 / 10);
  EXPECT_GT(r.total.hits, 0u);
  std::printf(
      "%s: %llu rays compared (%llu primary, %llu shadow, %llu ao), %llu grazes, %llu ties\n",
      std::filesystem::path(path).filename().c_str(), (unsigned long long)r.total.compared,
      (unsigned long long)r.by_kind[0].compared, (unsigned long long)r.by_kind[1].compared,
      (unsigned long long)r.by_kind[2].compared, (unsigned long long)r.total.grazes,
      (unsigned long long)r.total.ties);
}

class SharedScene : public ::testing::TestWithParam<const char*> {};

TEST_P(SharedScene, AgreesWithEmbree) {
  std::string path = test::shared_scene(GetParam());
  if (path.empty()) GTEST_SKIP() << "../shared/scenes absent: " << GetParam() << " not checked";
  check_scene(path, 150000);
}

INSTANTIATE_TEST_SUITE_P(CrossCheck, SharedScene,
                         ::testing::Values("bunny.glb", "teapot.glb", "killeroo.glb",
                                           "happy_buddha.glb", "sponza.glb", "cornell_box.glb"),
                         [](const auto& info) {
                           std::string n = info.param;
                           return n.substr(0, n.find('.'));
                         });

TEST(CrossCheck, OwnScenesAgreeWithEmbree) {
  for (const auto& p : test::own_scenes()) check_scene(p, 40000);
}

TEST(CrossCheck, DetectsAWrongTraversal) {
  // The check can fail: a BVH whose boxes were shrunk misses hits Embree finds.
  Scene s = load_scene(test::own_scenes().front());
  Bvh bvh = build_bvh(s.triangles);
  for (auto& n : bvh.nodes)
    if (n.is_leaf()) n.hi = n.lo + 0.5f * (n.hi - n.lo);
  build_pairs(bvh);  // the traversal reads the boxes from the pair layout
  CrossCheckOptions opt;
  opt.rays = 20000;
  CrossCheckResult r = cross_check(s, bvh, opt);
  EXPECT_FALSE(r.passed());
  EXPECT_GT(r.total.hit_mismatches + r.total.prim_mismatches, 100u);
}

// Quad Q of HARD_CASES.md: the plane z = 1 over [-1, 1]^2.
std::vector<Triangle> quad() {
  return {{{1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}, {{1, -1, 1}, {-1, -1, 1}, {-1, 1, 1}}};
}

TEST(CrossCheck, ACheckThatComparedNothingFails) {
  Scene s = test::scene_from_triangles(quad());
  Bvh bvh = build_bvh(s.triangles);
  EmbreeScene emb(s.triangles, kEmbreeReferenceConfig, true);
  const Ray nan_ray{{std::nanf(""), 0, 0}, {0, 0, 1}};
  CrossCheckResult r = cross_check_rays(s, bvh, emb, {{nan_ray, RayKind::kPrimary}});
  EXPECT_EQ(r.total.compared, 0u);
  EXPECT_FALSE(r.passed());
  EXPECT_NE(r.failure().find("no ray compared"), std::string::npos) << r.failure();
  EXPECT_EQ(r.to_json()["passed"], false);
  EXPECT_NE(r.to_json()["failure"].get<std::string>().find("no ray compared"), std::string::npos);
  // Nothing at all to compare: a scene without lights asked for shadow rays only.
  CrossCheckOptions opt;
  opt.rays = 1000;
  opt.kinds = {RayKind::kShadow};
  CrossCheckResult none = cross_check(s, bvh, opt);
  EXPECT_EQ(none.total.rays, 0u);
  EXPECT_FALSE(none.passed());
  EXPECT_NE(none.failure().find("no ray compared (0 rays"), std::string::npos) << none.failure();
}

TEST(CrossCheck, FewerThanTheRequiredFractionComparedFails) {
  Scene s = test::scene_from_triangles(quad());
  Bvh bvh = build_bvh(s.triangles);
  EmbreeScene emb(s.triangles, kEmbreeReferenceConfig, true);
  const Ray good{{0.25f, 0.5f, 0}, {0, 0, 1}}, bad{{0, 0, 0}, {0, 0, 0}};
  auto run = [&](int n_good, int n_bad) {
    std::vector<std::pair<Ray, RayKind>> rays;
    for (int i = 0; i < n_good; ++i) rays.push_back({good, RayKind::kPrimary});
    for (int i = 0; i < n_bad; ++i) rays.push_back({bad, RayKind::kPrimary});
    return cross_check_rays(s, bvh, emb, rays);
  };
  EXPECT_TRUE(run(99, 1).passed()) << run(99, 1).failure();
  const CrossCheckResult r = run(98, 2);
  EXPECT_EQ(r.total.compared, 98u);
  EXPECT_FALSE(r.passed());
  EXPECT_NE(r.failure().find("only 98 of 100 rays compared"), std::string::npos) << r.failure();
}

TEST(CrossCheck, OriginsOutsideEmbreesRangeAreNeverSent) {
  // This machine's Embree aborts on an origin component of 1.8441e18 (its FLT_LARGE is
  // 1.844e18) and traces 1.8439e18. Both are valid rays for our traversal.
  Scene s = test::scene_from_triangles(quad());
  Bvh bvh = build_bvh(s.triangles);
  EmbreeScene emb(s.triangles, kEmbreeReferenceConfig, true);
  std::vector<std::pair<Ray, RayKind>> rays;
  for (const Vec3& o : {Vec3(1.8441e18f, 0, 0), Vec3(0, -2e18f, 0), Vec3(0, 0, 1e30f)})
    for (RayKind k : {RayKind::kPrimary, RayKind::kShadow}) {
      const Ray r{o, {1, 0, 0}};
      EXPECT_EQ(validate_ray(r), RayError::kNone);
      EXPECT_FALSE(embree_accepts(r));
      rays.push_back({r, k});
    }
  const Ray inside{{1.8439e18f, 0, 0}, {1, 0, 0}};
  EXPECT_TRUE(embree_accepts(inside));
  rays.push_back({inside, RayKind::kPrimary});
  rays.push_back({inside, RayKind::kShadow});
  // Reaching the end proves none of the six was sent (Embree would abort the process).
  CrossCheckResult r = cross_check_rays(s, bvh, emb, rays);
  EXPECT_EQ(r.total.outside_embree, 6u);
  EXPECT_EQ(r.total.invalid_rays, 0u);
  EXPECT_EQ(r.total.compared, 2u);
  EXPECT_EQ(r.to_json()["outside_embree_range"], 6u);
  EXPECT_FALSE(r.passed()) << "2 of 8 compared";
  EXPECT_NE(r.failure().find("6 outside Embree's range"), std::string::npos) << r.failure();
  // Called directly, EmbreeScene refuses them with an exception instead of aborting.
  EXPECT_THROW(emb.intersect(rays[0].first), std::invalid_argument);
  EXPECT_THROW(emb.occluded(rays[0].first), std::invalid_argument);
}

}  // namespace
}  // namespace hrpp
