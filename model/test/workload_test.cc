// Ray workloads (docs/workloads.md): effects derived from hand-made glTF scenes, the geometry of
// reflection, refraction and area-light rays, 0 self-hits on every scene, and ray orders that
// permute one and the same multiset of rays.
#include "hrpp/workload/workload.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include "scene_builder.h"
#include "test_util.h"

namespace hrpp {
namespace {

std::vector<RayRecord> collect(const Scene& s, const Bvh& bvh, const WorkloadOptions& wo) {
  std::vector<RayRecord> out;
  generate_rays(s, bvh, wo, [&](const RayRecord& r, const Hit*) { out.push_back(r); });
  return out;
}

size_t count_kind(const std::vector<RayRecord>& rays, RayKind k) {
  return std::count_if(rays.begin(), rays.end(), [k](const RayRecord& r) { return r.kind == k; });
}

WorkloadOptions auto_options(const Scene& s, const std::string& spec = "auto") {
  WorkloadOptions wo;
  EXPECT_EQ(apply_effects(spec, s, &wo), "");
  return wo;
}

// Floor, a mirror sphere, a matte sphere; optionally a point light.
struct Spheres {
  Scene scene;
  uint32_t floor, mirror, matte, end;
};
Spheres spheres_scene(const std::string& name, bool light) {
  test::SceneBuilder b;
  const int matte = b.material({.name = "matte"});
  const int metal =
      b.material({.name = "mirror", .base = Vec3(0.9f), .metallic = 1, .roughness = 0});
  Spheres s;
  s.floor = b.quad("floor", Vec3(-4, 0, -4), Vec3(8, 0, 0), Vec3(0, 0, 8), Vec3(0, 1, 0), matte);
  s.mirror = b.sphere("mirror_sphere", Vec3(-1, 1, 0), 0.9f, metal);
  s.matte = b.sphere("matte_sphere", Vec3(1.2f, 1, 0), 0.9f, matte);
  s.end = b.triangles();
  if (light) b.point_light("lamp", Vec3(0, 5, 3), 40);
  s.scene = load_scene(b.write(test::temp_dir("workload_" + name), name));
  return s;
}

TEST(Effects, NoLightsNoShadowRays) {
  Spheres s = spheres_scene("nolight", false);
  const EffectChoice c = derive_effects(s.scene);
  EXPECT_FALSE(c.shadow);
  EXPECT_NE(c.shadow_why.find("no punctual light"), std::string::npos) << c.shadow_why;
  Bvh bvh = build_bvh(s.scene.triangles);
  // Even when asked for explicitly, there is nothing to cast shadow rays at.
  for (const char* spec : {"auto", "shadow,ao,reflection"}) {
    const auto rays = collect(s.scene, bvh, auto_options(s.scene, spec));
    EXPECT_EQ(count_kind(rays, RayKind::kShadow), 0u) << spec;
    EXPECT_GT(count_kind(rays, RayKind::kPrimary), 0u);
  }
  const auto lines = describe_effects(s.scene, auto_options(s.scene, "shadow"), "shadow");
  EXPECT_NE(lines[0].find("requested, but no punctual light"), std::string::npos) << lines[0];
}

TEST(Effects, OneMetallicSphereGivesReflectionRaysOnlyFromIt) {
  Spheres s = spheres_scene("mirror", true);
  const EffectChoice c = derive_effects(s.scene);
  EXPECT_TRUE(c.shadow);
  EXPECT_TRUE(c.reflection);
  EXPECT_FALSE(c.refraction);
  EXPECT_NE(c.reflection_why.find("'mirror'"), std::string::npos) << c.reflection_why;
  EXPECT_EQ(c.reflection_why.find("'matte'"), std::string::npos) << c.reflection_why;
  EXPECT_NE(c.shadow_why.find("lamp"), std::string::npos) << c.shadow_why;

  Bvh bvh = build_bvh(s.scene.triangles);
  const auto rays = collect(s.scene, bvh, auto_options(s.scene));
  std::map<uint64_t, const RayRecord*> by_id;
  for (const RayRecord& r : rays) by_id[r.id] = &r;
  size_t reflections = 0;
  for (const RayRecord& r : rays) {
    if (r.kind != RayKind::kReflection) continue;
    ++reflections;
    ASSERT_GE(r.spawn_prim, s.mirror);
    ASSERT_LT(r.spawn_prim, s.matte) << "a reflection ray left a non-metallic surface";
    // Roughness 0: exactly the mirror direction about the geometric normal.
    const RayRecord& parent = *by_id.at(r.parent);
    Vec3 n = glm::normalize(s.scene.triangles[r.spawn_prim].normal());
    if (glm::dot(n, parent.ray.dir) > 0) n = -n;
    const Vec3 d = glm::normalize(parent.ray.dir);
    const Vec3 m = d - 2.f * glm::dot(d, n) * n;
    EXPECT_LT(glm::length(r.ray.dir - m), 1e-5f);
    EXPECT_GT(glm::dot(r.ray.dir, n), 0.f);
  }
  EXPECT_GT(reflections, 50u);
  EXPECT_EQ(count_kind(rays, RayKind::kRefraction), 0u);
  EXPECT_EQ(count_kind(rays, RayKind::kAo), 0u) << "AO only on request";
  EXPECT_EQ(count_kind(rays, RayKind::kDiffuse), 0u) << "diffuse only on request";
  // Reflection rays that hit spawn their own shadow rays (depth 2).
  EXPECT_TRUE(std::any_of(rays.begin(), rays.end(), [](const RayRecord& r) {
    return r.kind == RayKind::kShadow && r.depth == 2;
  }));
  // --effects overrides: without reflection, none.
  const auto shadow_only = collect(s.scene, bvh, auto_options(s.scene, "shadow"));
  EXPECT_EQ(count_kind(shadow_only, RayKind::kReflection), 0u);
  EXPECT_GT(count_kind(shadow_only, RayKind::kShadow), 0u);
}

TEST(Effects, EmissiveQuadGivesAreaLightSamplesOnIt) {
  test::SceneBuilder b;
  const int matte = b.material({});
  const int emitter = b.material({.name = "panel",
                                  .base = Vec3(0),
                                  .emissive = Vec3(1),
                                  .emissive_strength = 10,
                                  .double_sided = false});
  b.quad("floor", Vec3(-4, 0, -4), Vec3(8, 0, 0), Vec3(0, 0, 8), Vec3(0, 1, 0), matte);
  const uint32_t panel =
      b.quad("panel", Vec3(-0.5f, 3, -0.5f), Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, -1, 0), emitter);
  b.box("block", Vec3(-0.5f, 0, -0.5f), Vec3(0.5f, 1, 0.5f), matte);
  Scene s = load_scene(b.write(test::temp_dir("workload_area"), "area"));
  const EffectChoice c = derive_effects(s);
  EXPECT_TRUE(c.shadow);
  EXPECT_NE(c.shadow_why.find("1 emissive mesh (panel: 2 triangles)"), std::string::npos)
      << c.shadow_why;
  EXPECT_FALSE(c.reflection);
  EXPECT_FALSE(c.refraction);

