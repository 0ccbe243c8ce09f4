// Scene loading: real scenes load with the expected contents; malformed files give clear errors.
#include "hrpp/scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "test_util.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;

TEST(Scene, SharedScenesLoadWithPublishedCounts) {
  struct Expect {
    const char* file;
    size_t triangles;
    size_t punctual_lights;
    bool area_light;
  };
  // Triangle counts from ../shared/scenes/SOURCES.md ("all mesh nodes together").
  const Expect expect[] = {{"bunny.glb", 69485, 1, true},    {"teapot.glb", 2360, 1, true},
                           {"killeroo.glb", 66852, 0, true}, {"happy_buddha.glb", 98601, 1, false},
                           {"sponza.glb", 66454, 1, false},  {"cornell_box.glb", 32, 0, true}};
  if (test::shared_scenes().empty()) GTEST_SKIP() << "../shared/scenes absent";
  for (const auto& e : expect) {
    Scene s = load_scene(test::shared_scene(e.file));
    EXPECT_EQ(s.triangles.size(), e.triangles) << e.file;
    EXPECT_EQ(s.lights.size(), e.punctual_lights) << e.file;
    EXPECT_EQ(!s.emissive_triangles().empty(), e.area_light) << e.file;
    EXPECT_EQ(s.camera.source,
              "sidecar " + std::string(e.file).substr(0, std::strlen(e.file) - 4) + ".camera.json");
    EXPECT_FALSE(s.bounds.empty());
  }
  // SOURCES.md: exactly one zero-area triangle in the whole set, in sponza.
  EXPECT_EQ(load_scene(test::shared_scene("sponza.glb")).degenerate_triangles, 1u);
  // The sun of sponza travels along (0.24321, -0.965926, -0.088521).
  Scene sp = load_scene(test::shared_scene("sponza.glb"));
  ASSERT_EQ(sp.lights.size(), 1u);
  EXPECT_EQ(sp.lights[0].type, Light::Type::kDirectional);
  EXPECT_NEAR(sp.lights[0].direction.x, 0.24321f, 1e-4f);
  EXPECT_NEAR(sp.lights[0].direction.y, -0.965926f, 1e-4f);
  // Materials and extensions: the bunny's area light has emissive strength 15.
  Scene bunny = load_scene(test::shared_scene("bunny.glb"));
  bool found = false;
  for (const Material& m : bunny.materials)
    if (m.is_emissive()) {
      EXPECT_FLOAT_EQ(m.emissive_strength, 15.f);
      EXPECT_FALSE(m.double_sided);
      found = true;
    }
  EXPECT_TRUE(found);
}

TEST(Scene, OwnScenesLoad) {
  auto own = test::own_scenes();
  ASSERT_GE(own.size(), 1u) << "scenes/ must hold the project's default scene";
  for (const auto& p : own) {
    Scene s = load_scene(p);
    EXPECT_GT(s.triangles.size(), 0u) << p;
    EXPECT_EQ(s.degenerate_triangles, 0u) << p;
    EXPECT_NE(s.camera.source.find("sidecar"), std::string::npos) << p;
  }
}

