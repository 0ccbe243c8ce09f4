// Pictures (hrpp render): the PNG files, the direct-lighting image's lit and unlit parts, the
// heat maps' values, colours and legend.
#include "hrpp/report/render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "hrpp/report/spec_image.h"
#include "hrpp/timing/cost_model.h"
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
  ASSERT_EQ(out.files.size(), 6u);
  int w, h;
  for (const char* f :
       {"shaded.png", "net_cycles.png", "work.png", "skipped.png", "mispredicted.png"}) {
    ASSERT_TRUE(png_size(dir + "/" + f, &w, &h)) << f;
    EXPECT_EQ(w, 480) << f << ": a legend band wide enough for its text";
    EXPECT_GT(h, 40 * 5 + 60) << f << ": the image (5x) and the legend band";
  }
  const auto& j = out.summary;
  EXPECT_EQ(j["workload"]["resolution"], nlohmann::json({48, 40}));
  EXPECT_GT(j["maps"]["work.png"]["max"].get<double>(), 0);
  EXPECT_LE(j["maps"]["mispredicted.png"]["max"].get<double>(), 1);
  EXPECT_TRUE(j["by_kind"].contains("shadow"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/render.json"));
  // Every picture's meaning; the captions name the scene, the workload and the predictor.
  for (const char* f :
       {"shaded.png", "net_cycles.png", "work.png", "skipped.png", "mispredicted.png"})
    EXPECT_FALSE(j["pictures"][f].get<std::string>().empty()) << f;
  EXPECT_NE(j["caption"][0].get<std::string>().find("cornell_box.glb: 48x40, 1 spp"),
            std::string::npos);
  EXPECT_NE(j["caption"][1].get<std::string>().find("table unbounded"), std::string::npos);
  // The net-cycle heat map: the cost model's cycles per pixel, adding up to the totals.
  const auto& nc = j["net_cycles"];
  const double saved = nc["baseline_cycles"].get<double>() - nc["hrpp_cycles"].get<double>();
  EXPECT_DOUBLE_EQ(nc["saved_cycles"].get<double>(), saved);
  EXPECT_NEAR(j["maps"]["net_cycles.png"]["mean"].get<double>() * 48 * 40, saved,
              1e-6 * std::fabs(nc["baseline_cycles"].get<double>()));
  EXPECT_EQ(nc["saves_time"].get<bool>(), saved > 0);
  const auto range = j["maps"]["net_cycles.png"]["range"];
  EXPECT_EQ(range[0].get<double>(), -range[1].get<double>()) << "centred on 0";
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

TEST(Render, NetCyclesPerPixelAddUpToTheCostModelsTotals) {
  // Prediction saves time on some pixels and costs it on others (the lookup on every ray).
  Scene s = load_scene(own("cornell_box.glb"));
  Bvh bvh = build_bvh(s.triangles);
  WorkloadOptions wo;
  wo.width = wo.height = 96;
  Predictor pred(bvh, default_predictor(s, bvh));
  const PixelStats ps = predictor_pixels(s, bvh, wo, &pred);
  const CycleCost total = cycle_cost(pred.total(), CostModel{});
  double base = 0, hrpp = 0;
  int costs = 0, saves = 0;
  for (size_t i = 0; i < ps.rays.size(); ++i) {
    base += ps.baseline_cycles[i];
    hrpp += ps.hrpp_cycles[i];
    costs += ps.hrpp_cycles[i] > ps.baseline_cycles[i];
    saves += ps.hrpp_cycles[i] < ps.baseline_cycles[i];
  }
  EXPECT_NEAR(base, total.baseline, 1e-9 * total.baseline);
  EXPECT_NEAR(hrpp, total.hrpp, 1e-9 * total.hrpp);
  EXPECT_GT(costs, 0) << "the lookup costs every pixel whose rays were not helped";
  EXPECT_GT(saves, 0);
}

TEST(Render, HeatMapValuesColoursAndLegend) {
  std::vector<double> v = {0, 1, 2, 3, NAN, 5};
  HeatMap m{.title = "test", .lo = 0, .hi = 5};
  LegendLayout lay;
  const Image img = heat_map_image(v, 3, 2, &m, {"scene x.glb"}, &lay);
  EXPECT_EQ(m.min, 0);
  EXPECT_EQ(m.max, 5);
  EXPECT_DOUBLE_EQ(m.mean, 11.0 / 5);
  const int k = display_scale(3, 2);
  EXPECT_EQ(k, 85) << "small pictures are enlarged";
  EXPECT_EQ(img.width, 480);
  EXPECT_EQ(lay.band_y, 2 * k);
  EXPECT_EQ(lay.x0, (480 - 3 * k) / 2);
  auto at = [&](int x, int y) { return img.get(lay.x0 + x * k + k / 2, y * k + k / 2); };
  EXPECT_LT(glm::length(at(1, 1) - Vec3(0.5f)), 0.01f) << "no data: grey";
  EXPECT_LT(glm::length(at(0, 0) - colormap("viridis", 0)), 0.01f);
  EXPECT_LT(glm::length(at(2, 1) - colormap("viridis", 1)), 0.01f);
  // The legend holds text (light pixels) and the colour bar.
  int light = 0;
  for (int y = lay.band_y; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) light += img.get(x, y).r > 0.9f && img.get(x, y).g > 0.9f;
  EXPECT_GT(light, 20);
  EXPECT_LT(glm::length(colormap("coolwarm", 0.5) - Vec3(0.865f)), 0.01f);
  EXPECT_GT(colormap("coolwarm", 1).r, colormap("coolwarm", 0).r);
  EXPECT_NEAR(srgb_encode(1.f), 1.f, 1e-6f);
  EXPECT_NEAR(srgb_encode(0.18f), 0.461f, 1e-3f);
}

}  // namespace
}  // namespace hrpp