  Bvh bvh = build_bvh(s.triangles);
  const auto rays = collect(s, bvh, auto_options(s));
  size_t shadows = 0, blocked = 0;
  for (const RayRecord& r : rays) {
    if (r.kind != RayKind::kShadow) continue;
    ++shadows;
    // The sampled point (tfar is 1e-4 short of it) lies on the panel.
    const Vec3 q = r.ray.org + r.ray.dir * (r.ray.tfar / (1.f - 1e-4f));
    EXPECT_NEAR(q.y, 3.f, 1e-3f);
    EXPECT_LE(std::fabs(q.x), 0.5f + 1e-3f);
    EXPECT_LE(std::fabs(q.z), 0.5f + 1e-3f);
    EXPECT_LT(r.ray.org.y, 3.f) << "the one-sided panel emits downwards only";
    EXPECT_NE(r.spawn_prim, panel);
    EXPECT_NE(r.spawn_prim, panel + 1);
    // The ray ends before the panel: it is not occluded by the light itself.
    Counters cnt;
    const Hit h = closest_hit(bvh, r.ray, &cnt);
    EXPECT_TRUE(!h.hit() || (h.prim != panel && h.prim != panel + 1));
    blocked += h.hit();
  }
  EXPECT_GT(shadows, 500u);
  EXPECT_GT(blocked, 0u) << "the block casts a shadow";
}

TEST(Effects, RefractionFollowsSnellAndTotalInternalReflectionReflects) {
  test::SceneBuilder b;
  const int matte = b.material({});
  const int glass = b.material({.name = "glass",
                                .base = Vec3(1),
                                .roughness = 0,
                                .transmission = 1,
                                .ior = 1.5f,
                                .double_sided = false});
  b.quad("floor", Vec3(-4, 0, -4), Vec3(8, 0, 0), Vec3(0, 0, 8), Vec3(0, 1, 0), matte);
  const uint32_t g0 = b.box("glass_block", Vec3(-1, 0.01f, -1), Vec3(1, 1.5f, 1), glass);
  b.point_light("lamp", Vec3(2, 5, 4), 40);
  b.camera(Vec3(0, 4, 4), Vec3(0, 0.5f, 0), Vec3(0, 1, 0), 40, 64, 64);
  Scene s = load_scene(b.write(test::temp_dir("workload_glass"), "glass"));
  const EffectChoice c = derive_effects(s);
  EXPECT_TRUE(c.refraction);
  EXPECT_FALSE(c.reflection);
  Bvh bvh = build_bvh(s.triangles);
  WorkloadOptions wo = auto_options(s);
  wo.max_depth = 3;
  const auto rays = collect(s, bvh, wo);
  std::map<uint64_t, const RayRecord*> by_id;
  for (const RayRecord& r : rays) by_id[r.id] = &r;
  size_t refracted = 0, tir = 0;
  for (const RayRecord& r : rays) {
    if (r.kind != RayKind::kRefraction && r.kind != RayKind::kReflection) continue;
    ASSERT_GE(r.spawn_prim, g0);
    ASSERT_LT(r.spawn_prim, g0 + 12);
    const RayRecord& parent = *by_id.at(r.parent);
    const Vec3 ng = glm::normalize(s.triangles[r.spawn_prim].normal());
    const Vec3 d = glm::normalize(parent.ray.dir);
    const bool entering = glm::dot(ng, d) < 0;
    const Vec3 n = entering ? ng : -ng;
    const float eta = entering ? 1 / 1.5f : 1.5f;
    const float sin_i = glm::length(glm::cross(d, n));
    if (r.kind == RayKind::kRefraction) {
      ++refracted;
      EXPECT_NEAR(glm::length(glm::cross(r.ray.dir, n)), eta * sin_i, 1e-4f);  // Snell
      EXPECT_LT(glm::dot(r.ray.dir, n), 0.f) << "leaves on the other side";
      EXPECT_GT(r.depth, 0);
    } else {
      ++tir;
      EXPECT_GT(eta * sin_i, 1.f - 1e-5f)
          << "a reflection from glass only on total internal reflection";
      EXPECT_LT(glm::length(r.ray.dir - (d - 2.f * glm::dot(d, n) * n)), 1e-5f);
      EXPECT_FALSE(entering);
    }
  }
  EXPECT_GT(refracted, 500u);
  EXPECT_GT(tir, 50u);
}

// Every secondary ray kind, on every shared and own scene: the first hit of a secondary ray is
// never the triangle it was spawned from.
TEST(Workload, NoSelfHitsOnAnyScene) {
  std::vector<std::string> scenes = test::shared_scenes();
  if (scenes.empty()) std::printf("../shared/scenes absent: own scenes only\n");
  for (const auto& p : test::own_scenes()) scenes.push_back(p);
  for (const std::string& path : scenes) {
    Scene s = load_scene(path);
    Bvh bvh = build_bvh(s.triangles);
    WorkloadOptions wo;
    ASSERT_EQ(apply_effects("auto,shadow,ao,reflection,refraction,diffuse", s, &wo), "");
    wo.width = wo.height = 96;
    std::array<uint64_t, kNumRayKinds> spawned{}, self{};
    generate_rays(s, bvh, wo, [&](const RayRecord& r, const Hit*) {
      if (r.kind == RayKind::kPrimary) return;
      ASSERT_NE(r.spawn_prim, kNoPrim);
      Counters c;
      const Hit h = closest_hit(bvh, r.ray, &c);
      spawned[int(r.kind)]++;
      self[int(r.kind)] += h.hit() && h.prim == r.spawn_prim;
    });
    for (int k = 1; k < kNumRayKinds; ++k)
      EXPECT_EQ(self[k], 0u) << path << " " << ray_kind_name(RayKind(k)) << ": " << self[k]
                             << " self-hits among " << spawned[k];
    EXPECT_GT(spawned[int(RayKind::kAo)] + spawned[int(RayKind::kDiffuse)], 1000u) << path;
    const EffectChoice c = derive_effects(s);
    if (c.reflection) {
      EXPECT_GT(spawned[int(RayKind::kReflection)], 0u) << path;
    }
    if (c.refraction) {
      EXPECT_GT(spawned[int(RayKind::kRefraction)], 0u) << path;
    }
    if (c.shadow) {
      EXPECT_GT(spawned[int(RayKind::kShadow)], 0u) << path;
    }
  }
}

// A ray without its id: what must be equal across orders.
using RayKey = std::tuple<uint32_t, uint32_t, int, int, uint32_t, std::array<uint32_t, 8>>;
RayKey key_of(const RayRecord& r) {
  std::array<uint32_t, 8> bits;
  std::memcpy(bits.data(), &r.ray.org, 12);
  std::memcpy(bits.data() + 3, &r.ray.dir, 12);
  std::memcpy(bits.data() + 6, &r.ray.tnear, 4);
  std::memcpy(bits.data() + 7, &r.ray.tfar, 4);
  return {r.pixel, r.sample, int(r.kind), r.depth, r.spawn_prim, bits};
}

void check_stream_structure(const std::vector<RayRecord>& rays) {
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(rays[i].id, i);
    if (rays[i].kind == RayKind::kPrimary) {
      ASSERT_EQ(rays[i].parent, ~0ull);
    } else {
      ASSERT_LT(rays[i].parent, i) << "a parent is issued before its children";
      const RayRecord& p = rays[rays[i].parent];
      ASSERT_EQ(p.pixel, rays[i].pixel);
      ASSERT_EQ(p.sample, rays[i].sample);
      ASSERT_FALSE(is_any_hit(p.kind));
      ASSERT_EQ(p.depth + 1, rays[i].depth);
    }
  }
}