// The own scenes' sizes as scenes/README.md lists them (gen_scenes.py prints them): a changed
// generator that moves or re-tessellates a scene fails here as well as in scenes.reproducible.
TEST(Scene, OwnScenesHaveTheirDocumentedCountsAndBounds) {
  struct Expect {
    const char* file;
    size_t triangles;
    size_t punctual_lights;
    bool area_light;
    float lo[3], hi[3];
  };
  const Expect expect[] = {
      {"cornell_box.glb", 32, 0, true, {0, 0, 0}, {556, 548.8f, 559.2f}},
      {"spd_balls.glb", 29122, 3, false, {-12, -12, -0.5f}, {12, 12, 0.784857f}},
      {"spd_tetra.glb", 1028, 1, true, {-5, -5, -0.01f}, {5, 5, 3.5f}},
      {"glass_spheres.glb", 2564, 1, false, {-3, 0, -3}, {3, 4, 3}},
      {"spd_rings.glb",
       47042,
       3,
       false,
       {-6.466081f, 1.653795f, -4.966081f},
       {4.466081f, 10.452504f, 5.966081f}},
      {"spd_gears.glb", 36866, 5, false, {-2, -2, 0}, {2, 2, 1}},
      {"spd_tree.glb", 26522, 7, false, {-50, -50, 0}, {50, 50, 3.001848f}},
      {"spd_mount.glb", 13312, 1, false, {-1.159163f, -1, -0.702953f}, {1, 1.159279f, 1.377919f}},
      {"spd_lattice.glb",
       30240,
       6,
       false,
       {-0.049868f, -0.049853f, -0.048310f},
       {1.049868f, 1.049853f, 1.048310f}},
      {"spd_shells.glb",
       28880,
       1,
       false,
       {-27.274710f, -21.545853f, -50.134758f},
       {17.025650f, 33.754421f, -0.003619f}},
      {"spd_jacks.glb",
       42048,
       1,
       false,
       {-1.174878f, -1.329931f, -1.396316f},
       {1.174878f, 1.329931f, 1.396316f}},
      {"spd_sombrero.glb", 7938, 1, false, {-4, -3.606853f, -4}, {4, -2, 4}}};
  EXPECT_EQ(test::own_scenes().size(), std::size(expect)) << "a new own scene: list it here";
  for (const auto& e : expect) {
    const Scene s = load_scene(std::string(HRPP_SOURCE_DIR) + "/scenes/" + e.file);
    EXPECT_EQ(s.triangles.size(), e.triangles) << e.file;
    EXPECT_EQ(s.lights.size(), e.punctual_lights) << e.file;
    EXPECT_EQ(!s.emissive_triangles().empty(), e.area_light) << e.file;
    const float lo[3] = {s.bounds.lo.x, s.bounds.lo.y, s.bounds.lo.z};
    const float hi[3] = {s.bounds.hi.x, s.bounds.hi.y, s.bounds.hi.z};
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(lo[k], e.lo[k], 1e-5f * std::max(1.f, std::fabs(e.lo[k]))) << e.file << " " << k;
      EXPECT_NEAR(hi[k], e.hi[k], 1e-5f * std::max(1.f, std::fabs(e.hi[k]))) << e.file << " " << k;
    }
  }
}

// keep_meshes: the named meshes' triangles in order, their materials, bounds and ranges; an
// unknown name is an error naming the scene's meshes.
TEST(Scene, KeepMeshesKeepsOnlyTheNamedOnes) {
  const Scene full = load_scene(std::string(HRPP_SOURCE_DIR) + "/scenes/cornell_box.glb");
  ASSERT_GE(full.meshes.size(), 3u);
  const MeshRange& a = full.meshes[1];
  const MeshRange& c = full.meshes[2];
  Scene s = full;
  keep_meshes(&s, {c.name, a.name});
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].name, a.name);  // in the scene's order
  EXPECT_EQ(s.meshes[1].first, a.count);
  ASSERT_EQ(s.triangles.size(), size_t(a.count) + c.count);
  Aabb b;
  for (uint32_t i = 0; i < a.count; ++i) {
    EXPECT_EQ(s.triangles[i].v0, full.triangles[a.first + i].v0);
    EXPECT_EQ(s.tri_material[i], full.tri_material[a.first + i]);
  }
  for (const Triangle& t : s.triangles) b.grow(t.bounds());
  EXPECT_EQ(s.bounds.lo, b.lo);
  EXPECT_EQ(s.bounds.hi, b.hi);
  EXPECT_THROW(keep_meshes(&s, {"no_such_mesh"}), std::invalid_argument);
}