namespace hrpp {
namespace {

/// The rows of IMG from Y0 on that hold text of colour C (at least one pixel of it).
int text_rows(const Image& img, int y0, Vec3 c) {
  int rows = 0;
  for (int y = y0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (glm::length(img.get(x, y) - c) < 0.01f) {
        ++rows;
        break;
      }
  return rows;
}

TEST(Render, LegendCompleteAtAnySize) {
  // A long title and caption wrap inside the band; nothing is drawn past its right edge, and the
  // band is as wide and its text as large at 8x8 as at 128x128 (the picture is enlarged).
  const std::string title =
      "net cycles saved per pixel by the cost model: baseline - HRPP cycles of the pixel's rays "
      "(all kinds); red: prediction saves, blue: it costs";
  const std::vector<std::string> caption = {
      "scene teapot.glb: 8x8, 1 spp, seed 1, depth 2; 150 rays (primary 64, shadow 66, ao 20)",
      "predictor: preset rtl-primary: hash improved (origin 5 bits, cell 2^-1, dir 3 bits concat), "
      "key 24 bits, table 128x8 (K=2, 12-bit node ids, 4864 bytes), go-up 0, mode closest-exact"};
  for (int n : {8, 32, 128, 512}) {
    std::vector<double> v(size_t(n) * n);
    for (size_t i = 0; i < v.size(); ++i) v[i] = double(i % 7) - 3;
    HeatMap m{.title = title, .colormap = "coolwarm", .lo = -3, .hi = 3, .units = "cycles"};
    LegendLayout lay;
    const Image img = heat_map_image(v, n, n, &m, caption, &lay);
    EXPECT_GE(img.width, 480) << n;
    EXPECT_GE(n * display_scale(n, n), 256) << n;
    // Every wrapped line fits: no text pixel in the right margin.
    const int pad = 6 * lay.text_scale;
    for (int y = lay.band_y; y < img.height; ++y)
      for (int x = img.width - pad + 1; x < img.width; ++x)
        ASSERT_GT(glm::length(img.get(x, y) - Vec3(0.95f)), 0.01f) << n << ": text at " << x;
    // The caption's two lines wrap into at least three, all drawn (dim text rows).
    EXPECT_GE(text_rows(img, lay.band_y, Vec3(0.7f)), 3 * 5) << n;
  }
  for (const std::string& l : wrap_text(caption[1], 200)) EXPECT_LE(text_width(l), 200) << l;
  EXPECT_EQ(wrap_text("a b", 1000), std::vector<std::string>{"a b"});
}

}  // namespace
}  // namespace hrpp

namespace hrpp {
namespace {

TEST(Render, SpecCompareNamesItsRunAndExplainsItsPanels) {
  const std::string dir = test::temp_dir("spec_compare");
  Scene s = load_scene(own("cornell_box.glb"));
  SpecImage img(s, 4, 2, 1, "preset test-config: hash improved");
  RayRecord r;
  RayResult res;
  for (uint32_t p = 0; p < 8; ++p) {
    r.pixel = p;
    img.add(r, res);
  }
  const auto j = img.finish(dir);
  int w, h;
  ASSERT_TRUE(png_size(dir + "/spec_compare.png", &w, &h));
  EXPECT_EQ(w, 3 * 4 * 40 + 2 * 6) << "three panels of 4x2 pixels, each enlarged to 160";
  EXPECT_GT(h, 2 * 40 + 14 + 8 * 12) << "the panels' names, the panels and the legend band";
  std::string legend;
  for (const auto& l : j["legend"]) legend += l.get<std::string>() + "\n";
  for (const char* want :
       {"1 exact: ", "2 speculative: ", "3 difference x8: ", "scene cornell_box.glb: 4x2, 1 spp",
        "predictor: preset test-config: hash improved"})
    EXPECT_NE(legend.find(want), std::string::npos) << want << " in\n" << legend;
}

}  // namespace
}  // namespace hrpp