TEST(Workload, OrdersPermuteTheSameRays) {
  Scene s = load_scene(std::string(HRPP_SOURCE_DIR) + "/scenes/glass_spheres.glb");
  Bvh bvh = build_bvh(s.triangles);
  for (int tile : {8, 5}) {
    WorkloadOptions wo;
    ASSERT_EQ(apply_effects("auto,ao,diffuse", s, &wo), "");
    wo.width = 37;  // not a multiple of the tile
    wo.height = 23;
    wo.spp = 2;
    wo.tile = tile;
    std::vector<RayKey> reference;
    for (RayOrder o : {RayOrder::kScanline, RayOrder::kTiled, RayOrder::kMorton}) {
      wo.order = o;
      const auto rays = collect(s, bvh, wo);
      SCOPED_TRACE(std::string(ray_order_name(o)) + " tile " + std::to_string(tile));
      check_stream_structure(rays);
      std::vector<RayKey> keys;
      for (const RayRecord& r : rays) keys.push_back(key_of(r));
      std::sort(keys.begin(), keys.end());
      if (o == RayOrder::kScanline) {
        reference = keys;
      } else {
        EXPECT_TRUE(keys == reference) << "the multiset of rays differs from scanline order";
      }
    }
    for (int k = 0; k < kNumRayKinds; ++k)  // every kind takes part
      EXPECT_GT(std::count_if(reference.begin(), reference.end(),
                              [k](const RayKey& r) { return std::get<2>(r) == k; }),
                0)
          << ray_kind_name(RayKind(k));
  }
}

