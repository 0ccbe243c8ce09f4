// MICRO 2021's BVH (hrpp/trace/bvh_micro21.h): its invariants, spatial splits, determinism, the
// split callback, and the traversal over it against brute force and against Embree.
#include "hrpp/trace/bvh_micro21.h"

#include <gtest/gtest.h>
#include <xmmintrin.h>

#include <cfloat>
#include <cstring>
#include <thread>

#include "hrpp/reference/crosscheck.h"
#include "hrpp/reference/embree_ref.h"
#include "hrpp/trace/traverse.h"
#include "hrpp/util/rng.h"
#include "test_util.h"

namespace hrpp {
namespace {

constexpr BvhBuildOptions kMicro21{.builder = BvhBuilder::kMicro21Sbvh};

/// Two BVHs are the same: nodes, references and links bit for bit.
void expect_identical(const Bvh& a, const Bvh& b, const std::string& what) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size()) << what;
  ASSERT_EQ(a.tris.size(), b.tris.size()) << what;
  EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BvhNode)), 0)
      << what;
  EXPECT_EQ(std::memcmp(a.tris.data(), b.tris.data(), a.tris.size() * sizeof(Triangle)), 0) << what;
  EXPECT_EQ(a.prim_ids, b.prim_ids) << what;
  EXPECT_EQ(a.parent, b.parent) << what;
  EXPECT_EQ(a.depth, b.depth) << what;
}

/// n long thin triangles (length ~2, width ~0.002) across [-1, 1]^3 in random directions:
/// the boxes of such triangles overlap most, where spatial splits pay.
std::vector<Triangle> long_thin_triangles(size_t n, uint64_t seed) {
  std::vector<Triangle> out(n);
  auto u = [&](uint64_t i, uint64_t k) { return 2.f * uniform01(seed, i, k) - 1.f; };
  for (size_t i = 0; i < n; ++i) {
    const Vec3 a(u(i, 0), u(i, 1), u(i, 2)), b(u(i, 3), u(i, 4), u(i, 5));
    out[i] = {a, b, b + 0.002f * Vec3(u(i, 6), u(i, 7), u(i, 8))};
  }
  return out;
}

TEST(Micro21Bvh, NamesAndOptions) {
  BvhBuilder b;
  ASSERT_TRUE(parse_bvh_builder("micro21-sbvh", &b));
  EXPECT_EQ(b, BvhBuilder::kMicro21Sbvh);
  ASSERT_TRUE(parse_bvh_builder("sah", &b));
  EXPECT_EQ(b, BvhBuilder::kSah);
  EXPECT_FALSE(parse_bvh_builder("sbvh", &b));
  EXPECT_EQ(bvh_builder_name(BvhBuilder::kMicro21Sbvh), "micro21-sbvh");
  // The build records its builder and the settings it ran with, whatever else was asked.
  const Bvh bvh = build_bvh(test::random_soup(300, 0.05f, 3),
                            {.builder = BvhBuilder::kMicro21Sbvh, .max_leaf_size = 2, .bins = 8});
  EXPECT_EQ(bvh.options.builder, BvhBuilder::kMicro21Sbvh);
  EXPECT_EQ(bvh.options.max_leaf_size, kMicro21MaxLeafSize);
  EXPECT_EQ(bvh.options.bins, kMicro21ObjectBins);
  EXPECT_EQ(bvh.options.traversal_cost, 1.f);
}

TEST(Micro21Bvh, InvariantsOnRandomSoups) {
  for (size_t n : {1u, 2u, 3u, 7u, 100u, 5000u}) {
    const auto tris = test::random_soup(n, 0.05f, n * 31 + 1);
    const Bvh bvh = build_bvh(tris, kMicro21);
    EXPECT_EQ(check_bvh(bvh, n), "") << "n=" << n;
    EXPECT_GE(bvh.stats.references, n);
    for (size_t k = kMicro21MaxLeafSize + 1; k < bvh.stats.leaf_size_histogram.size(); ++k)
      EXPECT_EQ(bvh.stats.leaf_size_histogram[k], 0u) << "leaf larger than Embree's maximum";
  }
}

TEST(Micro21Bvh, InvariantsOnRealScenes) {
  auto scenes = test::own_scenes();
  for (const auto& s : test::shared_scenes()) scenes.push_back(s);
  for (const auto& path : scenes) {
    const Scene s = load_scene(path);
    const Bvh bvh = build_bvh(s.triangles, kMicro21);
    EXPECT_EQ(check_bvh(bvh, s.triangles.size()), "") << path;
    EXPECT_GT(bvh.stats.sah_cost, 0) << path;
  }
  if (test::shared_scenes().empty()) GTEST_SKIP() << "../shared/scenes absent: own scenes only";
}

