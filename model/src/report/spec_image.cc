#include "hrpp/report/spec_image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "hrpp/report/render.h"

namespace hrpp {

// ---- speculative image error ------------------------------------------------------------------

SpecImage::SpecImage(const Scene& scene, int width, int height, int spp, std::string config)
    : scene_(scene),
      width_(width),
      height_(height),
      spp_(std::max(1, spp)),
      config_(std::move(config)),
      exact_(size_t(width) * height * 3, 0.f),
      spec_(size_t(width) * height * 3, 0.f) {}

static Vec3 eye_light(const Scene& scene, const Ray& r, const Hit& h) {
  if (!h.hit()) return Vec3(0.02f, 0.025f, 0.045f);  // render.cc's background
  const SurfacePoint sp = surface_point(scene, r, h);
  const Material& m = *sp.material;
  if (m.is_emissive()) {
    const Vec3 e = m.emission();
    return e / std::max({e.x, e.y, e.z});
  }
  return Vec3(m.base_color) * (0.25f + 0.75f * std::fabs(glm::dot(sp.n, glm::normalize(r.dir))));
}

void SpecImage::add(const RayRecord& r, const RayResult& res) {
  if (r.kind != RayKind::kPrimary || res.invalid) return;
  if (r.pixel >= uint32_t(width_) * uint32_t(height_)) return;
  const Vec3 e = eye_light(scene_, r.ray, res.baseline), s = eye_light(scene_, r.ray, res.answer);
  float* pe = &exact_[size_t(r.pixel) * 3];
  float* ps = &spec_[size_t(r.pixel) * 3];
  for (int c = 0; c < 3; ++c) {
    pe[c] += e[c];
    ps[c] += s[c];
  }
  ++samples_;
  wrong_ += res.baseline.prim != res.answer.prim || res.baseline.t != res.answer.t;
}

nlohmann::json SpecImage::finish(const std::string& dir) const {
  Image ex(width_, height_), sp(width_, height_), diff(width_, height_);
  double abs_sum = 0;
  uint64_t differ = 0;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const size_t i = (size_t(y) * width_ + x) * 3;
      Vec3 a, b;
      for (int c = 0; c < 3; ++c) {
        a[c] = srgb_encode(exact_[i + c] / spp_);
        b[c] = srgb_encode(spec_[i + c] / spp_);
      }
      ex.set(x, y, a);
      sp.set(x, y, b);
      bool d = false;
      Vec3 dv;
      for (int c = 0; c < 3; ++c) {
        const int va = ex.rgb[i + c], vb = sp.rgb[i + c];
        abs_sum += std::abs(va - vb) / 255.0;
        d = d || va != vb;
        dv[c] = std::min(1.f, 8.f * std::abs(va - vb) / 255.f);
      }
      differ += d;
      diff.set(x, y, dv);
    }
  const double pixels = double(width_) * height_;
  nlohmann::json j = {{"primary_samples", samples_},
                      {"wrong_primary_samples", wrong_},
                      {"wrong_primary_fraction", samples_ ? double(wrong_) / samples_ : 0.0},
                      {"mean_abs_error", pixels > 0 ? abs_sum / (3 * pixels) : 0.0},
                      {"differing_pixel_fraction", pixels > 0 ? differ / pixels : 0.0},
                      {"resolution", std::to_string(width_) + "x" + std::to_string(height_)}};
  if (!dir.empty()) {
    // exact | speculative | difference, each enlarged to at least 160 pixels and named above
    // it, and a legend band under them that explains the panels and names the run.
    const int k = std::max(1, 160 / std::max({1, width_, height_}));
    const int pw = width_ * k, ph = height_ * k, gap = 6;
    const int ts = 3 * pw + 2 * gap >= 640 ? 2 : 1, strip = 14 * ts;  // with_legend's text scale
    Image row(3 * pw + 2 * gap, ph + strip, Vec3(0.12f));
    const Image* panels[3] = {&ex, &sp, &diff};
    const char* names[3] = {"1 exact", "2 speculative", "3 difference x8"};
    for (int p = 0; p < 3; ++p) {
      const int x0 = p * (pw + gap);
      row.text(x0 + (pw - text_width(names[p]) * ts) / 2, 3 * ts, names[p], Vec3(0.95f), ts);
      const Image big = upscale(*panels[p], k);
      for (int y = 0; y < ph; ++y)
        for (int x = 0; x < pw; ++x) row.set(x0 + x, strip + y, big.get(x, y));
    }
    char stats[200];
    std::snprintf(stats, sizeof stats,
                  "%llu of %llu primary samples answered wrong (%.3f%%), %.3f%% of pixels differ, "
                  "mean absolute error %.5f",
                  (unsigned long long)wrong_, (unsigned long long)samples_,
                  samples_ ? 100.0 * wrong_ / samples_ : 0.0,
                  pixels > 0 ? 100.0 * differ / pixels : 0.0,
                  pixels > 0 ? abs_sum / (3 * pixels) : 0.0);
    const std::string scene_name = std::filesystem::path(scene_.path).filename().string();
    const Legend lg{
        .head = {"speculative closest hits against the exact image (primary rays)"},
        .body = {"1 exact: each camera sample's baseline closest hit, shaded by base colour under "
                 "a light at the eye",
                 "2 speculative: the predictor's answer for the same samples, shaded the same way",
                 "3 difference x8: |1 - 2| per channel of 8-bit sRGB, times 8 (black: the same)",
                 stats},
        .caption = {
            "scene " + scene_name + ": " + std::to_string(width_) + "x" + std::to_string(height_) +
                ", " + std::to_string(spp_) + " spp; primary rays only",
            "predictor: " + (config_.empty() ? std::string("configuration not given") : config_)}};
    const Image out = with_legend(row, lg);
    for (const auto* lines : {&lg.head, &lg.body, &lg.caption})
      for (const std::string& l : *lines) j["legend"].push_back(l);
    const std::string path = dir + "/spec_compare.png";
    write_png(path, out);
    j["image"] = path;
  }
  return j;
}

}  // namespace hrpp