TEST(Workload, OrdersIssueTilesThenKinds) {
  Scene s = load_scene(std::string(HRPP_SOURCE_DIR) + "/scenes/glass_spheres.glb");
  Bvh bvh = build_bvh(s.triangles);
  WorkloadOptions wo;
  ASSERT_EQ(apply_effects("auto,ao", s, &wo), "");
  wo.width = wo.height = 32;
  auto pixel_xy = [&](uint32_t p) { return std::pair<int, int>(p % 32, p / 32); };

  // Scanline: each camera sample's rays follow its primary ray (today's order).
  wo.order = RayOrder::kScanline;
  auto rays = collect(s, bvh, wo);
  uint32_t last_primary_pixel = 0;
  for (const RayRecord& r : rays) {
    if (r.kind == RayKind::kPrimary)
      last_primary_pixel = r.pixel;
    else
      ASSERT_EQ(r.pixel, last_primary_pixel);
  }

  // Tiled: the 64 primary rays of tile (0, 0) first, in scanline order inside the tile, then
  // that tile's rays grouped by generation and kind.
  wo.order = RayOrder::kTiled;
  rays = collect(s, bvh, wo);
  for (int i = 0; i < 64; ++i) {
    ASSERT_EQ(rays[i].kind, RayKind::kPrimary);
    EXPECT_EQ(pixel_xy(rays[i].pixel), std::pair(i % 8, i / 8));
  }
  size_t i = 64;
  for (; i < rays.size() && rays[i].kind != RayKind::kPrimary; ++i) {
    const auto [x, y] = pixel_xy(rays[i].pixel);
    EXPECT_LT(x, 8);
    EXPECT_LT(y, 8);
    if (rays[i].depth == rays[i - 1].depth) {
      EXPECT_GE(int(rays[i].kind), int(rays[i - 1].kind)) << "kinds grouped within a generation";
    } else {
      EXPECT_GT(rays[i].depth, rays[i - 1].depth);
    }
  }
  ASSERT_LT(i, rays.size());
  EXPECT_EQ(pixel_xy(rays[i].pixel), std::pair(8, 0)) << "the next tile to the right";

  // Morton: tiles and pixels along the Z curve.
  wo.order = RayOrder::kMorton;
  rays = collect(s, bvh, wo);
  const std::pair<int, int> z[8] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {2, 0}, {3, 0}, {2, 1}, {3, 1}};
  for (int k = 0; k < 8; ++k) EXPECT_EQ(pixel_xy(rays[k].pixel), z[k]);
  std::vector<std::pair<int, int>> tiles;
  for (const RayRecord& r : rays)
    if (r.kind == RayKind::kPrimary) {
      const auto [x, y] = pixel_xy(r.pixel);
      if (tiles.empty() || tiles.back() != std::pair(x / 8, y / 8)) tiles.push_back({x / 8, y / 8});
    }
  const std::vector<std::pair<int, int>> want = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {2, 0}, {3, 0},
                                                 {2, 1}, {3, 1}, {0, 2}, {1, 2}, {0, 3}, {1, 3},
                                                 {2, 2}, {3, 2}, {2, 3}, {3, 3}};
  EXPECT_EQ(tiles, want);
}

