#include "hrpp/cost_model.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>

#include "hrpp/cycle_model.h"
#include "hrpp/render.h"
#include "hrpp/rtl_config.h"

namespace hrpp {

nlohmann::json CostModel::to_json() const {
  return {{"node_fetch", node_fetch}, {"box_test", box_test},   {"tri_test", tri_test},
          {"lookup", lookup},         {"decision", decision},   {"mispredict", mispredict}};
}

// A walk's cycles: every interior node and every leaf is fetched; a node's two child boxes are
// tested in parallel, and a walk's start node has its own box tested first
// (box_tests - interior_tests box-test latencies in all); triangles one after another.
static double walk_cycles(const Counters& c, const CostModel& m) {
  return double(c.interior_tests + c.leaf_visits) * m.node_fetch +
         double(c.box_tests - c.interior_tests) * m.box_test + double(c.tri_tests) * m.tri_test;
}

CycleCost cycle_cost(const PredictStats& s, const CostModel& m) {
  CycleCost c;
  c.baseline = walk_cycles(s.baseline, m);
  const uint64_t valid = s.rays - s.invalid_rays;
  const uint64_t predicted = s.true_positive + s.false_positive;
  c.hrpp = walk_cycles(s.hrpp, m) + double(valid) * m.lookup + double(predicted) * m.decision +
           double(s.false_positive) * m.mispredict;
  return c;
}

nlohmann::json cycle_cost_json(const PredictStats& s, const CostModel& m) {
  const CycleCost c = cycle_cost(s, m);
  const double n = std::max<uint64_t>(1, s.rays);
  return {{"baseline_cycles", c.baseline},
          {"hrpp_cycles", c.hrpp},
          {"baseline_cycles_per_ray", c.baseline / n},
          {"hrpp_cycles_per_ray", c.hrpp / n},
          {"saved_cycle_fraction", c.saved_fraction()}};
}

// ---- the RTL's update delay, from the cycle model ----------------------------------------------

namespace {

// The RTL's default configuration (rtl/config/hrpp_configs.json).
CycleConfig default_rtl_config() { return rtl_config("default").cycle(PredictMode::kClosestExact); }

uint32_t f32(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

// Ray 0 is accepted; ray 1 (same key) is offered `gap` cycles later. True when ray 1's prediction
// holds ray 0's node.
bool second_ray_sees_write(const CycleConfig& cfg, uint32_t gap, uint32_t walk_latency) {
  CycleModel cm(cfg);
  DutIn ray;
  ray.ray_valid = true;
  ray.org = {f32(0.5f), f32(0.25f), f32(0.75f)};
  ray.dir = {f32(0.f), f32(0.6f), f32(0.8f)};
  std::optional<uint64_t> t0;
  bool sent1 = false;
  std::map<uint32_t, uint64_t> pw_due, upd_due;  // id -> cycle
  const uint64_t limit = uint64_t(gap) + walk_latency + 1000 + cfg.table.sets;
  while (cm.cycle() < limit) {
    const DutOut out = cm.outputs();
    DutIn in;
    in.pred_ready = in.skip_ready = true;
    const uint64_t now = cm.cycle();
    if (!t0 && out.ray_ready) {
      in = ray;
      in.ray_id = 0;
      in.pred_ready = in.skip_ready = true;
      t0 = now;
    } else if (t0 && !sent1 && now >= *t0 + gap && out.ray_ready) {
      in.ray_valid = true;
      in.ray_id = 1;
      in.org = ray.org;
      in.dir = ray.dir;
      sent1 = true;
    }
    if (out.pred_valid) {
      if (out.pred_id == 1) return out.pred_count > 0;
      pw_due[out.pred_id] = now + 1;  // an empty prediction: answered at once
    }
    for (auto it = pw_due.begin(); it != pw_due.end(); ++it)
      if (now >= it->second) {
        in.pw_valid = true;
        in.pw_id = it->first;
        in.pw_hit = false;
        if (out.pw_ready) pw_due.erase(it);
        break;
      }
    if (out.skip_valid && out.skip_id == 0) upd_due[0] = now + walk_latency;
    for (auto it = upd_due.begin(); it != upd_due.end(); ++it)
      if (now >= it->second) {
        in.outcome_valid = true;
        in.outcome_id = it->first;
        in.outcome_hit = true;
        in.outcome_node = 5;
        if (out.outcome_ready) upd_due.erase(it);
        break;
      }
    cm.tick(in);
  }
  return false;
}

}  // namespace

uint32_t rtl_update_delay(uint32_t walk_latency) {
  const CycleConfig cfg = default_rtl_config();
  // The smallest gap at which the second ray sees the first one's write.
  uint32_t lo = 1, hi = 64;
  while (!second_ray_sees_write(cfg, hi, walk_latency)) hi *= 2;
  while (lo < hi) {
    const uint32_t mid = lo + (hi - lo) / 2;
    if (second_ray_sees_write(cfg, mid, walk_latency)) hi = mid;
    else lo = mid + 1;
  }
  // At one ray per cycle, gap - 1 rays are looked up in between; but no more rays than there
  // are ray ids can be in flight.
  return std::min<uint32_t>(lo - 1, (1u << cfg.id_bits) - 1);
}

// ---- speculative image error ------------------------------------------------------------------

SpecImage::SpecImage(const Scene& scene, int width, int height, int spp)
    : scene_(scene), width_(width), height_(height), spp_(std::max(1, spp)),
      exact_(size_t(width) * height * 3, 0.f), spec_(size_t(width) * height * 3, 0.f) {}

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