TEST(Micro21Bvh, InvariantsWithCoincidentTriangles) {
  // 50 copies of one triangle: no split separates them; Embree's depth limit splits by count.
  const std::vector<Triangle> tris(50, Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const Bvh bvh = build_bvh(tris, kMicro21);
  EXPECT_EQ(check_bvh(bvh, tris.size()), "");
}

// Their converter wraps a root that is a leaf (GPUBVHConverter.cpp 36-53): a root whose child 0
// (our right child) is the leaf with box [-FLT_MAX, FLT_MAX] and whose child 1 (our left) holds
// the leaf's first triangle with an empty box. One triangle always makes a leaf root.
TEST(Micro21Bvh, LeafRootIsWrapped) {
  const std::vector<Triangle> tris{{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}};
  const Bvh bvh = build_bvh(tris, kMicro21);
  ASSERT_EQ(check_bvh(bvh, 1), "");
  ASSERT_EQ(bvh.nodes.size(), 3u);
  EXPECT_FALSE(bvh.nodes[0].is_leaf());
  EXPECT_EQ(bvh.nodes[0].right_or_first, 2u);
  EXPECT_TRUE(bvh.nodes[1].box().empty());
  EXPECT_EQ(bvh.nodes[1].lo, Vec3(FLT_MAX));
  EXPECT_EQ(bvh.nodes[1].hi, Vec3(-FLT_MAX));
  EXPECT_EQ(bvh.nodes[1].count, 1u);
  EXPECT_EQ(bvh.nodes[2].lo, Vec3(-FLT_MAX));
  EXPECT_EQ(bvh.nodes[2].hi, Vec3(FLT_MAX));
  EXPECT_EQ(bvh.nodes[2].count, 1u);
  EXPECT_EQ(bvh.stats.references, 2u);
  EXPECT_EQ(bvh.stats.sah_cost, 2.0);  // root 1, the wrapped leaf 1 x 1, the empty leaf 0
  // Every ray goes through the wrapped leaf: the triangle is found, never in the empty leaf.
  Counters c;
  const Hit h = closest_hit(bvh, Ray{{0.25f, 0.25f, 0}, {0, 0, 1}}, &c);
  ASSERT_TRUE(h.hit());
  EXPECT_EQ(h.leaf, 2u);
  EXPECT_EQ(c.leaf_visits, 1u);
  EXPECT_FALSE(closest_hit(bvh, Ray{{2, 2, 0}, {0, 0, 1}}, &c).hit());
}

TEST(Micro21Bvh, SpatialSplitsReferenceLongThinTrianglesMoreThanOnce) {
  const auto tris = long_thin_triangles(2000, 5);
  const Bvh bvh = build_bvh(tris, kMicro21);
  ASSERT_EQ(check_bvh(bvh, tris.size()), "");
  EXPECT_GT(bvh.stats.references, tris.size() + tris.size() / 10)
      << "spatial splits should reference many of these triangles more than once";
  EXPECT_LE(bvh.stats.references, 2 * tris.size());  // the primitive array's capacity
  // And they pay: a lower SAH cost than our build, which references each triangle once.
  const Bvh sah = build_bvh(tris);
  EXPECT_EQ(sah.stats.references, tris.size());
  EXPECT_LT(bvh.stats.sah_cost, sah.stats.sah_cost);
}

// The same BVH every time: again, from another thread, and while a device with Embree's default
// (every thread) is alive, whose thread count would otherwise apply to the build.
TEST(Micro21Bvh, Deterministic) {
  std::vector<std::vector<Triangle>> sets{long_thin_triangles(20000, 7)};
  const std::string bunny = test::shared_scene("bunny.glb");
  sets.push_back(load_scene(bunny.empty() ? test::own_scenes().front() : bunny).triangles);
  for (const auto& tris : sets) {
    const Bvh a = build_bvh(tris, kMicro21);
    ASSERT_EQ(check_bvh(a, tris.size()), "");
    expect_identical(a, build_bvh(tris, kMicro21), "built again");
    Bvh c;
    std::thread([&] { c = build_bvh(tris, kMicro21); }).join();
    expect_identical(a, c, "built on another thread");
    const EmbreeScene other(tris, "", true);
    expect_identical(a, build_bvh(tris, kMicro21), "built beside a multi-threaded device");
  }
}

// Embree asks applications to set flush-to-zero and denormals-are-zero; the build must not set
// them (or any other mode of MXCSR: rounding, exception masks) for the traversal that follows,
// which keeps IEEE denormals. Its exception flags (bits 0-5) are sticky status, not modes.
TEST(Micro21Bvh, BuildLeavesTheFloatingPointModesAlone) {
  constexpr unsigned kModes = ~0x3Fu;
  const unsigned before = _mm_getcsr() & kModes;
  build_bvh(long_thin_triangles(3000, 9), kMicro21);
  EXPECT_EQ(_mm_getcsr() & kModes, before) << "the traversal relies on IEEE denormals";
}

// Their SplitTriangle on a triangle whose parts are known: the plane x = 1 through the triangle
// (0,0,0), (4,0,0), (0,4,0) crosses its edges at (1,0,0) and (1,3,0).
TEST(Micro21Bvh, SplitCallbackClipsTheTriangle) {
  const Triangle t{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}};
  Aabb l, r;
  micro21_split_triangle(t, t.bounds(), 0, 1.f, &l, &r);
  EXPECT_EQ(l.lo, Vec3(0, 0, 0));
  EXPECT_EQ(l.hi, Vec3(1, 4, 0));
  EXPECT_EQ(r.lo, Vec3(1, 0, 0));
  EXPECT_EQ(r.hi, Vec3(4, 3, 0));
  // Intersected with the reference's current bounds (an earlier split left y <= 2).
  const Aabb cur{{0, 0, 0}, {4, 2, 0}};
  micro21_split_triangle(t, cur, 0, 1.f, &l, &r);
  EXPECT_EQ(l.hi, Vec3(1, 2, 0));
  EXPECT_EQ(r.lo, Vec3(1, 0, 0));
  EXPECT_EQ(r.hi, Vec3(4, 2, 0));
  // A plane beyond the triangle leaves that side empty (Embree then does not split).
  micro21_split_triangle(t, t.bounds(), 1, 5.f, &l, &r);
  EXPECT_EQ(l.lo, t.bounds().lo);
  EXPECT_EQ(l.hi, t.bounds().hi);
  EXPECT_TRUE(r.empty());
  // A vertex on the plane goes to both sides; no edge crosses it there.
  micro21_split_triangle(t, t.bounds(), 0, 0.f, &l, &r);
  EXPECT_EQ(l.lo, Vec3(0, 0, 0));
  EXPECT_EQ(l.hi, Vec3(0, 4, 0));
  EXPECT_EQ(r.lo, Vec3(0, 0, 0));
  EXPECT_EQ(r.hi, Vec3(4, 4, 0));
}

