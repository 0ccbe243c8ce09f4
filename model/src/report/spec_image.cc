#include "hrpp/report/spec_image.h"

#include <algorithm>
#include <cmath>

#include "hrpp/report/render.h"

namespace hrpp {

// ---- speculative image error ------------------------------------------------------------------

SpecImage::SpecImage(const Scene& scene, int width, int height, int spp)
    : scene_(scene),
      width_(width),
      height_(height),
      spp_(std::max(1, spp)),
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
    // exact | speculative | difference, each with a caption strip above it.
    constexpr int kStrip = 14, kGap = 4;
    Image out(3 * width_ + 2 * kGap, height_ + kStrip, Vec3(1));
    const Image* panels[3] = {&ex, &sp, &diff};
    const char* captions[3] = {"exact", "speculative", "difference x8"};
    for (int p = 0; p < 3; ++p) {
      const int x0 = p * (width_ + kGap);
      out.text(x0 + 2, 3, captions[p], Vec3(0));
      for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) out.set(x0 + x, kStrip + y, panels[p]->get(x, y));
    }
    const std::string path = dir + "/spec_compare.png";
    write_png(path, out);
    j["image"] = path;
  }
  return j;
}

}  // namespace hrpp
