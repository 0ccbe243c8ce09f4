#include "hrpp/reference/crosscheck.h"

#include <chrono>
#include <cstdio>
#include <sstream>

#include "hrpp/trace/traverse.h"
#include "hrpp/workload/workload.h"

namespace hrpp {

CrossCheckCounts& CrossCheckCounts::operator+=(const CrossCheckCounts& o) {
  rays += o.rays;
  invalid_rays += o.invalid_rays;
  outside_embree += o.outside_embree;
  compared += o.compared;
  hit_agree += o.hit_agree;
  hit_mismatches += o.hit_mismatches;
  grazes += o.grazes;
  t_mismatches += o.t_mismatches;
  prim_mismatches += o.prim_mismatches;
  ties += o.ties;
  hits += o.hits;
  return *this;
}

bool CrossCheckResult::passed() const { return failure().empty(); }

std::string CrossCheckResult::failure() const {
  const CrossCheckCounts& c = total;
  const std::string uncompared = std::to_string(c.invalid_rays) + " invalid, " +
                                 std::to_string(c.outside_embree) + " outside Embree's range";
  if (c.compared == 0)
    return "no ray compared (" + std::to_string(c.rays) +
           " rays of the kinds asked for: " + uncompared + ")";
  if (double(c.compared) < kMinComparedFraction * double(c.rays)) {
    char pct[16];
    std::snprintf(pct, sizeof pct, "%g%%", 100 * kMinComparedFraction);
    return "only " + std::to_string(c.compared) + " of " + std::to_string(c.rays) +
           " rays compared, fewer than the required " + pct + " (" + uncompared + ")";
  }
  if (c.hit_mismatches || c.t_mismatches || c.prim_mismatches)
    return "disagreements beyond genuine ties and grazes (" + std::to_string(c.hit_mismatches) +
           " hit, " + std::to_string(c.t_mismatches) + " t, " + std::to_string(c.prim_mismatches) +
           " primitive mismatches)";
  if (double(c.grazes) > 1e-5 * double(c.compared))
    return std::to_string(c.grazes) + " genuine grazes, more than 1e-5 of the " +
           std::to_string(c.compared) + " compared rays";
  return {};
}

namespace {

nlohmann::json counts_json(const CrossCheckCounts& c) {
  return {{"rays", c.rays},
          {"invalid_rays", c.invalid_rays},
          {"outside_embree_range", c.outside_embree},
          {"compared", c.compared},
          {"hits", c.hits},
          {"hit_agreement", c.hit_agreement()},
          {"hit_mismatches", c.hit_mismatches},
          {"grazes", c.grazes},
          {"t_mismatches", c.t_mismatches},
          {"prim_mismatches", c.prim_mismatches},
          {"ties", c.ties}};
}

std::string describe(const char* what, const Ray& r, RayKind k, const Hit& ours, const Hit& emb) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s: %s ray org (%.9g, %.9g, %.9g) dir (%.9g, %.9g, %.9g) t [%.9g, %.9g]; ours "
                "prim %d t %.9g; embree prim %d t %.9g",
                what, std::string(ray_kind_name(k)).c_str(), r.org.x, r.org.y, r.org.z, r.dir.x,
                r.dir.y, r.dir.z, r.tnear, r.tfar, ours.hit() ? int(ours.prim) : -1, ours.t,
                emb.hit() ? int(emb.prim) : -1, emb.t);
  return buf;
}

class Comparer {
 public:
  Comparer(const Scene& s, const Bvh& b, const EmbreeScene& e, CrossCheckResult& res,
           size_t max_examples)
      : scene_(s), bvh_(b), emb_(e), res_(res), max_examples_(max_examples) {}

  void compare(const Ray& ray, RayKind kind) {
    CrossCheckCounts c;
    c.rays = 1;
    if (validate_ray(ray) != RayError::kNone) {
      c.invalid_rays = 1;
      add(kind, c);
      return;
    }
    if (!embree_accepts(ray)) {  // Embree would abort on it: never sent
      c.outside_embree = 1;
      add(kind, c);
      return;
    }
    c.compared = 1;
    Counters counters;
    if (is_any_hit(kind)) {
      const Hit ours = any_hit(bvh_, ray, &counters);
      const bool occ = emb_.occluded(ray);
      c.hits = ours.hit();
      if (ours.hit() == occ) {
        c.hit_agree = 1;
      } else {
        const Hit occluder = ours.hit() ? ours : emb_.intersect(ray);
        if (!occluder.hit() || genuine_graze(ray, occluder.prim)) {
          c.grazes = 1;
        } else {
          c.hit_mismatches = 1;
          example("hit mismatch", ray, kind, ours, occluder);
        }
      }
      add(kind, c);
      return;
    }
    const Hit ours = closest_hit(bvh_, ray, &counters);
    const Hit emb = emb_.intersect(ray);
    c.hits = ours.hit();
    if (ours.hit() != emb.hit()) {
      const Hit& h = ours.hit() ? ours : emb;
      if (genuine_graze(ray, h.prim)) {
        c.grazes = 1;
      } else {
        c.hit_mismatches = 1;
        example("hit mismatch", ray, kind, ours, emb);
      }
    } else if (ours.hit()) {
      c.hit_agree = 1;
      const double tol = t_tolerance(ray, scene_.triangles[ours.prim], ours.t);
      const bool t_ok = std::fabs(double(ours.t) - emb.t) <= tol;
      if (ours.prim == emb.prim) {
        if (!t_ok) {
          c.t_mismatches = 1;
          example("t mismatch", ray, kind, ours, emb);
        }
      } else {
        // A tie: both triangles are hit (within the perturbation) at the same t.
        const double tol_b = t_tolerance(ray, scene_.triangles[emb.prim], emb.t);
        const bool t_tie = std::fabs(double(ours.t) - emb.t) <= std::max(tol, tol_b);
        if (t_tie && near_or_inside(ray, ours.prim) && near_or_inside(ray, emb.prim)) {
          c.ties = 1;
        } else if (genuine_graze(ray, ours.prim) || genuine_graze(ray, emb.prim)) {
          c.grazes = 1;
        } else {
          c.prim_mismatches = 1;
          if (!t_ok) c.t_mismatches = 1;
          example("primitive mismatch", ray, kind, ours, emb);
        }
      }
    } else {
      c.hit_agree = 1;
    }
    add(kind, c);
  }