class Malformed : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir(::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  // Writes the glTF JSON and expects load_scene to throw a SceneError containing every needle.
  void expect_error(const nlohmann::json& j, std::vector<std::string> needles,
                    const std::string& name = "scene.gltf") {
    std::string path = dir_ + "/" + name;
    test::write_text(path, j.dump());
    expect_error_file(path, needles);
  }
  void expect_error_file(const std::string& path, std::vector<std::string> needles) {
    try {
      load_scene(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const SceneError& e) {
      std::string msg = e.what();
      EXPECT_EQ(msg.rfind(path, 0), 0u) << "message must start with the file: " << msg;
      for (const auto& n : needles) EXPECT_NE(msg.find(n), std::string::npos) << msg;
    }
  }
  nlohmann::json good() { return test::minimal_gltf({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}); }
  std::string dir_;
};

TEST_F(Malformed, GoodMinimalSceneLoads) {
  std::string path = dir_ + "/ok.gltf";
  test::write_text(path, good().dump());
  Scene s = load_scene(path);
  EXPECT_EQ(s.triangles.size(), 1u);
  EXPECT_EQ(s.camera.source, "computed default");
}

TEST_F(Malformed, MissingFile) { expect_error_file(dir_ + "/nope.glb", {"no such file"}); }

TEST_F(Malformed, Directory) { expect_error_file(dir_, {"directory"}); }

TEST_F(Malformed, BadJson) {
  std::string path = dir_ + "/bad.gltf";
  test::write_text(path, "{ \"asset\": { \"version\": \"2.0\" ");
  expect_error_file(path, {"invalid glTF"});
}

TEST_F(Malformed, GlbWithBadMagic) {
  std::string path = dir_ + "/bad.glb";
  test::write_text(path, "NOPE0000000000000000");
  expect_error_file(path, {"bad magic"});
}

TEST_F(Malformed, TruncatedGlb) {
  std::string src = test::shared_scene("teapot.glb");
  if (src.empty()) src = std::string(HRPP_SOURCE_DIR) + "/scenes/cornell_box.glb";
  std::ifstream in(src, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::string path = dir_ + "/truncated.glb";
  test::write_text(path, bytes.substr(0, bytes.size() / 2));
  expect_error_file(path, {"invalid glTF"});
}

TEST_F(Malformed, IndexOutOfRange) {
  auto j = test::minimal_gltf({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 7});
  expect_error(j, {"index 7", "out of range", "3 vertices"});
}

TEST_F(Malformed, AccessorOfTheWrongType) {
  auto j = good();
  j["accessors"][0]["type"] = "VEC2";
  j["accessors"][0]["count"] = 4;
  expect_error(j, {"POSITION accessor 0", "FLOAT VEC3"});
  auto k = good();
  k["accessors"][1]["componentType"] = 5126;  // float indices
  expect_error(k, {"indices accessor 1", "SCALAR unsigned"});
}

TEST_F(Malformed, AccessorIndexOutOfRange) {
  auto j = good();
  j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9;
  expect_error(j, {"accessor"});
}

TEST_F(Malformed, NaNAndInfiniteVertex) {
  for (float bad : {std::nanf(""), std::numeric_limits<float>::infinity()}) {
    auto j = test::minimal_gltf({0, 0, 0, 1, bad, 0, 0, 1, 0}, {0, 1, 2});
    j["accessors"][0].erase("min");
    j["accessors"][0].erase("max");
    expect_error(j, {"vertex 1", "NaN or infinite"});
  }
}

TEST_F(Malformed, NonTriangleModeIsRefused) {
  auto j = good();
  j["meshes"][0]["primitives"][0]["mode"] = 1;
  expect_error(j, {"mode 1", "LINES", "not a triangle mode"});
}

TEST_F(Malformed, StripsAndFansAreConverted) {
  auto j = test::minimal_gltf({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 1, 2, 0}, {0, 1, 2, 3, 4});
  j["meshes"][0]["primitives"][0]["mode"] = 5;
  std::string path = dir_ + "/strip.gltf";
  test::write_text(path, j.dump());
  Scene s = load_scene(path);
  ASSERT_EQ(s.triangles.size(), 3u);
  // glTF strip order: (0,1,2), (2,1,3), (2,3,4): consistent winding, all facing +z or all -z.
  for (const auto& t : s.triangles) EXPECT_GT(t.normal().z * s.triangles[0].normal().z, 0.f);
  j["meshes"][0]["primitives"][0]["mode"] = 6;
  test::write_text(path, j.dump());
  EXPECT_EQ(load_scene(path).triangles.size(), 3u);
}

TEST_F(Malformed, TrianglesNotMultipleOfThree) {
  auto j = test::minimal_gltf({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 0});
  expect_error(j, {"not a multiple of 3"});
}

TEST_F(Malformed, MaterialIndexOutOfRange) {
  auto j = good();
  j["meshes"][0]["primitives"][0]["material"] = 5;
  expect_error(j, {"material index 5", "out of range"});
}

TEST_F(Malformed, BufferViewPastTheBuffer) {
  auto j = good();
  j["bufferViews"][1]["byteLength"] = 4000;
  expect_error(j, {});  // tinygltf or our check, either names the file
}

TEST_F(Malformed, NodeCycle) {
  auto j = good();
  j["nodes"][0]["children"] = {0};
  expect_error(j, {});
}

TEST_F(Malformed, NoTriangles) {
  auto j = good();
  j["scenes"][0]["nodes"] = nlohmann::json::array();
  expect_error(j, {"no triangles"});
}

TEST_F(Malformed, BadLightIndex) {
  auto j = good();
  j["extensionsUsed"] = {"KHR_lights_punctual"};
  j["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 1.0}}};
  j["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 3}}}}}});
  j["scenes"][0]["nodes"] = {0, 1};
  expect_error(j, {"light index 3", "out of range"});
}

TEST_F(Malformed, CameraSidecar) {
  std::string path = dir_ + "/s.gltf";
  test::write_text(path, good().dump());
  test::write_text(dir_ + "/s.camera.json", "{ not json");
  try {
    load_scene(path);
    ADD_FAILURE() << "no error for a bad sidecar";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("s.camera.json: bad JSON"), std::string::npos) << e.what();
  }
  test::write_text(dir_ + "/s.camera.json", R"({"eye":[0,0,5],"target":[0,0,0],"up":[0,1,0]})");
  try {
    load_scene(path);
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("fov_y_deg"), std::string::npos) << e.what();
  }
  test::write_text(dir_ + "/s.camera.json",
                   R"({"eye":[0,0,5],"target":[0,0,0],"up":[0,1,0],"fov_y_deg":40,"aspect":2})");
  Scene s = load_scene(path);
  EXPECT_EQ(s.camera.source, "sidecar s.camera.json");
  EXPECT_EQ(s.camera.fov_y_deg, 40.f);
  EXPECT_EQ(s.camera.aspect, 2.f);
}

TEST_F(Malformed, NodeTransformsAreApplied) {
  auto j = good();
  j["nodes"][0]["translation"] = {10, 0, 0};
  j["nodes"][0]["scale"] = {2, 2, 2};
  std::string path = dir_ + "/t.gltf";
  test::write_text(path, j.dump());
  Scene s = load_scene(path);
  EXPECT_EQ(s.triangles[0].v1, Vec3(12, 0, 0));
  // A mirroring transform keeps the geometric normal's facing (winding swapped back).
  j["nodes"][0]["scale"] = {-1, 1, 1};
  test::write_text(path, j.dump());
  Scene m = load_scene(path);
  EXPECT_GT(m.triangles[0].normal().z, 0.f);
}

// ---- The valid range (docs/bvh.md, "Valid range") -------------------------------------------

std::vector<float> square(float h, float z) { return {-h, -h, z, h, -h, z, h, h, z, -h, h, z}; }

TEST_F(Malformed, GeometryOutsideTheValidRangeIsRejected) {
  // Squares of half-size 1e12 at distance 1e14, 1e13 at 1e12, 1e17 at 1e6,
  // and coordinates of 1e19 (whose default camera sat at 3.7e19).
  struct Case {
    float h, z;
    const char* value;  // the first offending coordinate, as the message prints it
  };
  for (const Case& c :
       {Case{1e12f, 1e14f, "-9.99999996e+11"}, Case{1e13f, 1e12f, "-9.99999983e+12"},
        Case{1e17f, 1e6f, "-9.99999984e+16"}, Case{1e19f, 0, "-9.99999998e+18"}}) {
    auto j = test::minimal_gltf(square(c.h, c.z), {0, 1, 2, 0, 2, 3});
    j["nodes"][0]["name"] = "far";
    expect_error(j, {"node 0 (far) mesh 0 primitive 0: vertex 0 has the world coordinate", c.value,
                     "outside the traceable range |x| <= 1.37438953e+11"});
  }
  // The node transform counts: in range in the file, out of range in the world.
  auto t = test::minimal_gltf(square(1, 0), {0, 1, 2, 0, 2, 3});
  t["nodes"][0]["translation"] = {0, 0, 2e11};
  expect_error(t, {"node 0", "vertex 0 has the world coordinate 1.99999996e+11"});
}

TEST_F(Malformed, TheValidRangeIsAccepted) {
  // Vertices at exactly +-kMaxSceneCoordinate load, and their default camera is inside the range
  // of ray origins (a square of half-size g at z = g puts it farthest: z = (1 + 2.613 sqrt(2)) g);
  // one float step further is rejected.
  const float g = kMaxSceneCoordinate;
  std::string path = dir_ + "/edge.gltf";
  test::write_text(path, test::minimal_gltf(square(g, g), {0, 1, 2, 0, 2, 3}).dump());
  Scene s = load_scene(path);
  EXPECT_EQ(s.camera.source, "computed default");
  EXPECT_LE(max_abs(s.camera.eye), kMaxRayOrigin);
  EXPECT_GT(max_abs(s.camera.eye), 4.6f * g);
  expect_error(
      test::minimal_gltf(square(std::nextafter(kMaxSceneCoordinate, kInf), 0), {0, 1, 2, 0, 2, 3}),
      {"vertex 0", "outside the traceable range"});
}

TEST_F(Malformed, TrianglesBelowTheSmallestAreaAreRejected) {
  // Twice the area 1e-40: never hit by the float test (ValidRange.TrianglesBelowTheSmallestArea-
  // AreNeverHit). Zero-area triangles stay accepted (kept, never hit).
  auto j = test::minimal_gltf({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1e-20f, 0, 0, 0, 1e-20f, 0},
                              {0, 1, 2, 3, 4, 5});
  expect_error(j, {"node 0", "mesh 0 primitive 0: triangle 1 has twice the area 9.99999937e-41",
                   "below the smallest traceable 7.88860905e-31"});
  std::string path = dir_ + "/flat.gltf";
  test::write_text(path, test::minimal_gltf({0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 0, 5, 5, 0, 6, 6, 0},
                                            {0, 1, 2, 3, 4, 5})
                             .dump());
  EXPECT_EQ(load_scene(path).degenerate_triangles, 1u);
}

TEST_F(Malformed, CamerasAndLightsOutsideTheValidRangeAreRejected) {
  std::string path = dir_ + "/s.gltf";
  test::write_text(path, good().dump());
  test::write_text(dir_ + "/s.camera.json",
                   R"({"eye":[0,0,2e12],"target":[0,0,0],"up":[0,1,0],"fov_y_deg":40})");
  expect_error_file(path, {"camera (sidecar s.camera.json): the eye coordinate 1.99999999e+12",
                           "outside the traceable range |x| <= 1.09951163e+12"});
  std::filesystem::remove(dir_ + "/s.camera.json");
  auto j = good();
  j["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"name", "far"}}};
  j["extensionsUsed"] = {"KHR_lights_punctual"};
  j["nodes"].push_back(
      {{"translation", {0, -3e12, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  j["scenes"][0]["nodes"].push_back(1);
  expect_error(j, {"node 1: light 'far' has the position coordinate -3.00000005e+12", "outside"});
}

}  // namespace
}  // namespace hrpp
