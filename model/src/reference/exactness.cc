#include "hrpp/reference/exactness.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "hrpp/reference/crosscheck.h"
#include "hrpp/trace/referee.h"
#include "hrpp/workload/sampling.h"
#include "hrpp/workload/workload.h"

namespace hrpp {

namespace {

constexpr std::array<const char*, kNumStudyKinds> kStudyKindNames = {
    "primary", "shadow", "ao", "ao-short", "reflection", "refraction", "diffuse"};

/// The referee's verdict on a hit/miss disagreement: the side that hit is right when the
/// triangle it hit is hit in double precision, unless the hit changes within the perturbation.
Verdict::Side hit_miss_side(const Scene& scene, const Ray& ray, uint32_t prim, bool ours_hit) {
  const Triangle& tri = scene.triangles[prim];
  if (referee_graze(ray, tri)) return Verdict::Side::kGraze;
  const bool hitter_right = referee_intersect(ray, tri).hit;
  return hitter_right == ours_hit ? Verdict::Side::kOurs : Verdict::Side::kEmbree;
}

/// Inside the triangle, or outside it by no more than the perturbation (crosscheck.cc's test).
bool near_or_inside(const Scene& scene, const Ray& ray, uint32_t prim) {
  const Triangle& tri = scene.triangles[prim];
  const RefereeHit r = referee_intersect(ray, tri);
  return r.min_bary >= 0 || std::fabs(r.edge_dist) * r.cos_theta <= referee_delta(ray, tri, r.t);
}

const Hit& brute_hit(const Bvh& bvh, const Ray& ray, std::optional<Hit>* brute,
                     const BruteForce* fast) {
  if (!brute->has_value()) *brute = fast ? fast->closest(ray) : brute_force_closest(bvh, ray);
  return **brute;
}

bool nearer(const Hit& b, const Hit& ours) { return b.hit() && (!ours.hit() || b.t < ours.t); }
bool same_hit(const Hit& a, const Hit& b) {
  return a.prim == b.prim && (a.prim == kNoPrim || a.t == b.t);
}

/// Fills the walk-miss fields of v when brute force finds a hit nearer than `ours` (or any hit
/// when ours is none).
void check_walk(const Scene& scene, const Bvh& bvh, const Ray& ray, const Hit& ours,
                std::optional<Hit>* brute, const BruteForce* fast, Verdict* v) {
  v->brute_forced = true;
  if (!nearer(brute_hit(bvh, ray, brute, fast), ours)) return;
  if (fast) {  // decided by brute_force_closest itself
    const Hit exact = brute_force_closest(bvh, ray);
    v->search_mismatch = !same_hit(exact, **brute);
    *brute = exact;
    if (!nearer(exact, ours)) return;
  }
  const Hit& b = **brute;
  v->walk_miss = true;
  v->closer = b;
  const RefereeHit rb = referee_intersect(ray, scene.triangles[b.prim]);
  v->ref_t_closer = rb.t;
  bool ours_ref_hit = false;
  if (ours.hit()) {
    const RefereeHit ra = referee_intersect(ray, scene.triangles[ours.prim]);
    v->ref_t_ours = ra.t;
    ours_ref_hit = ra.hit;
  }
  v->confirmed = rb.hit && (!ours_ref_hit || rb.t < v->ref_t_ours);
}

std::string hex3(const Vec3& p) {
  char b[128];
  std::snprintf(b, sizeof b, "%a %a %a", p.x, p.y, p.z);
  return b;
}

std::string hexf(float f) {
  char b[40];
  std::snprintf(b, sizeof b, "%a", f);
  return b;
}

nlohmann::json hex_json(const Vec3& p) { return {hexf(p.x), hexf(p.y), hexf(p.z)}; }

nlohmann::json hit_json(const Hit& h) {
  if (!h.hit()) return nullptr;
  return {{"prim", h.prim}, {"t", h.t}, {"t_hex", hexf(h.t)}};
}

}  // namespace

std::string_view study_kind_name(StudyKind k) { return kStudyKindNames[static_cast<int>(k)]; }

bool parse_study_kind(std::string_view name, StudyKind* out) {
  for (int k = 0; k < kNumStudyKinds; ++k)
    if (name == kStudyKindNames[k]) {
      *out = static_cast<StudyKind>(k);
      return true;
    }
  return false;
}

std::string_view query_name(Query q) { return q == Query::kClosest ? "closest" : "any"; }

// ---- brute force --------------------------------------------------------------------------------

namespace {
constexpr float kWide = 0x1p-12f;  // the pre-test's margin, relative (float rounding: 2^-24)
}

BruteForce::BruteForce(const Bvh& bvh) : bvh_(bvh) {
  for (int a = 0; a < 3; ++a) {
    lo_[a].resize(bvh.tris.size());
    hi_[a].resize(bvh.tris.size());
  }
  for (size_t i = 0; i < bvh.tris.size(); ++i) {
    const Aabb b = bvh.tris[i].bounds();
    const float m = kWide * std::max(max_abs(b.lo), max_abs(b.hi));
    for (int a = 0; a < 3; ++a) {
      lo_[a][i] = b.lo[a] - m;
      hi_[a][i] = b.hi[a] + m;
    }
  }
}

Hit BruteForce::closest(const Ray& ray) const {
  const RayPre r(ray);
  Hit hit;
  float limit = next_float_up(ray.tfar);
  const float e = kWide * max_abs(ray.org);  // the hit point's rounding grows with the origin's
  const float tlo = ray.tnear * (1 - kWide);
  const size_t n = bvh_.tris.size();
  for (size_t i = 0; i < n; ++i) {
    // The slab test of intersect_box on the widened box (a NaN slab distance is ignored).
    float tmin = tlo, tmax = limit * (1 + kWide);
    for (int a = 0; a < 3; ++a) {
      float t0 = (lo_[a][i] - e - r.org[a]) * r.inv[a];
      float t1 = (hi_[a][i] + e - r.org[a]) * r.inv[a];
      if (r.inv[a] < 0) std::swap(t0, t1);
      tmin = t0 > tmin ? t0 : tmin;
      tmax = t1 < tmax ? t1 : tmax;
    }
    if (!(tmin <= tmax)) continue;
    // brute_force_closest's body.
    if (bvh_.tri_degenerate[i]) continue;
    float t, u, v;
    if (intersect_triangle(r, bvh_.tris[i], ray.tnear, limit, &t, &u, &v)) {
      hit.t = limit = t;
      hit.u = u;
      hit.v = v;
      hit.prim = bvh_.prim_ids[i];
    }
  }
  return hit;
}

// ---- judging ----------------------------------------------------------------------------------

Verdict judge_closest(const Scene& scene, const Bvh& bvh, const Ray& ray, const Traces& tr,
                      std::optional<Hit>* brute, const BruteForce* fast) {
  Verdict v;
  const Hit &o = tr.ours_closest, &e = tr.embree_closest;
  bool need_brute = tr.ours_any.hit() && !o.hit();  // our own walks disagree
  if (o.hit() != e.hit()) {
    v.what = Verdict::What::kHit;
    v.side = hit_miss_side(scene, ray, o.hit() ? o.prim : e.prim, o.hit());
    need_brute = true;
  } else if (o.hit() && o.prim != e.prim) {
    v.what = Verdict::What::kPrim;
    need_brute = true;
    const Triangle &ta = scene.triangles[o.prim], &tb = scene.triangles[e.prim];
    const double tol = std::max(t_tolerance(ray, ta, o.t), t_tolerance(ray, tb, e.t));
    if (std::fabs(double(o.t) - e.t) <= tol && near_or_inside(scene, ray, o.prim) &&
        near_or_inside(scene, ray, e.prim)) {
      v.side = Verdict::Side::kTie;
    } else if (referee_graze(ray, ta) || referee_graze(ray, tb)) {
      v.side = Verdict::Side::kGraze;
    } else {
      const RefereeHit ra = referee_intersect(ray, ta), rb = referee_intersect(ray, tb);
      const bool ours = ra.hit && (!rb.hit || ra.t <= rb.t);
      v.side = ours ? Verdict::Side::kOurs : Verdict::Side::kEmbree;
    }
  } else if (o.hit() && o.t != e.t) {
    v.what = Verdict::What::kT;
    const Triangle& tri = scene.triangles[o.prim];
    if (std::fabs(double(o.t) - e.t) <= t_tolerance(ray, tri, o.t)) {
      v.side = Verdict::Side::kRounding;
    } else {
      const double rt = referee_intersect(ray, tri).t;
      v.side = std::fabs(o.t - rt) <= std::fabs(e.t - rt) ? Verdict::Side::kOurs
                                                          : Verdict::Side::kEmbree;
      need_brute = true;
    }
  }
  if (need_brute) check_walk(scene, bvh, ray, o, brute, fast, &v);
  return v;
}

Verdict judge_any(const Scene& scene, const Bvh& bvh, const Ray& ray, const Traces& tr,
                  std::optional<Hit>* brute, const BruteForce* fast) {
  Verdict v;
  const bool ours = tr.ours_any.hit();
  bool need_brute = ours != tr.ours_closest.hit();  // our own walks disagree
  if (ours != tr.embree_occluded) {
    v.what = Verdict::What::kHit;
    need_brute = true;
    // The triangle the hitting side hit: ours, or Embree's closest hit (rtcOccluded1 names none),
    // or failing that the one our triangle test accepts.
    uint32_t prim = kNoPrim;
    if (ours)
      prim = tr.ours_any.prim;
    else if (tr.embree_closest.hit())
      prim = tr.embree_closest.prim;
    else if (brute_hit(bvh, ray, brute, fast).hit())
      prim = (*brute)->prim;
    v.side = prim == kNoPrim ? Verdict::Side::kOurs : hit_miss_side(scene, ray, prim, ours);
  }
  if (need_brute && !ours) check_walk(scene, bvh, ray, tr.ours_any, brute, fast, &v);
  if (need_brute) v.brute_forced = true;
  return v;
}

// ---- counts ------------------------------------------------------------------------------------

void QueryCounts::add(const Verdict& v) {
  compared++;
  switch (v.what) {
    case Verdict::What::kAgree:
      agree++;
      break;
    case Verdict::What::kHit:
      hit_disagree++;
      break;
    case Verdict::What::kPrim:
      prim_disagree++;
      break;
    case Verdict::What::kT:
      t_disagree++;
      break;
  }
  switch (v.side) {
    case Verdict::Side::kNone:
      break;
    case Verdict::Side::kOurs:
      ours_right++;
      break;
    case Verdict::Side::kEmbree:
      embree_right++;
      break;
    case Verdict::Side::kTie:
      ties++;
      break;
    case Verdict::Side::kGraze:
      grazes++;
      break;
    case Verdict::Side::kRounding:
      rounding++;
      break;
  }
  brute_forced += v.brute_forced;
  walk_misses += v.walk_miss;
  walk_misses_confirmed += v.walk_miss && v.confirmed;
}

QueryCounts& QueryCounts::operator+=(const QueryCounts& o) {
  compared += o.compared;
  hits += o.hits;
  agree += o.agree;
  hit_disagree += o.hit_disagree;
  prim_disagree += o.prim_disagree;
  t_disagree += o.t_disagree;
  ours_right += o.ours_right;
  embree_right += o.embree_right;
  ties += o.ties;
  grazes += o.grazes;
  rounding += o.rounding;
  brute_forced += o.brute_forced;
  walk_misses += o.walk_misses;
  walk_misses_confirmed += o.walk_misses_confirmed;
  return *this;
}

nlohmann::json QueryCounts::to_json() const {
  return {{"compared", compared},
          {"hits", hits},
          {"agree", agree},
          {"disagreements", disagreements()},
          {"hit_disagreements", hit_disagree},
          {"prim_disagreements", prim_disagree},
          {"t_disagreements", t_disagree},
          {"ours_right", ours_right},
          {"embree_right", embree_right},
          {"ties", ties},
          {"grazes", grazes},
          {"t_rounding", rounding},
          {"brute_forced", brute_forced},
          {"walk_misses", walk_misses},
          {"walk_misses_confirmed", walk_misses_confirmed}};
}

KindCounts& KindCounts::operator+=(const KindCounts& o) {
  rays += o.rays;
  invalid_rays += o.invalid_rays;
  outside_embree += o.outside_embree;
  for (int q = 0; q < 2; ++q) query[q] += o.query[q];
  return *this;
}

// ---- walk misses -------------------------------------------------------------------------------

std::string WalkMiss::line() const {
  char b[512];
  std::snprintf(b, sizeof b,
                "%s %s org %s dir %s tnear %a tfar %a ours %d %a closer %d %a referee %.17g "
                "%.17g %s",
                std::string(study_kind_name(kind)).c_str(), std::string(query_name(query)).c_str(),
                hex3(ray.org).c_str(), hex3(ray.dir).c_str(), ray.tnear, ray.tfar,
                ours.hit() ? int(ours.prim) : -1, ours.t, closer.hit() ? int(closer.prim) : -1,
                closer.t, ref_t_ours, ref_t_closer, confirmed ? "confirmed" : "unconfirmed");
  return b;
}

bool WalkMiss::parse(const std::string& line, WalkMiss* out) {
  std::istringstream in(line);
  std::string kind, query, w_org, w_dir, w_tnear, w_tfar;
  std::string f[8];
  if (!(in >> kind >> query >> w_org >> f[0] >> f[1] >> f[2] >> w_dir >> f[3] >> f[4] >> f[5] >>
        w_tnear >> f[6] >> w_tfar >> f[7]))
    return false;
  if (w_org != "org" || w_dir != "dir" || w_tnear != "tnear" || w_tfar != "tfar") return false;
  WalkMiss m;
  if (!parse_study_kind(kind, &m.kind)) return false;
  if (query == "closest")
    m.query = Query::kClosest;
  else if (query == "any")
    m.query = Query::kAny;
  else
    return false;
  float v[8];
  for (int i = 0; i < 8; ++i) {
    char* end = nullptr;
    v[i] = std::strtof(f[i].c_str(), &end);
    if (end == f[i].c_str() || *end) return false;
  }
  m.ray.org = Vec3(v[0], v[1], v[2]);
  m.ray.dir = Vec3(v[3], v[4], v[5]);
  m.ray.tnear = v[6];
  m.ray.tfar = v[7];
  *out = m;
  return true;
}

nlohmann::json WalkMiss::to_json() const {
  return {{"kind", study_kind_name(kind)},
          {"query", query_name(query)},
          {"org", hex_json(ray.org)},
          {"dir", hex_json(ray.dir)},
          {"tnear", hexf(ray.tnear)},
          {"tfar", hexf(ray.tfar)},
          {"ours", hit_json(ours)},
          {"closer", hit_json(closer)},
          {"referee_t_ours", ours.hit() ? nlohmann::json(ref_t_ours) : nlohmann::json(nullptr)},
          {"referee_t_closer", ref_t_closer},
          {"confirmed", confirmed},
          {"line", line()}};
}

// ---- result ------------------------------------------------------------------------------------

KindCounts ExactnessResult::total() const {
  KindCounts t;
  for (const KindCounts& k : by_kind) t += k;
  return t;
}

std::string ExactnessResult::failure() const {
  const KindCounts t = total();
  std::string why;
  auto add = [&](const std::string& s) { why += (why.empty() ? "" : "; ") + s; };
  const QueryCounts& c = t.query[0];
  const QueryCounts& a = t.query[1];
  // A walk miss the referee does not confirm (it puts our triangle at least as near: coplanar
  // triangles, or the float triangle test's own error) is reported, not failed: the goal is no
  // nearer triangle missed that exact arithmetic confirms.
  const uint64_t confirmed = c.walk_misses_confirmed + a.walk_misses_confirmed;
  if (confirmed)
    add(std::to_string(confirmed) + " walk misses confirmed by the referee (" +
        std::to_string(c.walk_misses_confirmed) + " closest-hit, " +
        std::to_string(a.walk_misses_confirmed) + " any-hit; " +
        std::to_string(c.walk_misses + a.walk_misses) + " walk misses in all)");
  const uint64_t wrong = c.ours_right + c.embree_right + a.ours_right + a.embree_right;
  if (wrong)
    add(std::to_string(wrong) + " disagreements beyond ties and grazes (" +
        std::to_string(c.ours_right + a.ours_right) + " ours right, " +
        std::to_string(c.embree_right + a.embree_right) + " Embree right)");
  // Grazes are resolved (the referee shows the hit changes within its perturbation), and a
  // traversal that loses hits is caught as walk misses by brute force: unlike the cross-check,
  // the check sets no limit on their rate (shadow rays aimed at a tessellated light graze it
  // by construction; docs/bvh.md, "Exactness check").
  if (search_mismatches)
    add(std::to_string(search_mismatches) + " of " + std::to_string(search_checks) +
        " brute-force searches gave another hit than brute_force_closest");
  if (c.compared == 0)
    add("no ray compared (" + std::to_string(t.rays) + " rays: " + std::to_string(t.invalid_rays) +
        " invalid, " + std::to_string(t.outside_embree) + " outside Embree's range)");
  else if (double(c.compared) < kMinComparedFraction * double(t.rays))
    add("only " + std::to_string(c.compared) + " of " + std::to_string(t.rays) + " rays compared");
  return why;
}

nlohmann::json ExactnessResult::to_json() const {
  nlohmann::json j;
  j["scene"] = scene;
  j["embree"] = embree;
  j["triangles"] = triangles;
  j["min_rays"] = min_rays;
  j["seconds"] = seconds;
  j["passed"] = passed();
  if (!passed()) j["failure"] = failure();
  j["criteria"] =
      "every ray traced as a closest-hit (closest_hit vs rtcIntersect1) and an any-hit query "
      "(any_hit vs rtcOccluded1); a disagreement (hit/miss, primitive, or t) is resolved by the "
      "double-precision referee: ours right, Embree right, tie (two primitives at the same t "
      "within delta/(|d| cos theta)), graze (the hit changes within delta = 128*FLT_EPSILON*M) "
      "or t rounding (the same primitive, t within the tolerance); a walk miss: our walk returned "
      "a farther hit or none although our own float triangle test accepts a nearer triangle in "
      "[tnear, tfar] (brute_force_closest, run on rays that disagree on hit/miss, primitive or t "
      "beyond the tolerance, or whose closest-hit and any-hit walks disagree), confirmed when the "
      "referee also puts that triangle nearer. Passes with no confirmed walk miss, no disagreement "
      "but ties, grazes and t rounding";
  nlohmann::json fr = nlohmann::json::array();
  for (const FrameInfo& f : frames)
    fr.push_back({{"seed", f.seed},
                  {"resolution", {f.width, f.height}},
                  {"spp", f.spp},
                  {"effects", f.effects},
                  {"camera_samples", f.camera_samples}});
  j["frames"] = fr;
  auto kind_json = [&](const KindCounts& k) {
    return nlohmann::json{{"rays", k.rays},
                          {"invalid_rays", k.invalid_rays},
                          {"outside_embree_range", k.outside_embree},
                          {"closest", k.query[0].to_json()},
                          {"any", k.query[1].to_json()}};
  };
  nlohmann::json bk = nlohmann::json::object();
  for (int k = 0; k < kNumStudyKinds; ++k) {
    if (!asked[k]) continue;
    nlohmann::json e = kind_json(by_kind[k]);
    e["note"] = note[k].empty() ? nlohmann::json(nullptr) : nlohmann::json(note[k]);
    bk[std::string(study_kind_name(StudyKind(k)))] = e;
  }
  j["by_kind"] = bk;
  j["total"] = kind_json(total());
  j["replayed"] = replayed;
  j["search_checks"] = search_checks;
  j["search_mismatches"] = search_mismatches;
  nlohmann::json wm = nlohmann::json::array();
  for (const WalkMiss& m : walk_misses) wm.push_back(m.to_json());
  j["walk_misses"] = wm;
  j["examples"] = examples;
  return j;
}

// ---- the check ---------------------------------------------------------------------------------

namespace {

struct StopFrame {};  // thrown from generate_rays' sink when a frame is no longer needed

class Checker {
 public:
  Checker(const Scene& s, const Bvh& b, const EmbreeScene& e, const ExactnessOptions& o,
          ExactnessResult& r)
      : scene_(s), bvh_(b), emb_(e), opt_(o), res_(r), fast_(b) {}