TEST(Micro21Bvh, CheckerDetectsBrokenTrees) {
  const auto tris = long_thin_triangles(1000, 11);
  const Bvh good = build_bvh(tris, kMicro21);
  ASSERT_EQ(check_bvh(good, tris.size()), "");
  ASSERT_GT(good.stats.references, tris.size());
  // A leaf box shrunk around its centre no longer covers its triangles' parts.
  Bvh b1 = good;
  for (auto& n : b1.nodes)
    if (n.is_leaf()) {
      const Vec3 c = n.box().center();
      n.lo = c + 0.7f * (n.lo - c);
      n.hi = c + 0.7f * (n.hi - c);
      break;
    }
  EXPECT_NE(check_bvh(b1, tris.size()), "");
  // A triangle referenced by no leaf: its references renamed.
  Bvh b2 = good;
  for (uint32_t& p : b2.prim_ids)
    if (p == 17) p = 18;
  EXPECT_NE(check_bvh(b2, tris.size()), "");
  // References of one triangle that differ: a copy of a triangle referenced twice, moved.
  Bvh b3 = good;
  std::vector<int> refs(tris.size(), 0);
  for (uint32_t p : b3.prim_ids) refs[p]++;
  size_t moved = b3.tris.size();
  for (size_t t = 0; t < b3.tris.size() && moved == b3.tris.size(); ++t)
    if (refs[b3.prim_ids[t]] > 1) moved = t;
  ASSERT_LT(moved, b3.tris.size());
  b3.tris[moved].v0.x += 1e-3f;
  b3.tri_degenerate[moved] = b3.tris[moved].degenerate();
  EXPECT_NE(check_bvh(b3, tris.size()), "");
  // Several references are allowed only to a spatial-split build.
  Bvh b4 = good;
  b4.options.builder = BvhBuilder::kSah;
  EXPECT_NE(check_bvh(b4, tris.size()), "");
}

