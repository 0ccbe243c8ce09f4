#include "hrpp/report/render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBIW_WINDOWS_UTF8 0
#include <stb/stb_easy_font.h>
#include <stb/stb_image_write.h>

#include "hrpp/util/atomic_file.h"

namespace hrpp {

// ---- images -----------------------------------------------------------------------------------

Image::Image(int w, int h, Vec3 fill) : width(w), height(h), rgb(size_t(w) * h * 3) {
  fill_rect(0, 0, w, h, fill);
}

void Image::set(int x, int y, const Vec3& c) {
  if (x < 0 || y < 0 || x >= width || y >= height) return;
  uint8_t* p = &rgb[(size_t(y) * width + x) * 3];
  for (int i = 0; i < 3; ++i)
    p[i] = static_cast<uint8_t>(std::lround(255.f * std::clamp(c[i], 0.f, 1.f)));
}

Vec3 Image::get(int x, int y) const {
  const uint8_t* p = &rgb[(size_t(y) * width + x) * 3];
  return Vec3(p[0], p[1], p[2]) / 255.f;
}

void Image::fill_rect(int x0, int y0, int x1, int y1, const Vec3& c) {
  for (int y = std::max(0, y0); y < std::min(height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(width, x1); ++x) set(x, y, c);
}

void Image::text(int x, int y, const std::string& s, const Vec3& c, int scale) {
  std::vector<char> txt(s.begin(), s.end());
  txt.push_back('\0');
  std::vector<char> buf(270 * (s.size() + 1) + 1024);
  const int quads =
      stb_easy_font_print(0, 0, txt.data(), nullptr, buf.data(), static_cast<int>(buf.size()));
  struct Vertex {
    float x, y, z;
    uint8_t color[4];
  };
  static_assert(sizeof(Vertex) == 16);
  const Vertex* v = reinterpret_cast<const Vertex*>(buf.data());
  for (int q = 0; q < quads; ++q) {
    const Vertex* k = v + 4 * q;
    const float qx0 = std::min({k[0].x, k[1].x, k[2].x, k[3].x});
    const float qx1 = std::max({k[0].x, k[1].x, k[2].x, k[3].x});
    const float qy0 = std::min({k[0].y, k[1].y, k[2].y, k[3].y});
    const float qy1 = std::max({k[0].y, k[1].y, k[2].y, k[3].y});
    fill_rect(x + static_cast<int>(std::floor(qx0 * scale)),
              y + static_cast<int>(std::floor(qy0 * scale)),
              x + static_cast<int>(std::ceil(qx1 * scale)),
              y + static_cast<int>(std::ceil(qy1 * scale)), c);
  }
}

int text_width(const std::string& s) {
  std::vector<char> txt(s.begin(), s.end());
  txt.push_back('\0');
  return stb_easy_font_width(txt.data());
}

namespace {

/// Writes BYTES to PATH through a temporary file (hrpp/util/atomic_file.h). Throws RenderError.
void write_output(const std::string& path, std::string_view bytes) {
  try {
    write_file_atomic(path, bytes);
  } catch (const AtomicFileError& e) {
    throw RenderError(e.what());
  }
}

}  // namespace

void write_png(const std::string& path, const Image& img) {
  // Encoded in memory and written here, because stbi_write_png ignores write errors.
  std::vector<unsigned char> png;
  auto append = [](void* ctx, void* data, int size) {
    auto* v = static_cast<std::vector<unsigned char>*>(ctx);
    v->insert(v->end(), static_cast<unsigned char*>(data),
              static_cast<unsigned char*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &png, img.width, img.height, 3, img.rgb.data(),
                              img.width * 3))
    throw RenderError(path + ": cannot encode the PNG image");
  write_output(path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

float srgb_encode(float l) {
  l = std::clamp(l, 0.f, 1.f);
  return l <= 0.0031308f ? 12.92f * l : 1.055f * std::pow(l, 1.f / 2.4f) - 0.055f;
}

// ---- shaded image -----------------------------------------------------------------------------

nlohmann::json ShadeInfo::to_json() const {
  return {{"exposure", exposure},
          {"lit_fraction", lit_fraction},
          {"samples", samples},
          {"surface_samples", surface_samples},
          {"emitter_samples", emitter_samples},
          {"background_samples", background_samples}};
}

Image shade(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt, ShadeInfo* info) {
  constexpr float kAmbient = 0.08f;               // display units, times the base colour
  const Vec3 kBackground(0.02f, 0.025f, 0.045f);  // linear; a dark blue-grey
  constexpr float kInvPi = 0.318309886f;
  int w, h;
  workload_resolution(scene, opt, &w, &h);
  const int spp = std::max(1, opt.spp);
  const size_t n = size_t(w) * h;
  std::vector<Vec3> lit(n, Vec3(0)), ambient(n, Vec3(0)), fixed(n, Vec3(0));
  std::vector<uint8_t> has_surface(n, 0);
  ShadeInfo si;
  uint64_t lit_samples = 0;
  const SceneLights lights(scene);
  std::vector<LightSample> ls;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint32_t pixel = uint32_t(y) * uint32_t(w) + uint32_t(x);
      for (int s = 0; s < spp; ++s) {
        ++si.samples;
        const Ray r = camera_ray(scene.camera, w, h, x, y, s, spp, opt.seed);
        Counters c;
        const Hit hit = closest_hit(bvh, r, &c);
        if (!hit.hit()) {
          ++si.background_samples;
          fixed[pixel] += kBackground;
          continue;
        }
        const SurfacePoint sp = surface_point(scene, r, hit);
        const Material& m = *sp.material;
        if (m.is_emissive()) {
          ++si.emitter_samples;
          const Vec3 e = m.emission();
          fixed[pixel] += e / std::max({e.x, e.y, e.z});
          continue;
        }
        ++si.surface_samples;
        has_surface[pixel] = 1;
        const Vec3 base(m.base_color);
        const Vec3 o = offset_ray_origin(sp.p, sp.n);
        lights.sample(o, sp.n, opt.seed, camera_key(pixel, uint32_t(s)), &ls);
        Vec3 e(0);
        bool reached = false;
        for (const LightSample& l : ls) {
          Ray sr;
          sr.org = o;
          sr.dir = l.dir;
          sr.tfar = l.tfar;
          if (any_hit(bvh, sr, &c).hit()) continue;
          e += l.irradiance * glm::dot(l.dir, sp.n);
          reached = true;
        }
        lit_samples += reached;
        lit[pixel] += base * kInvPi * e;
        // Ambient, shaded by the angle to the viewer so that unlit geometry keeps its shape.
        ambient[pixel] +=
            kAmbient * (0.25f + 0.75f * std::fabs(glm::dot(sp.n, glm::normalize(r.dir)))) * base;
      }
    }
  // Exposure: the 95th percentile of the lit pixels' luminance maps to 0.85.
  std::vector<float> lum;
  for (size_t i = 0; i < n; ++i) {
    const float l = glm::dot(lit[i] / float(spp), Vec3(0.2126f, 0.7152f, 0.0722f));
    if (has_surface[i] && l > 0) lum.push_back(l);
  }
  float exposure = 0;
  if (!lum.empty()) {
    auto k = lum.begin() + static_cast<long>(0.95 * (lum.size() - 1));
    std::nth_element(lum.begin(), k, lum.end());
    exposure = 0.85f / *k;
  }
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const Vec3 c = (exposure * lit[i] + ambient[i] + fixed[i]) / float(spp);
      img.set(x, y, Vec3(srgb_encode(c.x), srgb_encode(c.y), srgb_encode(c.z)));
    }
  si.exposure = exposure;
  si.lit_fraction = si.surface_samples ? double(lit_samples) / si.surface_samples : 0;
  if (info) *info = si;
  return img;
}

// ---- predictor per pixel ----------------------------------------------------------------------

PixelStats predictor_pixels(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                            Predictor* pred) {
  PixelStats ps;
  workload_resolution(scene, opt, &ps.width, &ps.height);
  ps.spp = std::max(1, opt.spp);
  const size_t n = size_t(ps.width) * ps.height;
  ps.baseline_interior.assign(n, 0);
  ps.hrpp_interior.assign(n, 0);
  ps.rays.assign(n, 0);
  ps.failed.assign(n, 0);
  generate_rays(scene, bvh, opt, [&](const RayRecord& r, const Hit*) {
    const RayResult res = pred->process(r);
    ps.rays[r.pixel]++;
    ps.baseline_interior[r.pixel] += res.base_counters.interior_tests;
    ps.hrpp_interior[r.pixel] += res.hrpp_counters.interior_tests;
    ps.failed[r.pixel] += res.predicted && !res.verified;
  });
  return ps;
}

// ---- heat maps --------------------------------------------------------------------------------

Vec3 colormap(const std::string& name, double t) {
  // viridis sampled at 0, 0.1, ..., 1 (matplotlib); coolwarm's ends and middle (Moreland 2009).
  static const Vec3 viridis[] = {
      {0.267, 0.005, 0.329}, {0.283, 0.141, 0.458}, {0.254, 0.265, 0.530}, {0.207, 0.372, 0.553},
      {0.164, 0.471, 0.558}, {0.128, 0.567, 0.551}, {0.135, 0.659, 0.518}, {0.267, 0.749, 0.441},
      {0.478, 0.821, 0.318}, {0.741, 0.873, 0.150}, {0.993, 0.906, 0.144}};
  static const Vec3 coolwarm[] = {{0.230, 0.299, 0.754},
                                  {0.552, 0.690, 0.996},
                                  {0.865, 0.865, 0.865},
                                  {0.958, 0.603, 0.482},
                                  {0.706, 0.016, 0.150}};
  const bool cw = name == "coolwarm";
  const Vec3* pts = cw ? coolwarm : viridis;
  const int count = cw ? 5 : 11;
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * (count - 1);
  const int i = std::min(count - 2, static_cast<int>(t));
  return glm::mix(pts[i], pts[i + 1], static_cast<float>(t - i));
}

nlohmann::json HeatMap::to_json() const {
  return {{"title", title}, {"colormap", colormap}, {"range", {lo, hi}},
          {"min", min},     {"mean", mean},         {"max", max}};
}

namespace {

std::string label(double v, bool percent) {
  char b[64];
  if (percent)
    std::snprintf(b, sizeof b, "%.0f%%", 100 * v);
  else if (std::fabs(v) >= 100 || v == std::floor(v))
    std::snprintf(b, sizeof b, "%.0f", v);
  else
    std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

}  // namespace

Image heat_map_image(const std::vector<double>& values, int w, int h, HeatMap* map) {
  const Vec3 kNoData(0.5f), kPanel(0.12f), kText(0.95f);
  double sum = 0, mn = INFINITY, mx = -INFINITY;
  size_t count = 0;
  for (double v : values)
    if (std::isfinite(v)) {
      sum += v;
      mn = std::min(mn, v);
      mx = std::max(mx, v);
      ++count;
    }
  map->min = count ? mn : 0;
  map->max = count ? mx : 0;
  map->mean = count ? sum / count : 0;
  const int scale = w >= 640 ? 2 : 1;
  const int canvas_w = std::max(w, 360 * scale), legend_h = 52 * scale;
  Image img(canvas_w, h + legend_h, kPanel);
  const double span = map->hi > map->lo ? map->hi - map->lo : 1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double v = values[size_t(y) * w + x];
      img.set(x, y, std::isfinite(v) ? colormap(map->colormap, (v - map->lo) / span) : kNoData);
    }
  // Legend: title, colour bar, the bar's end values, then min / mean / max of the data.
  const int pad = 6 * scale, y0 = h + 4 * scale;
  img.text(pad, y0, map->title, kText, scale);
  const int bar_y = y0 + 12 * scale, bar_h = 10 * scale, bar_x0 = pad, bar_x1 = canvas_w - pad;
  for (int x = bar_x0; x < bar_x1; ++x)
    img.fill_rect(x, bar_y, x + 1, bar_y + bar_h,
                  colormap(map->colormap, double(x - bar_x0) / std::max(1, bar_x1 - bar_x0 - 1)));
  const int ly = bar_y + bar_h + 3 * scale;
  const std::string lo = label(map->lo, map->percent), hi = label(map->hi, map->percent);
  img.text(bar_x0, ly, lo, kText, scale);
  img.text(bar_x1 - text_width(hi) * scale, ly, hi, kText, scale);
  const std::string stats =
      "min " + label(map->min, map->percent) + "   mean " + label(map->mean, map->percent) +
      "   max " + label(map->max, map->percent) + (count < values.size() ? "   grey: no data" : "");
  img.text((canvas_w - text_width(stats) * scale) / 2, ly + 11 * scale, stats, kText, scale);
  return img;
}

// ---- everything -------------------------------------------------------------------------------

RenderOutput render_all(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                        const PredictorConfig& cfg, const std::string& dir,
                        const nlohmann::json& tool) {
  namespace fs = std::filesystem;
  RenderOutput out;
  auto save = [&](const std::string& name, const Image& img) {
    const std::string path = (fs::path(dir) / name).string();
    write_png(path, img);
    out.files.push_back(path);
    return path;
  };
  ShadeInfo si;
  save("shaded.png", shade(scene, bvh, opt, &si));

  Predictor pred(bvh, cfg);
  const PixelStats ps = predictor_pixels(scene, bvh, opt, &pred);
  const size_t n = ps.rays.size();
  std::vector<double> work(n), skipped(n), failed(n);
  for (size_t i = 0; i < n; ++i) {
    work[i] = double(ps.baseline_interior[i]) / ps.spp;
    skipped[i] = ps.baseline_interior[i]
                     ? 1.0 - double(ps.hrpp_interior[i]) / double(ps.baseline_interior[i])
                     : NAN;
    failed[i] = ps.rays[i] ? double(ps.failed[i]) / ps.rays[i] : NAN;
  }
  HeatMap mw{.title = "baseline interior-node tests per camera sample (all its rays)"};
  std::vector<double> sorted = work;  // colour bar up to the 99th percentile (outliers clamp)
  std::nth_element(sorted.begin(), sorted.begin() + (n - 1) * 99 / 100, sorted.end());
  mw.hi = std::max(1.0, sorted[(n - 1) * 99 / 100]);
  HeatMap ms{.title = "interior-node tests skipped: 1 - HRPP / baseline (red saves, blue costs)",
             .colormap = "coolwarm",
             .lo = -1,
             .hi = 1,
             .percent = true};
  HeatMap mf{.title = "mispredicted: rays whose prediction failed / rays", .percent = true};
  nlohmann::json maps = nlohmann::json::object();
  for (auto [name, values, map] :
       {std::tuple{"work.png", &work, &mw}, std::tuple{"skipped.png", &skipped, &ms},
        std::tuple{"mispredicted.png", &failed, &mf}}) {
    save(name, heat_map_image(*values, ps.width, ps.height, map));
    maps[name] = map->to_json();
  }
  nlohmann::json pj = pred.to_json();
  if (!tool.is_null()) out.summary["tool"] = tool;
  out.summary.update({{"scene", scene.path},
                      {"workload", workload_json(scene, opt)},
                      {"shaded", si.to_json()},
                      {"maps", maps},
                      {"predictor", pj["config"]},
                      {"skipped_interior_fraction", pred.total().skipped_interior_fraction()},
                      {"by_kind", pj["by_kind"]}});
  const std::string jpath = (fs::path(dir) / "render.json").string();
  write_output(jpath, out.summary.dump(2) + "\n");
  out.files.push_back(jpath);
  return out;
}

}  // namespace hrpp
