// The Embree cross-check on every shared scene and on the project's own scenes.
#include <gtest/gtest.h>

#include <filesystem>

#include "hrpp/crosscheck.h"
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
  EXPECT_TRUE(r.passed()) << r.to_json().dump(2);
  EXPECT_EQ(r.total.hit_mismatches, 0u);
  EXPECT_EQ(r.total.t_mismatches, 0u);
  EXPECT_EQ(r.total.prim_mismatches, 0u);
  EXPECT_GE(r.by_kind[int(RayKind::kPrimary)].compared, rays * 9 / 10);
  EXPECT_GT(r.total.hits, 0u);
  std::printf("%s: %llu rays compared (%llu primary, %llu shadow, %llu ao), %llu grazes, %llu ties\n",
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

}  // namespace
}  // namespace hrpp
