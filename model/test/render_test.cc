// Pictures (hrpp render): the PNG files, the direct-lighting image's lit and unlit parts, the
// heat maps' values, colours and legend.
#include "hrpp/report/render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "test_util.h"

namespace hrpp {
namespace {

std::string own(const std::string& name) {
  return std::string(HRPP_SOURCE_DIR) + "/scenes/" + name;
}

/// Width and height from a PNG's IHDR chunk; false when the file is not a PNG.
bool png_size(const std::string& path, int* w, int* h) {
  std::ifstream f(path, std::ios::binary);
  unsigned char b[24];
  if (!f.read(reinterpret_cast<char*>(b), 24)) return false;
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (std::memcmp(b, sig, 8) != 0 || std::memcmp(b + 12, "IHDR", 4) != 0) return false;
  *w = b[16] << 24 | b[17] << 16 | b[18] << 8 | b[19];
  *h = b[20] << 24 | b[21] << 16 | b[22] << 8 | b[23];
  return true;
}

PredictorConfig default_predictor(const Scene& s, const Bvh& bvh) {
  PredictorConfig c;  // hrpp predict's defaults: faithful hash, unbounded table, K = 1
  c.table.unbounded = true;
  c.table.nodes_per_entry = 1;
  c.hash.index_bits = 0;
  c.hash.origin_cell_exp = cell_exp_for(s.bounds, c.hash.origin_bits);
  c.table.node_bits = node_bits_for(bvh.nodes.size());
  c.table.key_bits = c.hash.key_bits();
  c.table.tag_bits = 0;
  return c;
}

TEST(Render, WritesTheShadedImageAndTheHeatMaps) {
  const std::string dir = test::temp_dir("render_all");
  Scene s = load_scene(own("cornell_box.glb"));
  Bvh bvh = build_bvh(s.triangles);
  WorkloadOptions wo;
  wo.width = 48;
  wo.height = 40;
  const RenderOutput out = render_all(s, bvh, wo, default_predictor(s, bvh), dir);
  ASSERT_EQ(out.files.size(), 5u);
  int w, h;
  ASSERT_TRUE(png_size(dir + "/shaded.png", &w, &h));
  EXPECT_EQ(w, 48);
  EXPECT_EQ(h, 40);
  for (const char* f : {"work.png", "skipped.png", "mispredicted.png"}) {
    ASSERT_TRUE(png_size(dir + "/" + f, &w, &h)) << f;
    EXPECT_EQ(w, 360) << "a legend wide enough for its text";
    EXPECT_EQ(h, 40 + 52) << "the image and the legend strip";
  }
  const auto& j = out.summary;
  EXPECT_EQ(j["workload"]["resolution"], nlohmann::json({48, 40}));
  EXPECT_GT(j["maps"]["work.png"]["max"].get<double>(), 0);
  EXPECT_LE(j["maps"]["mispredicted.png"]["max"].get<double>(), 1);
  EXPECT_TRUE(j["by_kind"].contains("shadow"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/render.json"));
  EXPECT_THROW(render_all(s, bvh, wo, default_predictor(s, bvh), dir + "/missing"), RenderError);
}

TEST(Render, ShadedImageShowsLitAndShadowedSurfaces) {
  Scene s = load_scene(own("cornell_box.glb"));
  Bvh bvh = build_bvh(s.triangles);
  WorkloadOptions wo;
  wo.width = wo.height = 64;
  ShadeInfo info;
  const Image img = shade(s, bvh, wo, &info);
  EXPECT_GT(info.exposure, 0);
  EXPECT_GT(info.lit_fraction, 0.3);   // the ceiling light reaches most of the box ...
  EXPECT_LT(info.lit_fraction, 0.95);  // ... but not the ceiling itself nor the blocks' shadows
  EXPECT_GT(info.emitter_samples, 0u);
  // The light (top centre) is drawn in its own colour, brighter than the ceiling beside it.
  float brightest = 0;
  for (int x = 24; x < 40; ++x)
    for (int y = 0; y < 12; ++y) brightest = std::max(brightest, img.get(x, y).r);
  EXPECT_GT(brightest, 0.95f);
  // A scene without lights: nothing lit, the ambient term still shows the geometry.
  Scene dark = test::scene_from_triangles(test::random_soup(200, 0.2f, 3));
  Bvh dbvh = build_bvh(dark.triangles);
  const Image d = shade(dark, dbvh, wo, &info);
  EXPECT_EQ(info.lit_fraction, 0);
  EXPECT_GT(info.surface_samples, 0u);
}

TEST(Render, HeatMapValuesColoursAndLegend) {
  std::vector<double> v = {0, 1, 2, 3, NAN, 5};
  HeatMap m{.title = "test", .lo = 0, .hi = 5};
  const Image img = heat_map_image(v, 3, 2, &m);
  EXPECT_EQ(m.min, 0);
  EXPECT_EQ(m.max, 5);
  EXPECT_DOUBLE_EQ(m.mean, 11.0 / 5);
  EXPECT_EQ(img.width, 360);
  EXPECT_EQ(img.height, 2 + 52);
  EXPECT_LT(glm::length(img.get(1, 1) - Vec3(0.5f)), 0.01f) << "no data: grey";
  EXPECT_LT(glm::length(img.get(0, 0) - colormap("viridis", 0)), 0.01f);
  EXPECT_LT(glm::length(img.get(2, 1) - colormap("viridis", 1)), 0.01f);
  // The legend holds text (light pixels) and the colour bar.
  int light = 0;
  for (int y = 2; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) light += img.get(x, y).r > 0.9f && img.get(x, y).g > 0.9f;
  EXPECT_GT(light, 20);
  EXPECT_LT(glm::length(colormap("coolwarm", 0.5) - Vec3(0.865f)), 0.01f);
  EXPECT_GT(colormap("coolwarm", 1).r, colormap("coolwarm", 0).r);
  EXPECT_NEAR(srgb_encode(1.f), 1.f, 1e-6f);
  EXPECT_NEAR(srgb_encode(0.18f), 0.461f, 1e-3f);
}

}  // namespace
}  // namespace hrpp