TEST(Workload, EffectsSpecErrors) {
  Scene s = load_scene(std::string(HRPP_SOURCE_DIR) + "/scenes/cornell_box.glb");
  WorkloadOptions wo;
  EXPECT_NE(apply_effects("shadows", s, &wo).find("unknown effect 'shadows'"), std::string::npos);
  EXPECT_NE(apply_effects("none,ao", s, &wo).find("'none' cannot be combined"), std::string::npos);
  EXPECT_NE(apply_effects("", s, &wo).find("unknown effect ''"), std::string::npos);
  ASSERT_EQ(apply_effects("none", s, &wo), "");
  EXPECT_FALSE(wo.shadow || wo.ao || wo.reflection || wo.refraction || wo.diffuse);
  ASSERT_EQ(apply_effects("auto", s, &wo), "");
  EXPECT_TRUE(wo.shadow);
  EXPECT_FALSE(wo.ao || wo.reflection || wo.refraction || wo.diffuse);
  ASSERT_EQ(apply_effects("auto, ao", s, &wo), "");
  EXPECT_TRUE(wo.shadow && wo.ao);
  // The library default is the workload the predictor figures were measured with.
  const WorkloadOptions def;
  EXPECT_TRUE(def.shadow && def.ao);
  EXPECT_FALSE(def.reflection || def.refraction || def.diffuse);
  EXPECT_EQ(def.order, RayOrder::kScanline);
}

// ---- MICRO 2021's AO benchmark (--workload micro21-ao) -----------------------------------------