  /// Checks one ray of kind k; walk_hit: our closest-hit walk's result when already known.
  void check(const Ray& ray, StudyKind k, const Hit* walk_hit) {
    KindCounts& kc = res_.by_kind[static_cast<int>(k)];
    kc.rays++;
    if (validate_ray(ray) != RayError::kNone) {
      kc.invalid_rays++;
      return;
    }
    if (!embree_accepts(ray)) {
      kc.outside_embree++;
      return;
    }
    Traces tr;
    Counters c;
    if (opt_.closest_walk)
      tr.ours_closest = opt_.closest_walk(bvh_, ray);
    else
      tr.ours_closest = walk_hit ? *walk_hit : closest_hit(bvh_, ray, &c);
    tr.ours_any = opt_.any_walk ? opt_.any_walk(bvh_, ray) : any_hit(bvh_, ray, &c);
    tr.embree_closest = emb_.intersect(ray);
    tr.embree_occluded = emb_.occluded(ray);
    std::optional<Hit> brute;
    const Verdict vc = judge_closest(scene_, bvh_, ray, tr, &brute, &fast_);
    const Verdict va = judge_any(scene_, bvh_, ray, tr, &brute, &fast_);
    record(k, Query::kClosest, ray, tr, tr.ours_closest, vc);
    record(k, Query::kAny, ray, tr, tr.ours_any, va);
    // BruteForce against brute_force_closest: on every walk miss (judge_*), and on every 64th ray
    // it ran on.
    for (const Verdict* v : {&vc, &va})
      if (v->walk_miss || v->search_mismatch) {
        res_.search_checks++;
        res_.search_mismatches += v->search_mismatch;
      }
    if (brute && !vc.walk_miss && !va.walk_miss && (searches_++ & 63) == 0) {
      res_.search_checks++;
      res_.search_mismatches += !same_hit(*brute, brute_force_closest(bvh_, ray));
    }
  }