 private:
  /// The referee's verdict: the ray passes within the perturbation of the triangle's boundary,
  /// or its hit sits within the perturbation of an end of the ray's interval, so either answer
  /// is correct. Distances in the plane scale with cos(theta): at grazing incidence a small
  /// perturbation of the ray moves the hit point far.
  bool genuine_graze(const Ray& ray, uint32_t prim) const {
    return referee_graze(ray, scene_.triangles[prim]);
  }
  /// Inside the triangle, or outside it by no more than the perturbation.
  bool near_or_inside(const Ray& ray, uint32_t prim) const {
    const Triangle& tri = scene_.triangles[prim];
    const RefereeHit r = referee_intersect(ray, tri);
    return r.min_bary >= 0 || std::fabs(r.edge_dist) * r.cos_theta <= referee_delta(ray, tri, r.t);
  }
  void example(const char* what, const Ray& r, RayKind k, const Hit& a, const Hit& b) {
    if (res_.examples.size() < max_examples_) res_.examples.push_back(describe(what, r, k, a, b));
  }
  void add(RayKind k, const CrossCheckCounts& c) {
    res_.total += c;
    res_.by_kind[static_cast<int>(k)] += c;
  }

  const Scene& scene_;
  const Bvh& bvh_;
  const EmbreeScene& emb_;
  CrossCheckResult& res_;
  size_t max_examples_;
};

}  // namespace

nlohmann::json CrossCheckResult::to_json() const {
  nlohmann::json j = counts_json(total);
  j["scene"] = scene;
  j["embree"] = embree;
  j["resolution"] = {width, height};
  j["seconds"] = seconds;
  j["passed"] = passed();
  j["min_compared_fraction"] = kMinComparedFraction;
  if (!passed()) j["failure"] = failure();
  j["tolerance"] =
      "perturbation delta = 128*FLT_EPSILON*M (M: largest coordinate of origin, hit point, "
      "triangle); t tolerance delta/(|d| cos theta); graze: double-precision hit within delta "
      "of an edge or of an interval end (scaled by cos theta); tie: different primitives hit at "
      "the same t";
  nlohmann::json bk = nlohmann::json::object();
  for (int k = 0; k < kNumRayKinds; ++k)
    if (by_kind[k].rays)
      bk[std::string(ray_kind_name(static_cast<RayKind>(k)))] = counts_json(by_kind[k]);
  j["by_kind"] = bk;
  j["examples"] = examples;
  return j;
}

CrossCheckResult cross_check_rays(const Scene& scene, const Bvh& bvh, const EmbreeScene& embree,
                                  const std::vector<std::pair<Ray, RayKind>>& rays,
                                  size_t max_examples) {
  CrossCheckResult res;
  res.scene = scene.path;
  res.embree = embree.description();
  Comparer cmp(scene, bvh, embree, res, max_examples);
  for (const auto& [r, k] : rays) cmp.compare(r, k);
  return res;
}

CrossCheckResult cross_check(const Scene& scene, const Bvh& bvh, const CrossCheckOptions& opt) {
  auto t0 = std::chrono::steady_clock::now();
  EmbreeScene embree(scene.triangles, opt.embree_config, /*robust=*/true);
  CrossCheckResult res;
  res.scene = scene.path;
  res.embree = embree.description();
  bool want[kNumRayKinds] = {};
  for (RayKind k : opt.kinds) want[static_cast<int>(k)] = true;
  WorkloadOptions wo;
  wo.spp = 1;
  wo.seed = opt.seed;
  wo.shadow = want[static_cast<int>(RayKind::kShadow)];
  wo.ao = want[static_cast<int>(RayKind::kAo)];
  resolution_for(scene.camera, opt.rays, wo.spp, &wo.width, &wo.height);
  res.width = wo.width;
  res.height = wo.height;
  Comparer cmp(scene, bvh, embree, res, opt.max_examples);
  const uint64_t samples = uint64_t(wo.width) * wo.height * wo.spp;
  uint64_t done = 0;
  generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit*) {
    if (want[static_cast<int>(r.kind)]) cmp.compare(r.ray, r.kind);
    if (opt.progress && r.kind == RayKind::kPrimary && (++done & 0xFFF) == 0)
      opt.progress(done, samples);
  });
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace hrpp