Scene micro21_scene(size_t n) {
  Scene s;
  for (size_t i = 0; i < n; ++i) {
    const float x = static_cast<float>(i % 1000), z = static_cast<float>(i / 1000);
    // Triangles of alternating winding in the plane y = x / 1000, and every 7th degenerate.
    Triangle t{Vec3(x, x / 1000, z), Vec3(x + 0.5f, (x + 0.5f) / 1000, z),
               Vec3(x, x / 1000, z + 0.5f)};
    if (i % 2) std::swap(t.v1, t.v2);
    if (i % 7 == 3) t.v2 = t.v0 + 2.f * (t.v1 - t.v0);  // collinear
    s.triangles.push_back(t);
  }
  return s;
}

std::vector<RayRecord> micro21_rays(const Scene& s, uint64_t seed = 1) {
  WorkloadOptions wo;
  wo.source = WorkloadSource::kMicro21Ao;
  wo.seed = seed;
  return collect(s, Bvh{}, wo);
}

TEST(Micro21Ao, OneRayPerNonDegenerateTriangleInOrder) {
  const Scene s = micro21_scene(700);
  const std::vector<RayRecord> rays = micro21_rays(s);
  std::vector<uint32_t> want;
  for (uint32_t i = 0; i < s.triangles.size(); ++i)
    if (i % 7 != 3) want.push_back(i);
  ASSERT_EQ(rays.size(), want.size());
  for (size_t k = 0; k < rays.size(); ++k) {
    const RayRecord& r = rays[k];
    EXPECT_EQ(r.spawn_prim, want[k]);
    EXPECT_EQ(r.id, k);
    EXPECT_EQ(r.kind, RayKind::kAo);
    // tmin as MICRO 2021's, unbounded.
    EXPECT_EQ(r.ray.tnear, kMicro21AoTnear);
    EXPECT_TRUE(std::isinf(r.ray.tfar) && r.ray.tfar > 0);
    // The origin on its triangle (inside, in its plane), the direction unit and on the side
    // the triangle's winding faces.
    const Triangle& t = s.triangles[r.spawn_prim];
    const Vec3 ng = glm::cross(t.v1 - t.v0, t.v2 - t.v0);
    const Vec3 p = r.ray.org;
    EXPECT_NEAR(glm::dot(p - t.v0, glm::normalize(ng)), 0.f, 1e-4f);
    EXPECT_GE(glm::dot(glm::cross(t.v1 - t.v0, p - t.v0), ng), -1e-6f);
    EXPECT_GE(glm::dot(glm::cross(t.v2 - t.v1, p - t.v1), ng), -1e-6f);
    EXPECT_GE(glm::dot(glm::cross(t.v0 - t.v2, p - t.v2), ng), -1e-6f);
    EXPECT_NEAR(glm::length(r.ray.dir), 1.f, 1e-5f);
    EXPECT_GT(glm::dot(r.ray.dir, ng), 0.f);
  }
}

TEST(Micro21Ao, CosineDistributedAndSeeded) {
  // cos(theta) of a cosine-weighted direction: cos^2 uniform on [0, 1] (mean of cos 2/3).
  const Scene s = micro21_scene(40000);
  const std::vector<RayRecord> rays = micro21_rays(s);
  ASSERT_GT(rays.size(), 30000u);
  int bins[10] = {};
  double sum = 0, sum_t = 0;
  for (const RayRecord& r : rays) {
    const Triangle& t = s.triangles[r.spawn_prim];
    const Vec3 n = glm::normalize(glm::cross(t.v1 - t.v0, t.v2 - t.v0));
    const double c = glm::dot(r.ray.dir, n);
    sum += c;
    sum_t += glm::dot(r.ray.dir, glm::normalize(t.v1 - t.v0));  // a tangent: mean 0
    ++bins[std::min(9, static_cast<int>(c * c * 10))];
  }
  const double n = static_cast<double>(rays.size());
  EXPECT_NEAR(sum / n, 2.0 / 3.0, 5 * std::sqrt(1.0 / 18 / n));
  EXPECT_NEAR(sum_t / n, 0.0, 5 * std::sqrt(1.0 / 4 / n));
  double chi2 = 0;
  for (int b : bins) chi2 += (b - n / 10) * (b - n / 10) / (n / 10);
  EXPECT_LT(chi2, 27.88) << "cos^2 not uniform (chi-square, 9 degrees of freedom, p = 0.001)";
  // Deterministic for a seed, other rays for another.
  const std::vector<RayRecord> again = micro21_rays(s), other = micro21_rays(s, 2);
  EXPECT_EQ(again[123].ray.dir, rays[123].ray.dir);
  EXPECT_EQ(again[123].ray.org, rays[123].ray.org);
  EXPECT_NE(other[123].ray.dir, rays[123].ray.dir);
}