 private:
  void record(StudyKind k, Query q, const Ray& ray, const Traces& tr, const Hit& ours,
              const Verdict& v) {
    QueryCounts& qc = res_.by_kind[static_cast<int>(k)].query[static_cast<int>(q)];
    qc.add(v);
    qc.hits += ours.hit();
    if (v.walk_miss) {
      WalkMiss m;
      m.kind = k;
      m.query = q;
      m.ray = ray;
      m.ours = ours;
      m.closer = v.closer;
      m.ref_t_ours = v.ref_t_ours;
      m.ref_t_closer = v.ref_t_closer;
      m.confirmed = v.confirmed;
      res_.walk_misses.push_back(m);
      if (opt_.on_walk_miss) opt_.on_walk_miss(m);
    }
    if ((v.side == Verdict::Side::kOurs || v.side == Verdict::Side::kEmbree) &&
        res_.examples.size() < opt_.max_examples) {
      static const char* what[] = {"agree", "hit", "primitive", "t"};
      // The referee on both sides' triangles: t and |cos theta|.
      auto ref = [&](const Hit& h) -> std::string {
        if (!h.hit()) return "";
        const RefereeHit r = referee_intersect(ray, scene_.triangles[h.prim]);
        char s[96];
        std::snprintf(s, sizeof s, " (referee t %.9g, cos %.3g%s)", r.t, r.cos_theta,
                      r.hit ? "" : ", outside");
        return s;
      };
      char b[768];
      std::snprintf(b, sizeof b,
                    "%s disagreement (%s right): %s %s ray org %s dir %s tnear %a tfar %a; ours "
                    "prim %d t %a%s; embree prim %d t %a%s occluded %d",
                    what[int(v.what)], v.side == Verdict::Side::kOurs ? "ours" : "Embree",
                    std::string(study_kind_name(k)).c_str(), std::string(query_name(q)).c_str(),
                    hex3(ray.org).c_str(), hex3(ray.dir).c_str(), ray.tnear, ray.tfar,
                    ours.hit() ? int(ours.prim) : -1, ours.t, ref(ours).c_str(),
                    tr.embree_closest.hit() ? int(tr.embree_closest.prim) : -1, tr.embree_closest.t,
                    ref(tr.embree_closest).c_str(), int(tr.embree_occluded));
      res_.examples.push_back(b);
    }
  }

