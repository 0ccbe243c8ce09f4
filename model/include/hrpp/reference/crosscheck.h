// Cross-check of our BVH traversal against Embree on the same rays, with a double-precision
// referee (hrpp/trace/referee.h) that separates genuine ties and grazes from real disagreements.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hrpp/reference/embree_ref.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/trace/ray.h"
#include "hrpp/trace/referee.h"

namespace hrpp {

/// A cross-check must compare at least this fraction of the rays it was given or generated (of
/// the kinds asked for), and at least one: a check that compared nothing proves nothing.
constexpr double kMinComparedFraction = 0.99;

struct CrossCheckCounts {
  uint64_t rays = 0;             // generated
  uint64_t invalid_rays = 0;     // rejected by validate_ray, never traced nor sent to Embree
  uint64_t outside_embree = 0;   // valid, but outside Embree's range (embree_accepts): not sent
  uint64_t compared = 0;         // valid rays traced by both
  uint64_t hit_agree = 0;        // hit/miss agreement
  uint64_t hit_mismatches = 0;   // disagreements the referee does not explain
  uint64_t grazes = 0;           // hit/miss disagreements the referee shows to be grazes
  uint64_t t_mismatches = 0;     // same hit, t outside the tolerance
  uint64_t prim_mismatches = 0;  // different primitive, not a tie
  uint64_t ties = 0;             // different primitive, both hit at the same t (genuine tie)
  uint64_t hits = 0;             // rays our BVH reports as hitting

  CrossCheckCounts& operator+=(const CrossCheckCounts& o);
  double hit_agreement() const { return compared ? double(hit_agree) / compared : 1.0; }
};

struct CrossCheckOptions {
  uint64_t rays = 100000;  // camera samples; secondary rays come on top
  std::vector<RayKind> kinds{RayKind::kPrimary, RayKind::kShadow, RayKind::kAo};
  uint64_t seed = 1;
  std::string embree_config = kEmbreeReferenceConfig;
  size_t max_examples = 8;
  /// Called with the camera samples done of width x height, every 4096 (progress).
  std::function<void(uint64_t done, uint64_t total)> progress;
};

struct CrossCheckResult {
  std::string scene;
  std::string embree;
  CrossCheckCounts total;
  std::array<CrossCheckCounts, kNumRayKinds> by_kind{};
  int width = 0, height = 0;
  double seconds = 0;
  std::vector<std::string> examples;  // descriptions of the first disagreements

  /// True when at least kMinComparedFraction of the rays (and at least one) were compared, there
  /// is no hit, t or primitive mismatch, and genuine grazes are below 1e-5 of the compared rays.
  bool passed() const;
  /// Why the check failed ("" when it passed).
  std::string failure() const;
  nlohmann::json to_json() const;
};

/// Traces the workload (camera rays and the shadow / AO rays spawned from their hits) with our
/// BVH and with Embree and compares them. Rays of kinds not in opt.kinds are generated (primary
/// hits are needed for secondary rays) but not compared or counted.
CrossCheckResult cross_check(const Scene& scene, const Bvh& bvh, const CrossCheckOptions& opt);

/// Compares an explicit list of rays (each with its kind) against Embree.
CrossCheckResult cross_check_rays(const Scene& scene, const Bvh& bvh, const EmbreeScene& embree,
                                  const std::vector<std::pair<Ray, RayKind>>& rays,
                                  size_t max_examples = 8);

}  // namespace hrpp