// The sorted workload: the same rays, ordered by MICRO 2021's sorting key, rays of one key in
// triangle order, ids in issue order; the key's fields as their hash_grid_spherical computes them.
TEST(Micro21Ao, SortedByTheirKeyStably) {
  const Scene s = micro21_scene(5000);
  const std::vector<RayRecord> plain = micro21_rays(s);
  WorkloadOptions wo;
  wo.source = WorkloadSource::kMicro21AoSorted;
  const std::vector<RayRecord> sorted = collect(s, Bvh{}, wo);
  ASSERT_EQ(sorted.size(), plain.size());
  Aabb b;
  for (const Triangle& t : s.triangles)
    for (const Vec3& v : {t.v0, t.v1, t.v2}) b.grow(v);
  std::vector<uint32_t> prims;
  for (size_t k = 0; k < sorted.size(); ++k) {
    EXPECT_EQ(sorted[k].id, k);
    prims.push_back(sorted[k].spawn_prim);
    if (k == 0) continue;
    const uint64_t a = micro21_sort_key(sorted[k - 1].ray, b),
                   c = micro21_sort_key(sorted[k].ray, b);
    ASSERT_LE(a, c) << k;
    if (a == c) {
      EXPECT_LT(sorted[k - 1].spawn_prim, sorted[k].spawn_prim) << k;
    }
  }
  std::sort(prims.begin(), prims.end());
  for (size_t k = 0; k < plain.size(); ++k) ASSERT_EQ(prims[k], plain[k].spawn_prim);
  EXPECT_NE(sorted[10].spawn_prim, plain[10].spawn_prim);  // another order
  // The key: origin cell (32 per axis over the vertex bounds) << 7 | phi (4 bits) << 3 | theta.
  Ray r;
  r.org = b.lo;
  r.dir = Vec3(0, 0, 1);  // theta 0; phi = atan2(0, 0) + pi = 180 degrees: 180 >> 5 = 5
  EXPECT_EQ(micro21_sort_key(r, b), uint64_t(5) << 3);
  r.org = b.hi;
  r.dir = Vec3(0, 0, -1);  // theta 180 >> 5 = 5
  EXPECT_EQ(micro21_sort_key(r, b), (uint64_t(0x7FFF) << 7) | (5 << 3) | 5);
}

// --ao-normal flipped: the hemisphere about the opposite of the normal as wound.
TEST(Micro21Ao, FlippedNormalSamplesTheOtherHemisphere) {
  const Scene s = micro21_scene(700);
  WorkloadOptions wo;
  wo.source = WorkloadSource::kMicro21Ao;
  wo.micro21_flip = true;
  const std::vector<RayRecord> flipped = collect(s, Bvh{}, wo), plain = micro21_rays(s);
  ASSERT_EQ(flipped.size(), plain.size());
  for (size_t k = 0; k < flipped.size(); ++k) {
    const Triangle& t = s.triangles[flipped[k].spawn_prim];
    EXPECT_LT(glm::dot(flipped[k].ray.dir, glm::cross(t.v1 - t.v0, t.v2 - t.v0)), 0.f);
    EXPECT_EQ(flipped[k].ray.org, plain[k].ray.org);
  }
}

TEST(Micro21Ao, AtMostItsPointCount) {
  // MICRO 2021's generator stops once it has more than 1,000,000 points.
  const Scene s = micro21_scene(1200000);
  const std::vector<RayRecord> rays = micro21_rays(s);
  EXPECT_EQ(rays.size(), kMicro21AoMaxRays);
  EXPECT_EQ(rays.back().id, kMicro21AoMaxRays - 1);
}

}  // namespace
}  // namespace hrpp