  const Scene& scene_;
  const Bvh& bvh_;
  const EmbreeScene& emb_;
  const ExactnessOptions& opt_;
  ExactnessResult& res_;
  const BruteForce fast_;
  uint64_t searches_ = 0;
};

std::string effects_string(const WorkloadOptions& wo) {
  std::string s;
  auto add = [&](bool on, const char* n) {
    if (on) s += (s.empty() ? "" : ",") + std::string(n);
  };
  add(wo.shadow, "shadow");
  add(wo.ao, "ao");
  add(wo.reflection, "reflection");
  add(wo.refraction, "refraction");
  add(wo.diffuse, "diffuse");
  return s.empty() ? "none" : s;
}

}  // namespace

void check_rays(const Scene& scene, const Bvh& bvh, const EmbreeScene& embree,
                const std::vector<std::pair<Ray, StudyKind>>& rays, const ExactnessOptions& opt,
                ExactnessResult* res) {
  Checker chk(scene, bvh, embree, opt, *res);
  for (const auto& [r, k] : rays) {
    res->asked[static_cast<int>(k)] = true;
    chk.check(r, k, nullptr);
    res->replayed++;
  }
}

ExactnessResult check_exactness(const Scene& scene, const Bvh& bvh, const ExactnessOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  EmbreeScene embree(scene.triangles, opt.embree_config, /*robust=*/true);
  ExactnessResult res;
  res.scene = scene.path;
  res.embree = embree.description();
  res.triangles = scene.triangles.size();
  res.min_rays = opt.min_rays;
  res.asked = opt.kinds;

  // What the scene can produce.
  const EffectChoice eff = derive_effects(scene);
  std::array<bool, kNumStudyKinds> active = opt.kinds;
  auto impossible = [&](StudyKind k, bool possible, const std::string& why) {
    const int i = static_cast<int>(k);
    if (active[i] && !possible) {
      active[i] = false;
      res.note[i] = "the scene has none: " + why;
    }
  };
  impossible(StudyKind::kShadow, eff.shadow, eff.shadow_why);
  impossible(StudyKind::kReflection, eff.reflection, eff.reflection_why);
  impossible(StudyKind::kRefraction, eff.refraction, eff.refraction_why);

  // The frame.
  int w = opt.width, h = opt.height, spp = std::max(1, opt.spp);
  if (w <= 0 || h <= 0)
    resolution_for(scene.camera, std::min<uint64_t>(opt.min_rays, uint64_t{1} << 20), spp, &w, &h);
  const uint64_t frame_samples = uint64_t(w) * uint64_t(h) * uint64_t(spp);
  const uint64_t max_samples = opt.max_samples ? opt.max_samples : 16 * opt.min_rays;

  const uint64_t n = opt.min_rays;
  uint64_t wanted = 0;
  for (int k = 0; k < kNumStudyKinds; ++k) wanted += active[k] ? n : 0;
  auto needs = [&](StudyKind k) {
    const int i = static_cast<int>(k);
    return active[i] && res.by_kind[i].rays < n;
  };
  auto done_rays = [&] {
    uint64_t d = 0;
    for (int k = 0; k < kNumStudyKinds; ++k)
      if (active[k]) d += std::min(res.by_kind[k].rays, n);
    return d;
  };

  Checker chk(scene, bvh, embree, opt, res);
  uint64_t samples = 0, checked = 0;
  for (uint64_t f = 0;; ++f) {
    bool any = false;
    for (int k = 0; k < kNumStudyKinds; ++k) any |= needs(StudyKind(k));
    if (!any || samples >= max_samples) break;
    WorkloadOptions wo;
    wo.width = w;
    wo.height = h;
    wo.spp = spp;
    wo.seed = opt.seed + f;
    wo.max_depth = opt.max_depth;
    wo.shadow = needs(StudyKind::kShadow);
    wo.ao = needs(StudyKind::kAo) || needs(StudyKind::kAoShort);
    wo.reflection = needs(StudyKind::kReflection);
    wo.refraction = needs(StudyKind::kRefraction);
    wo.diffuse = needs(StudyKind::kDiffuse);
    FrameInfo fi{wo.seed, w, h, spp, effects_string(wo), 0};
    auto one = [&](const Ray& r, StudyKind k, const Hit* hit) {
      if (!needs(k)) return;
      chk.check(r, k, hit);
      if ((++checked & 0xFFF) == 0 && opt.progress) opt.progress(done_rays(), wanted);
    };
    try {
      generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit* hit) {
        switch (r.kind) {
          case RayKind::kPrimary:
            if (samples >= max_samples) throw StopFrame{};
            samples++;
            fi.camera_samples++;
            one(r.ray, StudyKind::kPrimary, hit);
            break;
          case RayKind::kShadow:
            one(r.ray, StudyKind::kShadow, nullptr);
            break;
          case RayKind::kAo: {
            one(r.ray, StudyKind::kAoShort, nullptr);
            Ray unbounded = r.ray;  // MICRO 2021's AO: the same ray, unbounded
            unbounded.tfar = kInf;
            one(unbounded, StudyKind::kAo, nullptr);
            break;
          }
          case RayKind::kReflection:
            one(r.ray, StudyKind::kReflection, hit);
            break;
          case RayKind::kRefraction:
            one(r.ray, StudyKind::kRefraction, hit);
            break;
          case RayKind::kDiffuse:
            one(r.ray, StudyKind::kDiffuse, hit);
            break;
        }
        for (int k = 0; k < kNumStudyKinds; ++k)
          if (needs(StudyKind(k))) return;
        throw StopFrame{};
      });
    } catch (const StopFrame&) {
    }
    res.frames.push_back(fi);
    // A kind of which a whole frame gave no ray gets none from more frames of the same size
    // (only the seed changes): it is reported as short rather than run to the cap.
    if (fi.camera_samples == frame_samples)
      for (int k = 0; k < kNumStudyKinds; ++k)
        if (needs(StudyKind(k)) && res.by_kind[k].rays == 0) {
          active[k] = false;
          res.note[k] = "none in a whole frame of " + std::to_string(frame_samples) +
                        " camera samples (the scene produces none, or nearly none)";
        }
  }
  for (int k = 0; k < kNumStudyKinds; ++k) {
    if (!active[k] || res.by_kind[k].rays >= n) continue;
    char b[200];
    std::snprintf(
        b, sizeof b, "%llu of %llu rays: %llu camera samples (the cap) gave %.3g per camera sample",
        (unsigned long long)res.by_kind[k].rays, (unsigned long long)n, (unsigned long long)samples,
        samples ? double(res.by_kind[k].rays) / double(samples) : 0.0);
    res.note[k] = b;
  }
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace hrpp