// A triangle referenced by several leaves is tested in each of them, and its hit may lie outside
// the leaf it was found in: closest and any hit still agree with testing every triangle.
TEST(Micro21Bvh, TraversalAgreesWithBruteForce) {
  for (uint64_t seed : {1u, 2u}) {
    const auto tris = seed == 1 ? long_thin_triangles(3000, 13) : test::random_soup(3000, 0.08f, 2);
    const Bvh bvh = build_bvh(tris, kMicro21);
    ASSERT_EQ(check_bvh(bvh, tris.size()), "");
    int hits = 0;
    for (uint64_t i = 0; i < 4000; ++i) {
      const Ray r = test::random_ray(seed * 1000, i);
      Counters c;
      const Hit a = closest_hit(bvh, r, &c);
      const Hit b = brute_force_closest(bvh, r);
      ASSERT_EQ(a.hit(), b.hit()) << "seed " << seed << " ray " << i;
      const Hit any = any_hit(bvh, r, &c);
      ASSERT_EQ(any.hit(), b.hit()) << "seed " << seed << " ray " << i;
      if (!a.hit()) continue;
      ++hits;
      EXPECT_EQ(a.t, b.t) << "ray " << i;
      if (a.prim != b.prim) {  // only acceptable as an exact tie
        float t, u, v;
        EXPECT_TRUE(intersect_triangle(RayPre(r), tris[a.prim], r.tnear, kInf, &t, &u, &v) &&
                    t == b.t);
      }
      EXPECT_TRUE(bvh.nodes[a.leaf].is_leaf());
      EXPECT_GE(any.t, r.tnear);
      EXPECT_LE(any.t, r.tfar);
    }
    EXPECT_GT(hits, 300) << "too few hits for the test to mean anything";
  }
}

/// Random rays through a scene's bounds: origins in the box grown by half its diagonal, aimed at
/// a random point inside it; kind primary (closest hit) or shadow (any hit, ending at the point).
std::vector<std::pair<Ray, RayKind>> random_scene_rays(const Scene& s, size_t n, uint64_t seed) {
  std::vector<std::pair<Ray, RayKind>> out;
  const Vec3 lo = s.bounds.lo, ext = s.bounds.hi - s.bounds.lo;
  const float d = s.bounds.diagonal();
  for (size_t i = 0; i < n; ++i) {
    auto u = [&](uint64_t k) { return uniform01(seed, i, k); };
    const Vec3 org = lo - 0.5f * Vec3(d) + Vec3(u(0), u(1), u(2)) * (ext + Vec3(d));
    const Vec3 to = lo + Vec3(u(3), u(4), u(5)) * ext;
    Ray r;
    r.org = org;
    r.dir = glm::normalize(to - org);
    const bool any = i % 2;
    if (any) r.tfar = glm::length(to - org);
    out.push_back({r, any ? RayKind::kShadow : RayKind::kPrimary});
  }
  return out;
}

// Our walks over MICRO 2021's BVH against Embree's own BVH and intersection (the cross-check's
// referee): random rays closest-hit and any-hit, and the camera workload's rays.
TEST(Micro21Bvh, AgreesWithEmbree) {
  std::vector<std::string> scenes = test::own_scenes();
  const std::string bunny = test::shared_scene("bunny.glb");
  if (!bunny.empty()) scenes.push_back(bunny);
  for (const std::string& path : scenes) {
    SCOPED_TRACE(path);
    const Scene s = load_scene(path);
    const Bvh bvh = build_bvh(s.triangles, kMicro21);
    ASSERT_EQ(check_bvh(bvh, s.triangles.size()), "");
    const EmbreeScene emb(s.triangles, kEmbreeReferenceConfig, true);
    const CrossCheckResult r = cross_check_rays(s, bvh, emb, random_scene_rays(s, 4000, 17));
    EXPECT_TRUE(r.passed()) << r.failure() << "\n" << r.to_json().dump(2);
    EXPECT_EQ(r.total.compared, 4000u);
    EXPECT_GT(r.by_kind[int(RayKind::kPrimary)].hits, 200u);
    EXPECT_GT(r.by_kind[int(RayKind::kShadow)].hits, 200u);
    CrossCheckOptions opt;
    opt.rays = 20000;
    const CrossCheckResult w = cross_check(s, bvh, opt);
    EXPECT_TRUE(w.passed()) << w.failure() << "\n" << w.to_json().dump(2);
    EXPECT_GT(w.total.hits, 0u);
  }
  if (bunny.empty()) GTEST_SKIP() << "../shared/scenes absent: own scenes only";
}

}  // namespace
}  // namespace hrpp
