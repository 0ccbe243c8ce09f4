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

#include "hrpp/timing/cost_model.h"
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

std::vector<std::string> wrap_text(const std::string& s, int max_width, int scale) {
  std::vector<std::string> lines;
  std::string line;
  auto fits = [&](const std::string& t) { return text_width(t) * scale <= max_width; };
  size_t i = 0;
  while (i < s.size()) {
    size_t j = s.find(' ', i);
    if (j == std::string::npos) j = s.size();
    std::string word = s.substr(i, j - i);
    i = j + 1;
    if (word.empty()) continue;
    const std::string joined = line.empty() ? word : line + " " + word;
    if (fits(joined)) {
      line = joined;
      continue;
    }
    if (!line.empty()) lines.push_back(line);
    line.clear();
    while (!fits(word) && word.size() > 1) {  // a word wider than the band: cut it
      size_t n = word.size() - 1;
      while (n > 1 && !fits(word.substr(0, n))) --n;
      lines.push_back(word.substr(0, n));
      word = word.substr(n);
    }
    line = word;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

int display_scale(int w, int h) { return std::max(1, 256 / std::max({1, w, h})); }

Image upscale(const Image& img, int k) {
  if (k <= 1) return img;
  Image out(img.width * k, img.height * k);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) out.set(x, y, img.get(x / k, y / k));
  return out;
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

Image shade(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt, ShadeInfo* info,
            const RowProgress& progress) {
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
      if (progress && x == w - 1) progress(uint64_t(y + 1) * w, n);
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
                            Predictor* pred, const RowProgress& progress) {
  PixelStats ps;
  workload_resolution(scene, opt, &ps.width, &ps.height);
  ps.spp = std::max(1, opt.spp);
  const size_t n = size_t(ps.width) * ps.height;
  ps.baseline_interior.assign(n, 0);
  ps.hrpp_interior.assign(n, 0);
  ps.rays.assign(n, 0);
  ps.failed.assign(n, 0);
  ps.baseline_cycles.assign(n, 0);
  ps.hrpp_cycles.assign(n, 0);
  const CostModel cost;
  const uint64_t samples = uint64_t(n) * ps.spp;
  uint64_t done = 0;
  generate_rays(scene, bvh, opt, [&](const RayRecord& r, const Hit*) {
    const RayResult res = pred->process(r);
    ps.rays[r.pixel]++;
    ps.baseline_interior[r.pixel] += res.base_counters.interior_tests;
    ps.hrpp_interior[r.pixel] += res.hrpp_counters.interior_tests;
    ps.failed[r.pixel] += res.predicted && !res.verified;
    // The ray's own statistics, as the predictor adds them up (classify), priced alone: the
    // per-pixel cycles add up to cycle_cost of the totals.
    PredictStats one;
    one.rays = 1;
    one.invalid_rays = res.invalid;
    one.baseline = res.base_counters;
    one.hrpp = res.hrpp_counters;
    if (res.predicted) (res.verified ? one.true_positive : one.false_positive) = 1;
    const CycleCost c = cycle_cost(one, cost);
    ps.baseline_cycles[r.pixel] += c.baseline;
    ps.hrpp_cycles[r.pixel] += c.hrpp;
    if (r.kind == RayKind::kPrimary && (++done & 0xFF) == 0 && progress) progress(done, samples);
  });
  if (progress) progress(samples, samples);
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
  return {{"title", title},    {"meaning", meaning}, {"units", units}, {"colormap", colormap},
          {"range", {lo, hi}}, {"min", min},         {"mean", mean},   {"max", max}};
}

namespace {

std::string label(double v, bool percent, bool sign = false) {
  char b[64];
  const char* plus = sign && v > 0 ? "+" : "";
  if (percent)
    std::snprintf(b, sizeof b, "%s%.0f%%", plus, 100 * v);
  else if (std::fabs(v) >= 100 || v == std::floor(v))
    std::snprintf(b, sizeof b, "%s%.0f", plus, v);
  else
    std::snprintf(b, sizeof b, "%s%.3g", plus, v);
  return b;
}

}  // namespace

Image with_legend(const Image& pic, const Legend& lg, LegendLayout* layout) {
  const Vec3 kPanel(0.12f), kText(0.95f), kDim(0.7f);
  const int s = pic.width >= 640 ? 2 : 1;
  const int canvas_w = std::max(pic.width, 480 * s);
  const int pad = 6 * s, line_h = 12 * s, text_w = canvas_w - 2 * pad;
  auto wrap_all = [&](const std::vector<std::string>& in) {
    std::vector<std::string> out;
    for (const std::string& l : in)
      for (std::string& w : wrap_text(l, text_w, s)) out.push_back(std::move(w));
    return out;
  };
  const std::vector<std::string> head = wrap_all(lg.head), body = wrap_all(lg.body),
                                 caption = wrap_all(lg.caption);
  const int bar_h = 10 * s, bar_block = lg.bar ? bar_h + 3 * s + line_h : 0;
  const int sep = caption.empty() ? 0 : 5 * s;
  const int band_h = 4 * s + int(head.size()) * line_h + bar_block + int(body.size()) * line_h +
                     sep + int(caption.size()) * line_h + 2 * s;
  Image img(canvas_w, pic.height + band_h, kPanel);
  const int x0 = (canvas_w - pic.width) / 2;
  for (int y = 0; y < pic.height; ++y)
    for (int x = 0; x < pic.width; ++x) img.set(x0 + x, y, pic.get(x, y));
  int y = pic.height + 4 * s;
  for (const std::string& l : head) {
    img.text(pad, y, l, kText, s);
    y += line_h;
  }
  if (const HeatMap* m = lg.bar) {
    const int bar_x0 = pad, bar_x1 = canvas_w - pad;
    for (int x = bar_x0; x < bar_x1; ++x)
      img.fill_rect(x, y, x + 1, y + bar_h,
                    colormap(m->colormap, double(x - bar_x0) / std::max(1, bar_x1 - bar_x0 - 1)));
    y += bar_h + 3 * s;
    const bool diverging = m->lo < 0 && m->hi > 0;
    std::string lo = label(m->lo, m->percent, diverging), hi = label(m->hi, m->percent, diverging);
    if (!m->lo_note.empty()) lo += " (" + m->lo_note + ")";
    if (!m->hi_note.empty()) hi = "(" + m->hi_note + ") " + hi;
    const int lo_w = text_width(lo) * s, hi_w = text_width(hi) * s;
    img.text(bar_x0, y, lo, kText, s);
    img.text(bar_x1 - hi_w, y, hi, kText, s);
    if (diverging) {  // 0 under its place on the bar, unless it would touch an end label
      const int zx = bar_x0 + int(std::lround((bar_x1 - bar_x0) * (0 - m->lo) / (m->hi - m->lo)));
      const int zw = text_width("0") * s;
      img.fill_rect(zx, y - 3 * s - bar_h / 2, zx + std::max(1, s / 2 + 1), y - 3 * s, kText);
      if (zx - zw / 2 > bar_x0 + lo_w + pad && zx + zw / 2 < bar_x1 - hi_w - pad)
        img.text(zx - zw / 2, y, "0", kText, s);
    }
    y += line_h;
  }
  for (const std::string& l : body) {
    img.text(pad, y, l, kText, s);
    y += line_h;
  }
  if (!caption.empty()) {
    img.fill_rect(pad, y + sep / 2 - 1, canvas_w - pad, y + sep / 2, kDim * 0.6f);
    y += sep;
  }
  for (const std::string& l : caption) {
    img.text(pad, y, l, kDim, s);
    y += line_h;
  }
  if (layout) *layout = {x0, s, pic.height};
  return img;
}

Image heat_map_image(const std::vector<double>& values, int w, int h, HeatMap* map,
                     const std::vector<std::string>& caption, LegendLayout* layout) {
  const Vec3 kNoData(0.5f);
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
  Image pic(w, h);
  const double span = map->hi > map->lo ? map->hi - map->lo : 1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double v = values[size_t(y) * w + x];
      pic.set(x, y, std::isfinite(v) ? colormap(map->colormap, (v - map->lo) / span) : kNoData);
    }
  Legend lg{.head = {map->title}, .bar = map, .caption = caption};
  if (!map->units.empty()) lg.body.push_back("colour: " + map->units);
  lg.body.push_back("min " + label(map->min, map->percent) + "   mean " +
                    label(map->mean, map->percent) + "   max " + label(map->max, map->percent) +
                    (count < values.size() ? "   grey: no data" : ""));
  return with_legend(upscale(pic, display_scale(w, h)), lg, layout);
}

// ---- everything -------------------------------------------------------------------------------

std::string config_caption(const PredictorConfig& cfg) {
  const TableConfig& t = cfg.table;
  const std::string table =
      t.unbounded ? "unbounded" : std::to_string(t.sets) + "x" + std::to_string(t.ways);
  std::string line = "hash " + std::string(hash_variant_name(cfg.hash.variant)) + ", table " +
                     table + " (K=" + std::to_string(t.nodes_per_entry) + "), go-up " +
                     std::to_string(cfg.go_up) + ", mode " + predict_mode_name(cfg.mode);
  if (cfg.any_hit_only) line += ", any-hit rays only";
  return line;
}

RenderOutput render_all(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                        const PredictorConfig& cfg, const std::string& dir,
                        const RenderOptions& ro) {
  namespace fs = std::filesystem;
  RenderOutput out;
  auto save = [&](const std::string& name, const Image& img) {
    const std::string path = (fs::path(dir) / name).string();
    write_png(path, img);
    out.files.push_back(path);
    return path;
  };
  auto phase = [&](const char* name, const char* unit) -> RowProgress {
    if (!ro.progress) return nullptr;
    return
        [&ro, name, unit](uint64_t done, uint64_t total) { ro.progress(name, unit, done, total); };
  };
  ShadeInfo si;
  const Image shaded = shade(scene, bvh, opt, &si, phase("shading", "pixels"));

  Predictor pred(bvh, cfg);
  const PixelStats ps =
      predictor_pixels(scene, bvh, opt, &pred, phase("predictor", "camera samples"));
  const size_t n = ps.rays.size();

  // What every picture names: the scene, the workload and its rays, the predictor.
  std::string kinds;
  uint64_t rays = 0;
  for (int k = 0; k < kNumRayKinds; ++k)
    if (const uint64_t r = pred.by_kind(RayKind(k)).rays) {
      kinds += (kinds.empty() ? "" : ", ") + std::string(ray_kind_name(RayKind(k))) + " " +
               std::to_string(r);
      rays += r;
    }
  char wl[160];
  std::snprintf(wl, sizeof wl, "%dx%d, %d spp, seed %llu, depth %d", ps.width, ps.height, ps.spp,
                (unsigned long long)opt.seed, opt.max_depth);
  const std::vector<std::string> caption = {
      "scene " + fs::path(scene.path).filename().string() + ": " + wl + "; " +
          std::to_string(rays) + " rays (" + kinds + ")",
      "predictor: " + (ro.config.empty() ? config_caption(cfg) : ro.config)};

  // The cost model's net cycles per pixel (docs/cost_model.md).
  const CostModel cost;
  const PredictStats& total = pred.total();
  const CycleCost cc = cycle_cost(total, cost);
  std::vector<double> net(n), work(n), skipped(n), failed(n);
  for (size_t i = 0; i < n; ++i) {
    net[i] = ps.rays[i] ? ps.baseline_cycles[i] - ps.hrpp_cycles[i] : NAN;
    work[i] = double(ps.baseline_interior[i]) / ps.spp;
    skipped[i] = ps.baseline_interior[i]
                     ? 1.0 - double(ps.hrpp_interior[i]) / double(ps.baseline_interior[i])
                     : NAN;
    failed[i] = ps.rays[i] ? double(ps.failed[i]) / ps.rays[i] : NAN;
  }
  // Colour bars up to the 99th percentile (outliers clamp); the net cycles' symmetric about 0.
  auto p99 = [](std::vector<double> v) {
    v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }),
            v.end());
    if (v.empty()) return 0.0;
    auto k = v.begin() + long((v.size() - 1) * 99 / 100);
    std::nth_element(v.begin(), k, v.end());
    return *k;
  };
  std::vector<double> abs_net(n);
  for (size_t i = 0; i < n; ++i) abs_net[i] = std::fabs(net[i]);
  const double net_range = std::max(1.0, std::ceil(p99(abs_net)));
  char per_ray[200];
  const double nrays = std::max<uint64_t>(1, total.rays);
  std::snprintf(
      per_ray, sizeof per_ray, "all rays: %.1f -> %.1f cycles per ray, %+.2f%% saved (%s)",
      cc.baseline / nrays, cc.hrpp / nrays, 100 * cc.saved_fraction(),
      cc.hrpp > cc.baseline ? "this configuration costs time" : "this configuration saves time");
  HeatMap mc{.title =
                 "net cycles saved per pixel by the cost model: baseline - HRPP cycles of the "
                 "pixel's rays (all kinds); red: prediction saves, blue: it costs",
             .colormap = "coolwarm",
             .lo = -net_range,
             .hi = net_range,
             .units = std::string("cycles per pixel (") + std::to_string(ps.spp) +
                      " camera sample(s) and their rays); the bar ends at the 99th percentile of "
                      "|value|; " +
                      per_ray,
             .lo_note = "costs",
             .hi_note = "saves",
             .meaning =
                 "per pixel, the cost model's baseline cycles minus HRPP's cycles (lookup, "
                 "decision, predicted and full walks, mispredict penalties) over every ray "
                 "of the pixel, all kinds (docs/cost_model.md); positive: prediction saves "
                 "time, negative: it costs time"};
  HeatMap mw{.title = "baseline interior-node tests per camera sample (all its rays)",
             .hi = std::max(1.0, p99(work)),
             .units =
                 "interior-node tests of the baseline walks per camera sample; the bar ends "
                 "at the 99th percentile",
             .meaning =
                 "per pixel, the baseline walks' interior-node tests over every ray of the "
                 "pixel (all kinds), per camera sample"};
  HeatMap ms{.title =
                 "interior-node tests skipped: 1 - HRPP / baseline (HRPP's count includes the "
                 "wasted predicted walks' tests; red: fewer tests, blue: more)",
             .colormap = "coolwarm",
             .lo = -1,
             .hi = 1,
             .percent = true,
             .units =
                 "% of the pixel's baseline interior-node tests (work, not time: see "
                 "net_cycles.png)",
             .meaning =
                 "per pixel, 1 - HRPP / baseline interior-node tests over the pixel's rays "
                 "(all kinds); HRPP's tests include those of predicted walks that failed; "
                 "work skipped, not time: lookups, decisions and leaf and triangle work "
                 "are not in it"};
  HeatMap mf{.title = "mispredicted: rays whose prediction failed (false positives) / rays",
             .percent = true,
             .units = "% of the pixel's rays (all kinds)",
             .meaning =
                 "per pixel, the share of the pixel's rays (all kinds) whose predicted "
                 "subtrees held no hit (false positives: a wasted predicted walk)"};

  nlohmann::json pictures = nlohmann::json::object();
  const std::string shaded_title =
      "direct lighting (Lambert, every light, shadows traced): camera, lights and geometry";
  const std::string shaded_units = "colour: display sRGB, auto-exposed (exposure " +
                                   label(si.exposure, false) +
                                   "); emitters in their colour, misses dark blue-grey";
  save("shaded.png",
       with_legend(upscale(shaded, display_scale(shaded.width, shaded.height)),
                   {.head = {shaded_title}, .body = {shaded_units}, .caption = caption}));
  pictures["shaded.png"] = shaded_title + "; " + shaded_units;
  nlohmann::json maps = nlohmann::json::object();
  for (auto [name, values, map] :
       {std::tuple{"net_cycles.png", &net, &mc}, std::tuple{"work.png", &work, &mw},
        std::tuple{"skipped.png", &skipped, &ms}, std::tuple{"mispredicted.png", &failed, &mf}}) {
    save(name, heat_map_image(*values, ps.width, ps.height, map, caption));
    maps[name] = map->to_json();
    pictures[name] = map->meaning;
  }
  nlohmann::json pj = pred.to_json();
  nlohmann::json net_json = cycle_cost_json(total, cost);
  net_json["saved_cycles"] = cc.baseline - cc.hrpp;
  net_json["saves_time"] = cc.hrpp < cc.baseline;
  net_json["cost_model"] = cost.to_json();
  for (int k = 0; k < kNumRayKinds; ++k)
    if (pred.by_kind(RayKind(k)).rays)
      net_json["by_kind"][std::string(ray_kind_name(RayKind(k)))] =
          cycle_cost_json(pred.by_kind(RayKind(k)), cost);
  if (!ro.tool.is_null()) out.summary["tool"] = ro.tool;
  out.summary.update({{"scene", scene.path},
                      {"workload", workload_json(scene, opt)},
                      {"shaded", si.to_json()},
                      {"maps", maps},
                      {"pictures", pictures},
                      {"caption", caption},
                      {"net_cycles", net_json},
                      {"predictor", pj["config"]},
                      {"skipped_interior_fraction", pred.total().skipped_interior_fraction()},
                      {"by_kind", pj["by_kind"]}});
  const std::string jpath = (fs::path(dir) / "render.json").string();
  write_output(jpath, out.summary.dump(2) + "\n");
  out.files.push_back(jpath);
  return out;
}

}  // namespace hrpp
