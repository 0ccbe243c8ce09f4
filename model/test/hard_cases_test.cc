// The traversal hard cases T1-T18 of ../shared/HARD_CASES.md (and the project's own T19), each
// checked on our BVH and, where the ray is valid, on Embree (robust mode, the pinned reference
// configuration).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <map>

#include "hrpp/reference/crosscheck.h"
#include "hrpp/reference/embree_ref.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/trace/traverse.h"
#include "hrpp/util/rng.h"
#include "hrpp/workload/workload.h"
#include "test_util.h"

namespace hrpp {
namespace {

// Quad Q: two triangles in the plane z = 1 covering [-1, 1]^2.
std::vector<Triangle> quad() {
  return {{{1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}, {{1, -1, 1}, {-1, -1, 1}, {-1, 1, 1}}};
}

// The unit cube [0, 1]^3 as 12 triangles, wound outwards.
std::vector<Triangle> unit_cube() {
  const Vec3 p[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                     {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int f[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                       {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  std::vector<Triangle> out;
  for (const auto& q : f) {
    out.push_back({p[q[0]], p[q[1]], p[q[2]]});
    out.push_back({p[q[0]], p[q[2]], p[q[3]]});
  }
  return out;
}

struct Both {
  Hit ours, embree;
};

class Tracer {
 public:
  explicit Tracer(std::vector<Triangle> tris)
      : tris_(tris), bvh_(build_bvh(tris)), emb_(tris, kEmbreeReferenceConfig, true) {}
  Both trace(const Ray& r) const {
    EXPECT_EQ(validate_ray(r), RayError::kNone);
    Counters c;
    Both b{closest_hit(bvh_, r, &c), emb_.intersect(r)};
    Hit any = any_hit(bvh_, r, &c);
    EXPECT_EQ(any.hit(), b.ours.hit()) << "any-hit and closest-hit disagree";
    EXPECT_EQ(emb_.occluded(r), b.embree.hit()) << "Embree occluded and intersect disagree";
    if (b.ours.hit()) {
      EXPECT_TRUE(std::isfinite(b.ours.t));
    }
    return b;
  }
  const Bvh& bvh() const { return bvh_; }
  const EmbreeScene& embree() const { return emb_; }
  const std::vector<Triangle>& tris() const { return tris_; }

 private:
  std::vector<Triangle> tris_;
  Bvh bvh_;
  EmbreeScene emb_;
};

Ray make_ray(Vec3 o, Vec3 d, float tnear = 0.f, float tfar = kInf) { return {o, d, tnear, tfar}; }

void expect_hit_near(const Hit& h, float t, const char* who) {
  ASSERT_TRUE(h.hit()) << who << " missed";
  EXPECT_NEAR(h.t, t, 16 * std::numeric_limits<float>::epsilon() * t) << who;
}

TEST(HardCases, T01_QuadFromOriginAlongZ) {
  Tracer tr(quad());
  Both b = tr.trace(make_ray({0, 0, 0}, {0, 0, 1}));
  expect_hit_near(b.ours, 1.f, "ours");
  expect_hit_near(b.embree, 1.f, "embree");
}

TEST(HardCases, T02_NegativeZeroDirectionComponents) {
  Tracer tr(quad());
  Both b = tr.trace(make_ray({0, 0, 0}, {-0.f, -0.f, 1}));
  expect_hit_near(b.ours, 1.f, "ours");
  expect_hit_near(b.embree, 1.f, "embree");
  Counters c1, c2;
  Hit h1 = closest_hit(tr.bvh(), make_ray({0, 0, 0}, {0, 0, 1}), &c1);
  Hit h2 = closest_hit(tr.bvh(), make_ray({0, 0, 0}, {-0.f, -0.f, 1}), &c2);
  EXPECT_EQ(h1.t, h2.t);
  EXPECT_EQ(c1, c2);
}

TEST(HardCases, T03_BelowAVertex) {
  Tracer tr(quad());
  Both b = tr.trace(make_ray({1, 1, 0}, {0, 0, 1}));
  expect_hit_near(b.ours, 1.f, "ours");
  expect_hit_near(b.embree, 1.f, "embree");
}

TEST(HardCases, T04_JustOutsideAnEdgeEitherAnswer) {
  Tracer tr(quad());
  Both b = tr.trace(make_ray({std::nextafter(1.f, 2.f), 0, 0}, {0, 0, 1}));
  // Documented: either answer is correct; a hit must be at t ~ 1.
  if (b.ours.hit()) {
    expect_hit_near(b.ours, 1.f, "ours");
  }
  if (b.embree.hit()) {
    expect_hit_near(b.embree, 1.f, "embree");
  }
  // Ours misses: the origin is strictly outside the quad and the test is exact there.
  EXPECT_FALSE(b.ours.hit());
}

TEST(HardCases, T05_OriginOnTheSurface) {
  Tracer tr(quad());
  Both b = tr.trace(make_ray({0.25f, 0.5f, 1}, {0, 0, 1}));
  // Documented behaviour (docs/bvh.md): with tnear = 0 a ray starting on a surface hits it at
  // t = 0. Secondary rays avoid this with offset origins (T18).
  ASSERT_TRUE(b.ours.hit());
  EXPECT_EQ(b.ours.t, 0.f);
}

TEST(HardCases, T06_CoplanarRayMisses) {
  Tracer tr(quad());
  Both b = tr.trace(make_ray({-2, 0.5f, 1}, {1, 0, 0}));
  EXPECT_FALSE(b.ours.hit());
  EXPECT_FALSE(b.embree.hit());
}

TEST(HardCases, T07_BackFaceIsHit) {
  Tracer tr(quad());
  Both b = tr.trace(make_ray({0.25f, 0.5f, 2}, {0, 0, -1}));
  expect_hit_near(b.ours, 1.f, "ours");
  expect_hit_near(b.embree, 1.f, "embree");
}

TEST(HardCases, T08_HitExactlyAtTfar) {
  Tracer tr(quad());
  Both b = tr.trace(make_ray({0.25f, 0.5f, 0}, {0, 0, 1}, 0.f, 1.f));
  expect_hit_near(b.ours, 1.f, "ours");
  expect_hit_near(b.embree, 1.f, "embree");
  Both b2 = tr.trace(make_ray({0.25f, 0.5f, 0}, {0, 0, 1}, 0.f, std::nextafter(1.f, 0.f)));
  if (b2.ours.hit()) {  // either answer
    EXPECT_LE(b2.ours.t, std::nextafter(1.f, 0.f));
  }
}

TEST(HardCases, T09_TnearAboveTfarIsRejected) {
  const Ray r = make_ray({0.25f, 0.5f, 0}, {0, 0, 1}, 2.f, 1.f);
  const Ray copy = r;
  EXPECT_EQ(validate_ray(r), RayError::kTnearAboveTfar);
  Scene s = test::scene_from_triangles(quad());
  Tracer tr(quad());
  CrossCheckResult res = cross_check_rays(s, tr.bvh(), tr.embree(), {{r, RayKind::kPrimary}});
  EXPECT_EQ(res.total.invalid_rays, 1u);
  EXPECT_EQ(res.total.compared, 0u);
  EXPECT_FALSE(res.passed()) << "a cross-check that compared nothing must not pass";
  EXPECT_EQ(std::memcmp(&r, &copy, sizeof r), 0) << "ray changed";
}

TEST(HardCases, T10_DenormalDirectionMissesWithoutNaN) {
  Tracer tr(quad());
  Both b = tr.trace(make_ray({0, 0, 0}, {0, 0, 1e-40f}));
  EXPECT_FALSE(b.ours.hit());
  EXPECT_FALSE(b.embree.hit()) << "robust Embree misses (its fast mode returns t = NaN)";
}

TEST(HardCases, T11_NonFiniteAndNegativeTnearRaysNeverReachEmbree) {
  const float nan = std::nanf(""), inf = kInf;
  std::vector<std::pair<Ray, RayError>> bad = {
      {make_ray({nan, 0, 0}, {0, 0, 1}), RayError::kNotFinite},
      {make_ray({0, inf, 0}, {0, 0, 1}), RayError::kNotFinite},
      {make_ray({0, 0, 0}, {0, nan, 1}), RayError::kNotFinite},
      {make_ray({0, 0, 0}, {-inf, 0, 1}), RayError::kNotFinite},
      {make_ray({0, 0, 0}, {0, 0, 1}, nan), RayError::kNotFinite},
      {make_ray({0, 0, 0}, {0, 0, 1}, 0.f, nan), RayError::kNotFinite},
      {make_ray({0, 0, 0}, {0, 0, 1}, inf), RayError::kNotFinite},
      {make_ray({0, 0, 0}, {0, 0, 1}, -1.f), RayError::kNegativeTnear},
      {make_ray({0, 0, 0}, {0, 0, 0}), RayError::kZeroDirection},
      {make_ray({0, 0, 0}, {-0.f, 0, -0.f}), RayError::kZeroDirection},
      {make_ray({0, 0, 0}, {0, 0, 1e19f}), RayError::kDirectionTooLarge},
  };
  Scene s = test::scene_from_triangles(quad());
  Tracer tr(quad());
  std::vector<std::pair<Ray, RayKind>> rays;
  for (const auto& [r, e] : bad) {
    EXPECT_EQ(validate_ray(r), e) << ray_error_name(e);
    rays.push_back({r, RayKind::kPrimary});
    rays.push_back({r, RayKind::kShadow});
  }
  // Embree would abort the process on any of these: reaching the end proves none was sent.
  CrossCheckResult res = cross_check_rays(s, tr.bvh(), tr.embree(), rays);
  EXPECT_EQ(res.total.invalid_rays, rays.size());
  EXPECT_EQ(res.total.compared, 0u);
  EXPECT_FALSE(res.passed());
  EXPECT_NE(res.failure().find("no ray compared"), std::string::npos) << res.failure();
  // tfar = +inf is valid.
  EXPECT_EQ(validate_ray(make_ray({0, 0, 0}, {0, 0, 1}, 0.f, inf)), RayError::kNone);
}

TEST(HardCases, T12_OriginOnABoxFacePlane) {
  Tracer tr(quad());
  for (float zero : {0.f, -0.f}) {
    Both b = tr.trace(make_ray({-1, 0.5f, 0}, {zero, 0, 1}));
    expect_hit_near(b.ours, 1.f, "ours");
    expect_hit_near(b.embree, 1.f, "embree");
  }
  // The same on the unit cube with the zero direction component on every axis in turn (the
  // NaN slab is then the first, second or last one tested): the ray runs in a face plane.
  Tracer cube(unit_cube());
  for (int a = 0; a < 3; ++a)      // axis the ray travels along
    for (int z = 0; z < 3; ++z) {  // axis whose face plane holds the ray
      if (z == a) continue;
      for (float plane : {0.f, 1.f}) {
        Vec3 o(0.5f), d(0.f);
        o[a] = -1.f;
        o[z] = plane;
        d[a] = 1.f;
        Both b = cube.trace(make_ray(o, d));
        expect_hit_near(b.ours, 1.f, "ours");
      }
    }
}

TEST(HardCases, T13_CubeFromCentreAlongEachAxis) {
  Tracer tr(unit_cube());
  for (int a = 0; a < 3; ++a)
    for (float s : {1.f, -1.f}) {
      Vec3 d(0);
      d[a] = s;
      Both b = tr.trace(make_ray({0.5f, 0.5f, 0.5f}, d));
      expect_hit_near(b.ours, 0.5f, "ours");
      expect_hit_near(b.embree, 0.5f, "embree");
    }
}

TEST(HardCases, T14_GrazingTheTopFace) {
  Tracer tr(unit_cube());
  Both b = tr.trace(make_ray({-1, 1, 0.5f}, {1, 0, 0}));
  expect_hit_near(b.ours, 1.f, "ours");
  expect_hit_near(b.embree, 1.f, "embree");
}

TEST(HardCases, T15_ThroughACubeVertex) {
  Tracer tr(unit_cube());
  Both b = tr.trace(make_ray({-1, -1, -1}, glm::normalize(Vec3(1, 1, 1))));
  ASSERT_TRUE(b.ours.hit());
  ASSERT_TRUE(b.embree.hit());
  EXPECT_NEAR(b.ours.t, std::sqrt(3.f), 1e-5f);
}

TEST(HardCases, T16_DegenerateTrianglesAreNeverHit) {
  std::vector<Triangle> tris = {
      {{0, 0, 1}, {1, 1, 1}, {2, 2, 1}},     // collinear
      {{-1, 0, 1}, {-1, 0, 1}, {-2, 1, 1}},  // repeated vertex
      {{3, 3, 1}, {3, 3, 1}, {3, 3, 1}},     // a point
  };
  Tracer tr(tris);
  EXPECT_EQ(test::scene_from_triangles(tris).degenerate_triangles, 3u);
  const Vec3 targets[] = {{0.5f, 0.5f, 1},  {1, 1, 1}, {0, 0, 1}, {-1, 0, 1},
                          {-1.5f, 0.5f, 1}, {3, 3, 1}, {2, 2, 1}};
  for (const Vec3& t : targets)
    for (const Vec3& o : {Vec3(t.x, t.y, 0), Vec3(t.x + 0.3f, t.y - 0.2f, -1)}) {
      Both b = tr.trace(make_ray(o, glm::normalize(t - o)));
      EXPECT_FALSE(b.ours.hit());
      // Coplanar rays along the collinear triangle's line.
      Both c = tr.trace(make_ray({-1, -1, 1}, glm::normalize(Vec3(1, 1, 0))));
      EXPECT_FALSE(c.ours.hit());
    }
}

// An icosphere: a closed, watertight mesh (shared vertices bit-identical).
std::vector<Triangle> icosphere(int subdiv, Vec3 centre, float radius) {
  const float t = (1.f + std::sqrt(5.f)) / 2.f;
  std::vector<Vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& p : v) p = glm::normalize(p);
  for (int s = 0; s < subdiv; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return mid[key] = static_cast<int>(v.size() - 1);
    };
    std::vector<std::array<int, 3>> nf;
    for (auto [a, b, c] : f) {
      int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      nf.push_back({a, ab, ca});
      nf.push_back({b, bc, ab});
      nf.push_back({c, ca, bc});
      nf.push_back({ab, bc, ca});
    }
    f = nf;
  }
  std::vector<Triangle> out;
  for (auto [a, b, c] : f)
    out.push_back({centre + radius * v[a], centre + radius * v[b], centre + radius * v[c]});
  return out;
}

TEST(HardCases, T17_RaysAtSharedEdgesAndVerticesNeverFallThrough) {
  for (const Vec3& centre : {Vec3(0.f), Vec3(1000.f, -2000.f, 3000.f)}) {
    auto tris = icosphere(3, centre, 1.f);
    Tracer tr(tris);
    uint64_t rays = 0, ours_miss = 0, embree_miss = 0;
    // From several interior points towards every vertex and every edge midpoint.
    for (const Vec3& o : {centre, centre + Vec3(0.1f, -0.2f, 0.3f), centre + Vec3(-0.5f, 0.1f, 0)})
      for (const Triangle& t : tris)
        for (const Vec3& target : {t.v0, 0.5f * (t.v0 + t.v1), 0.5f * (t.v1 + t.v2)}) {
          Ray r = make_ray(o, glm::normalize(target - o));
          Counters c;
          ++rays;
          ours_miss += !closest_hit(tr.bvh(), r, &c).hit();
          embree_miss += !tr.embree().intersect(r).hit();
        }
    EXPECT_EQ(ours_miss, 0u) << "of " << rays << " rays, centre " << centre.x;
    EXPECT_EQ(embree_miss, 0u) << "Embree robust mode, of " << rays << " rays";
  }
}

// Shoots secondary rays from the primary hits; returns how many re-hit their own triangle.
uint64_t self_hits(const std::vector<Triangle>& tris, bool offset, uint64_t* spawned) {
  Scene s = test::scene_from_triangles(tris);
  Bvh bvh = build_bvh(s.triangles);
  uint64_t self = 0;
  *spawned = 0;
  const int n = 200;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      Ray r = camera_ray(s.camera, n, n, x, y, 0, 1, 3);
      Counters c;
      Hit h = closest_hit(bvh, r, &c);
      if (!h.hit()) continue;
      const Triangle& t = s.triangles[h.prim];
      Vec3 p = t.v0 + h.u * (t.v1 - t.v0) + h.v * (t.v2 - t.v0);
      Vec3 nrm = glm::normalize(t.normal());
      if (glm::dot(nrm, r.dir) > 0) nrm = -nrm;
      // A direction in the hemisphere the camera ray came from.
      Vec3 d = glm::normalize(nrm + 0.9f * Vec3(uniform01(1, x, y, 0) - 0.5f,
                                                uniform01(1, x, y, 1) - 0.5f,
                                                uniform01(1, x, y, 2) - 0.5f));
      Ray sr = make_ray(offset ? offset_ray_origin(p, nrm) : p, d);
      Hit sh = closest_hit(bvh, sr, &c);
      ++*spawned;
      self += sh.hit() && sh.prim == h.prim;
    }
  return self;
}

TEST(HardCases, T18_OffsetOriginsGiveNoSelfHits) {
  // A scene far from the origin, where self-intersection is common without the offset.
  auto tris = test::random_soup(3000, 0.1f, 42);
  for (auto& t : tris)
    for (Vec3* v : {&t.v0, &t.v1, &t.v2}) *v = 1000.f * *v + Vec3(5e4f, -3e4f, 2e4f);
  uint64_t spawned = 0;
  EXPECT_EQ(self_hits(tris, true, &spawned), 0u);
  EXPECT_GT(spawned, 10000u);
  // The check can fail: without the offset, rays do re-hit their own triangle.
  EXPECT_GT(self_hits(tris, false, &spawned), spawned / 20);
}

// T19 (the project's own, beyond HARD_CASES.md's list; docs/bvh.md, "Culling against the current
// hit"): a triangle P1 in the face plane z = 1 of its leaf's box, and a tilted triangle P2 whose
// leaf is entered first. Float rounding puts P1's t one ulp below its box's computed entry
// distance, and P2's t at that entry: a walk that culls P1's box against P2's hit unwidened
// returns P2, one ulp behind P1. Found by a search over random rays (constants in hex).
TEST(HardCases, T19_TriangleInABoxFacePlane) {
  const Triangle p1{{-4, -4, 1}, {4, -4, 1}, {0, 4, 1}};
  const Triangle p2{{-0x1.167b7p+1f, -0x1.732764p+0f, 0x1.fae144p-1f},
                    {0x1.d3092p+0f, -0x1.732764p+0f, 0x1.fae144p-1f},
                    {-0x1.67b706p-3f, 0x1.466c4ep+1f, 0x1.028f5ap+0f}};
  const Ray ray = make_ray({-0x1.6bd93p-5f, 0x1.c9a82p-3f, -0x1.1d144p-3f},
                           {-0x1.c2ca04p-4f, 0x1.1894eep-2f, 0x1.e92b84p-1f});
  // The case is what it claims: t(P1) < t(P2) = P1's box entry, and P2's box is entered first.
  const RayPre pre(ray);
  float t1, t2, e1, e2, u, v;
  ASSERT_TRUE(intersect_triangle(pre, p1, 0.f, kInf, &t1, &u, &v));
  ASSERT_TRUE(intersect_triangle(pre, p2, 0.f, kInf, &t2, &u, &v));
  ASSERT_TRUE(intersect_box(pre, p1.bounds().lo, p1.bounds().hi, 0.f, kInf, &e1));
  ASSERT_TRUE(intersect_box(pre, p2.bounds().lo, p2.bounds().hi, 0.f, kInf, &e2));
  ASSERT_EQ(t1, 0x1.313ee8p+0f);
  ASSERT_EQ(t2, 0x1.313eeap+0f);
  ASSERT_EQ(e1, t2);
  ASSERT_LT(e2, e1);
  // One triangle per leaf, so the root's two children are the two leaves.
  const Bvh bvh = build_bvh({p1, p2}, {.max_leaf_size = 1});
  ASSERT_EQ(bvh.nodes.size(), 3u);
  Bvh nodes_only = bvh;  // the node layout's walk (pairs cleared) must agree
  nodes_only.pairs.clear();
  nodes_only.pair_of.clear();
  for (const Bvh* b : std::array<const Bvh*, 2>{&bvh, &nodes_only}) {
    Counters c;
    const Hit h = closest_hit(*b, ray, &c);
    ASSERT_TRUE(h.hit());
    EXPECT_EQ(h.prim, 0u) << "the walk culled P1's box against P2's hit";
    EXPECT_EQ(h.t, t1);
    EXPECT_EQ(c.leaf_visits, 2u);
    // The predictor's bounded walk (closest_hit_pair) with the bound at P2's t.
    Hit base, bounded;
    Counters cb, cv;
    closest_hit_pair(*b, ray, t2, &base, &cb, &bounded, &cv);
    EXPECT_EQ(base.prim, 0u);
    EXPECT_EQ(bounded.prim, 0u);
  }
  // Embree (robust mode, its own rounding) reports P2 here, at P1's t within the float tolerance:
  // for the referee the two are a tie, which is why the Embree cross-check cannot see this case.
  const EmbreeScene emb({p1, p2}, kEmbreeReferenceConfig, true);
  expect_hit_near(emb.intersect(ray), t1, "Embree");
}

// T19 generalised: rays from random origins below the face plane z = 1, and for each ray whose
// float t on P1 falls below P1's box entry, a tilted P2 through the ray between the two whose
// float t lands in that gap. Every such pair is a case where an unwidened cull misses P1; the
// walk must return brute force's hit on every one.
TEST(HardCases, T19_FacePlaneCasesFromRandomRays) {
  const Triangle p1{{-4, -4, 1}, {4, -4, 1}, {0, 4, 1}};
  int cases = 0;
  for (uint64_t i = 0; i < 20000 && cases < 200; ++i) {
    auto u = [&](uint64_t k) { return 2 * uniform01(19, i, k) - 1; };
    const Ray ray = make_ray({0.5f * u(0), 0.5f * u(1), -1.f + 0.9f * u(2)},
                             glm::normalize(Vec3(0.3f * u(3), 0.3f * u(4), 1.f)));
    const RayPre pre(ray);
    float t1, e1, t2, bu, bv;
    if (!intersect_triangle(pre, p1, 0.f, kInf, &t1, &bu, &bv)) continue;
    intersect_box(pre, p1.bounds().lo, p1.bounds().hi, 0.f, kInf, &e1);
    if (!(t1 < e1)) continue;
    for (int k = 0; k < 200; ++k) {
      const Vec3 q = ray.org + (t1 + (e1 - t1) * float(k % 10) / 9.f) * ray.dir;
      const float s = 0.01f * float(1 + k / 10);
      const Triangle p2{q + Vec3(-2, -2, -s), q + Vec3(2, -2, -s), q + Vec3(0, 2, s)};
      if (!intersect_triangle(pre, p2, 0.f, kInf, &t2, &bu, &bv) || !(t1 < t2 && t2 <= e1))
        continue;
      const Bvh bvh = build_bvh({p1, p2}, {.max_leaf_size = 1});
      Counters c;
      const Hit h = closest_hit(bvh, ray, &c);
      const Hit bf = brute_force_closest(bvh, ray);
      ASSERT_EQ(bf.prim, 0u);
      EXPECT_EQ(h.prim, bf.prim) << "ray " << i;
      EXPECT_EQ(h.t, bf.t) << "ray " << i;
      ++cases;
      break;
    }
  }
  EXPECT_EQ(cases, 200) << "too few constructed cases for the test to mean anything";
}

// ---- The valid range (docs/bvh.md, "Valid range") ------------------------------------------

// A square of half-size h centred at c in the plane z = c.z, as two triangles.
std::vector<Triangle> square(Vec3 c, float h) {
  const Vec3 a = c + Vec3(-h, -h, 0), b = c + Vec3(h, -h, 0), d = c + Vec3(h, h, 0),
             e = c + Vec3(-h, h, 0);
  return {{a, b, d}, {a, d, e}};
}

// Traces rays from `o` at points inside the triangles (several barycentric positions); returns
// how many of them our traversal misses although the double-precision referee hits.
int silent_misses(const std::vector<Triangle>& tris, Vec3 o, int* traced) {
  Bvh bvh = build_bvh(tris);
  int misses = 0;
  *traced = 0;
  for (const Triangle& t : tris)
    for (const Vec3 b : {Vec3(1, 1, 1) / 3.f, Vec3(0.6f, 0.3f, 0.1f), Vec3(0.1f, 0.2f, 0.7f)}) {
      const DVec3 target =
          double(b.x) * DVec3(t.v0) + double(b.y) * DVec3(t.v1) + double(b.z) * DVec3(t.v2);
      const Ray r = make_ray(o, Vec3(glm::normalize(target - DVec3(o))));
      if (validate_ray(r) != RayError::kNone || !referee_intersect(r, t).hit) continue;
      ++*traced;
      Counters c;
      const Hit h = closest_hit(bvh, r, &c);
      misses += !h.hit() || !std::isfinite(h.t);
    }
  return misses;
}

TEST(ValidRange, LargeTrianglesInsideTheRangeAreHit) {
  // The extremes the loader accepts: vertices at +-kMaxSceneCoordinate, ray origins at up to
  // kMaxRayOrigin on every side (slanted directions: the dominant component near 1/sqrt(3)).
  const float g = kMaxSceneCoordinate, o = kMaxRayOrigin;
  int total = 0;
  for (float h : {g, g / 2, 1e6f, 1.f})
    for (float z : {-g, 0.f, g}) {
      auto tris = square(Vec3(g - h, h - g, z), h);
      for (const Vec3& org :
           {Vec3(0, 0, o), Vec3(o, o, o), Vec3(-o, o, -o), Vec3(o, -o, 0), Vec3(g, -g, z + 1e3f)}) {
        int traced;
        EXPECT_EQ(silent_misses(tris, org, &traced), 0)
            << "half-size " << h << " at z " << z << " from " << org.x << "," << org.y << ","
            << org.z;
        total += traced;
      }
    }
  EXPECT_GT(total, 200);
}

TEST(ValidRange, JustOutsideTheRangeTheFloatTestOverflows) {
  // Geometry just outside the valid range (why the loader rejects it): T = t * det overflows float,
  // t is NaN and every hit is lost. If a fallback ever traces them, this test tells that the range
  // may grow.
  struct Case {
    float h, dist;
  };
  for (const Case& k : {Case{1e12f, 1e14f}, Case{1e13f, 1e12f}, Case{1e17f, 1e6f}}) {
    int traced;
    EXPECT_EQ(silent_misses(square(Vec3(0, 0, k.dist), k.h), Vec3(0), &traced), traced)
        << "half-size " << k.h << " at distance " << k.dist;
    EXPECT_GT(traced, 0);
    EXPECT_GT(k.h + k.dist, kMaxSceneCoordinate);
  }
}

TEST(ValidRange, TrianglesBelowTheSmallestAreaAreNeverHit) {
  // Twice the area 1e-40: 1/det overflows and the float test never reports the hit the referee
  // sees; at kMinTwiceArea (2^-100) it does, also at an incidence of about 2^-20 from grazing.
  const float tiny = 1e-20f, limit = 0x1p-50f;
  int traced;
  EXPECT_EQ(silent_misses({{{0, 0, 0}, {tiny, 0, 0}, {0, tiny, 0}}}, Vec3(0, 0, 1), &traced),
            traced);
  EXPECT_GT(traced, 0);
  const Triangle at_limit{{0, 0, 0}, {limit, 0, 0}, {0, limit, 0}};
  EXPECT_DOUBLE_EQ(glm::length(glm::cross(DVec3(at_limit.v1), DVec3(at_limit.v2))), kMinTwiceArea);
  // (The last origin sits 2^-20 of its distance above the plane: a grazing ray at the scale of
  // the triangle, whose coordinates the subtraction v - o keeps exactly.)
  for (const Vec3& o : {Vec3(0, 0, 1), Vec3(0, 0, 1e-10f), Vec3(4 * limit, 4 * limit, 0x1p-68f)}) {
    EXPECT_EQ(silent_misses({at_limit}, o, &traced), 0) << o.z;
    EXPECT_GT(traced, 0);
  }
}

TEST(ValidRange, SpawnOffsetDistance) {
  // docs/bvh.md: the offset along axis a is floor(256 |n_a|) ulps of p_a, ulp(x) =
  // 2^(floor(log2 |x|) - 23): between 2^-16 and 2^-15 of |p_a| |n_a| (|p_a| >= 1/32), else
  // n_a / 65536. At x = 148,376 (ulp 2^-6) that is 4 world units.
  EXPECT_EQ(offset_ray_origin({148376.f, 0, 0}, {1, 0, 0}).x, 148380.f);
  EXPECT_EQ(offset_ray_origin({-148376.f, 0, 0}, {-1, 0, 0}).x, -148380.f);
  EXPECT_EQ(offset_ray_origin({0.01f, 0, 0}, {1, 0, 0}).x, 0.01f + 1.f / 65536);
  auto u = [](int i, int k) { return uniform01(7, i, k); };
  for (int i = 0; i < 100000; ++i) {
    Vec3 p, n;
    for (int a = 0; a < 3; ++a) {
      p[a] = std::ldexp(u(i, a) - 0.5f, int(u(i, 3 + a) * 80) - 20);
      n[a] = u(i, 6 + a) - 0.5f;
    }
    n = glm::normalize(n);
    const Vec3 q = offset_ray_origin(p, n);
    for (int a = 0; a < 3; ++a) {
      const double d = std::fabs(double(q[a]) - p[a]), pa = std::fabs(p[a]), na = std::fabs(n[a]);
      if (pa < 1.0 / 32) {
        // p + n / 65536 rounded to float: within half an ulp of the result.
        EXPECT_NEAR(d, na / 65536, std::ldexp(1.0, std::ilogb(q[a]) - 24)) << p[a] << " " << n[a];
        continue;
      }
      const double ulp = std::ldexp(1.0, std::ilogb(p[a]) - 23);
      const double k = std::floor(256 * na);
      if (k > 0) {
        EXPECT_EQ(q[a] > p[a], n[a] > 0) << "moved along the normal";
      }
      if (std::ilogb(q[a]) == std::ilogb(p[a])) {
        EXPECT_EQ(d, k * ulp) << p[a] << " " << n[a];
      }
      EXPECT_LE(d, 0x1p-15 * pa * na * (1 + 1e-6)) << p[a] << " " << n[a];
      EXPECT_GE(d, 0x1p-16 * pa * (k / 256) * (1 - 1e-6)) << p[a] << " " << n[a];
    }
  }
}

TEST(ValidRange, OccludersWithinTheSpawnOffsetAreMissed) {
  // The consequence: a surface at x = 148,376 spawns rays 4 units in front of it, so an occluder
  // 3 units away is behind the origin and missed; one 5 units away is found.
  const float x = 148376.f;
  for (float gap : {3.f, 5.f}) {
    std::vector<Triangle> tris = {{{x, -10, -10}, {x, 10, -10}, {x, 10, 10}}};
    for (const Triangle& t : square(Vec3(0), 10.f)) {  // the occluder, turned into x = x + gap
      auto yz = [&](const Vec3& v) { return Vec3(x + gap, v.x, v.y); };
      tris.push_back({yz(t.v0), yz(t.v1), yz(t.v2)});
    }
    Bvh bvh = build_bvh(tris);
    const Vec3 o = offset_ray_origin({x, 1, 2}, {1, 0, 0});
    EXPECT_EQ(o.x, x + 4.f);
    Counters c;
    const Hit h = any_hit(bvh, make_ray(o, {1, 0, 0}), &c);
    EXPECT_EQ(h.hit(), gap > 4.f) << "gap " << gap;
  }
}

}  // namespace
}  // namespace hrpp
