// The exactness check (docs/bvh.md, "Exactness check"): every ray kind of the studies' workloads,
// each ray traced as a closest-hit and as an any-hit query by our walk and by Embree, every
// disagreement resolved by the double-precision referee (hrpp/trace/referee.h), and "walk
// misses" counted exactly: our walk returned a farther hit, or none, although our own float
// triangle test accepts a nearer triangle in [tnear, tfar] (confirmed by brute_force_closest).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hrpp/reference/embree_ref.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/trace/ray.h"
#include "hrpp/trace/traverse.h"

namespace hrpp {

/// The ray kinds of the studies (model/tools/sim_results.py, design_study.py) and of the
/// secondary-ray workloads. kAo is MICRO 2021's ambient occlusion (unbounded); kAoShort the
/// project's (5% of the scene diagonal). Both are the same AO rays of the workload, kAo with
/// tfar = +inf: the rays `--ao-distance inf` generates.
enum class StudyKind : uint8_t {
  kPrimary = 0,
  kShadow,
  kAo,
  kAoShort,
  kReflection,
  kRefraction,
  kDiffuse,
};
constexpr int kNumStudyKinds = 7;
/// "primary", "shadow", "ao", "ao-short", "reflection", "refraction", "diffuse".
std::string_view study_kind_name(StudyKind k);
bool parse_study_kind(std::string_view name, StudyKind* out);

/// The two queries every ray is traced as.
enum class Query : uint8_t { kClosest = 0, kAny = 1 };
std::string_view query_name(Query q);

/// How one query of one ray came out against Embree.
struct Verdict {
  /// What disagrees: nothing; hit against miss; the primitive; only t (same primitive).
  enum class What : uint8_t { kAgree, kHit, kPrim, kT } what = What::kAgree;
  /// Who is right by the referee: (a) ours, (b) Embree, or (c) neither is wrong: a tie (two
  /// primitives hit at the same t within the referee's tolerance), a graze (the hit changes within
  /// its perturbation), or rounding (the same primitive, t within the tolerance).
  enum class Side : uint8_t { kNone, kOurs, kEmbree, kTie, kGraze, kRounding } side = Side::kNone;
  bool brute_forced = false;  // brute_force_closest was run on the ray
  /// Our walk returned a farther hit or none although our own triangle test accepts `closer`,
  /// nearer, in [tnear, tfar] (brute_force_closest). For the any-hit query: our any-hit walk
  /// found nothing although our triangle test accepts `closer`.
  bool walk_miss = false;
  /// The referee agrees: `closer`'s triangle is hit in double precision, nearer than ours.
  bool confirmed = false;
  bool search_mismatch = false;             // BruteForce's hit differed from brute_force_closest's
  Hit closer;                               // brute force's hit, when walk_miss
  double ref_t_ours = 0, ref_t_closer = 0;  // the referee's t of our triangle and of `closer`'s
};

/// brute_force_closest with a bounding-box pre-test: each triangle's box, widened by 2^-12 of its
/// largest coordinate magnitude and of the ray origin's, is tested against [tnear, limit] widened
/// by 2^-12 before the triangle test, so that only triangles far from the ray are skipped; the
/// triangles are tested in brute_force_closest's order with its limit, so the hit is the same, bit
/// for bit (Exactness.FastBruteForceIsBruteForce; the check also compares the two on a sample of
/// its rays and on every walk miss). About ten times faster.
class BruteForce {
 public:
  explicit BruteForce(const Bvh& bvh);
  Hit closest(const Ray& ray) const;

 private:
  const Bvh& bvh_;
  std::array<std::vector<float>, 3> lo_, hi_;  // per triangle of bvh.tris, widened
};

/// What one ray's four traces gave: our closest-hit and any-hit walks, Embree's rtcIntersect1 and
/// rtcOccluded1.
struct Traces {
  Hit ours_closest, ours_any, embree_closest;
  bool embree_occluded = false;
};

/// Judges the closest-hit query of a valid ray. Brute force (our triangle test on every
/// triangle) runs when the hit or the primitive disagrees, when t disagrees beyond the referee's
/// tolerance, and when our any-hit walk hit but our closest-hit walk did not. *brute caches its
/// hit for the ray: fast's when given, else brute_force_closest's; a walk miss is always decided
/// by brute_force_closest (Verdict::search_mismatch: fast's hit was another).
Verdict judge_closest(const Scene& scene, const Bvh& bvh, const Ray& ray, const Traces& tr,
                      std::optional<Hit>* brute, const BruteForce* fast = nullptr);
/// Judges the any-hit query. Brute force runs when our any-hit walk and Embree disagree, or our
/// any-hit and closest-hit walks disagree on hit against miss.
Verdict judge_any(const Scene& scene, const Bvh& bvh, const Ray& ray, const Traces& tr,
                  std::optional<Hit>* brute, const BruteForce* fast = nullptr);

struct QueryCounts {
  uint64_t compared = 0, hits = 0;  // hits: our walk's
  uint64_t agree = 0, hit_disagree = 0, prim_disagree = 0, t_disagree = 0;
  uint64_t ours_right = 0, embree_right = 0, ties = 0, grazes = 0, rounding = 0;
  uint64_t brute_forced = 0, walk_misses = 0, walk_misses_confirmed = 0;
  uint64_t disagreements() const { return hit_disagree + prim_disagree + t_disagree; }
  void add(const Verdict& v);
  QueryCounts& operator+=(const QueryCounts& o);
  nlohmann::json to_json() const;
};

struct KindCounts {
  uint64_t rays = 0;                   // of this kind, checked
  uint64_t invalid_rays = 0;           // rejected by validate_ray: never traced
  uint64_t outside_embree = 0;         // valid, outside Embree's range: never sent to it
  std::array<QueryCounts, 2> query{};  // by Query
  KindCounts& operator+=(const KindCounts& o);
};

/// One frame: a workload of generate_rays (the options `hrpp predict` would take).
struct FrameInfo {
  uint64_t seed = 0;
  int width = 0, height = 0, spp = 0;
  std::string effects;          // "shadow,ao,diffuse"
  uint64_t camera_samples = 0;  // generated (the last frame stops when every kind is done)
};

/// A walk miss as a regression test needs it.
struct WalkMiss {
  StudyKind kind = StudyKind::kPrimary;
  Query query = Query::kClosest;
  Ray ray;
  Hit ours, closer;
  double ref_t_ours = 0, ref_t_closer = 0;
  bool confirmed = false;
  /// One line, every float in hex (%a): "KIND QUERY org X Y Z dir X Y Z tnear T tfar T ours
  /// PRIM T closer PRIM T referee T T confirmed|unconfirmed" (PRIM -1: no hit).
  std::string line() const;
  /// Parses line(): the kind, query and ray (the rest is ignored). False on a malformed line.
  static bool parse(const std::string& line, WalkMiss* out);
  nlohmann::json to_json() const;
};

struct ExactnessOptions {
  uint64_t min_rays = 10'000'000;  // rays per kind to check (each as both queries)
  uint64_t seed = 1;               // frame f (0, 1, ...) uses seed + f
  /// Frame size: 0 picks width x height at the camera's aspect with about min(min_rays, 2^20)
  /// camera samples and 1 spp.
  int width = 0, height = 0, spp = 0;
  /// Camera samples at most (0: 16 * min_rays); kinds still short then are reported as such.
  uint64_t max_samples = 0;
  std::array<bool, kNumStudyKinds> kinds{true, true, true, true, true, true, true};
  std::string embree_config = kEmbreeReferenceConfig;
  size_t max_examples = 16;
  int max_depth = 2;  // generations of reflection / refraction / diffuse rays (the default)
  /// Called with the rays checked so far and the rays asked for (every 4096 rays).
  std::function<void(uint64_t done, uint64_t total)> progress;
  /// Called with every walk miss as it is found (before the run ends).
  std::function<void(const WalkMiss&)> on_walk_miss;
  /// Our walks; empty: closest_hit and any_hit. Tests plant broken walks here.
  std::function<Hit(const Bvh&, const Ray&)> closest_walk, any_walk;
};

struct ExactnessResult {
  std::string scene, embree;
  size_t triangles = 0;
  uint64_t min_rays = 0;
  std::array<KindCounts, kNumStudyKinds> by_kind{};
  std::array<bool, kNumStudyKinds> asked{};
  std::array<std::string, kNumStudyKinds> note{};  // why a kind has fewer rays than asked
  std::vector<FrameInfo> frames;
  std::vector<WalkMiss> walk_misses;  // every one (the goal is none)
  std::vector<std::string> examples;  // the first other disagreements that fail the check
  uint64_t replayed = 0;              // rays of check_rays
  /// BruteForce compared with brute_force_closest: on every 64th ray it ran on and on every walk
  /// miss; mismatches fail the check.
  uint64_t search_checks = 0, search_mismatches = 0;
  double seconds = 0;

  KindCounts total() const;
  /// "" when passed: no walk miss that the referee confirms, no disagreement but ties, grazes
  /// and t rounding, at least kMinComparedFraction of the rays compared.
  std::string failure() const;
  bool passed() const { return failure().empty(); }
  nlohmann::json to_json() const;
};

/// Generates frames of the workload until every kind asked for has opt.min_rays rays (or cannot:
/// no lights, no reflecting or transmissive material, or max_samples reached) and checks each ray.
ExactnessResult check_exactness(const Scene& scene, const Bvh& bvh, const ExactnessOptions& opt);

/// Checks given rays (e.g. walk misses found before, WalkMiss::parse) into res (its by_kind,
/// walk_misses and examples; `replayed` counts them).
void check_rays(const Scene& scene, const Bvh& bvh, const EmbreeScene& embree,
                const std::vector<std::pair<Ray, StudyKind>>& rays, const ExactnessOptions& opt,
                ExactnessResult* res);

}  // namespace hrpp
