// Embree 3 as the reference tracer (cross-check and benchmark only). Rays must be valid
// (validate_ray) and inside Embree's range (embree_accepts): Debian's Embree 3.13.5 aborts on
// NaN/inf fields, tnear < 0 and origin or direction components of magnitude FLT_LARGE or more.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hrpp/scene/geometry.h"
#include "hrpp/trace/ray.h"
#include "hrpp/trace/traverse.h"

namespace hrpp {

/// The pinned configuration the cross-check compares against: one thread, SSE4.2 kernels (the
/// AVX2 and SSE4.2 paths differ in the last ulp of t), robust scene flag, high build quality.
constexpr const char* kEmbreeReferenceConfig = "threads=1,isa=sse4.2";

/// Embree's FLT_LARGE (common/math/constants.h): its ray validity assertion requires every origin
/// and direction component to lie strictly between -FLT_LARGE and FLT_LARGE (measured on this
/// machine's Embree: an origin of 1.8439e18 is traced, 1.8441e18 aborts, in rtcIntersect1 and
/// rtcOccluded1 alike). Directions are already bounded by validate_ray (kMaxDirection).
constexpr float kEmbreeLarge = 1.844e18f;

/// True when a valid ray (validate_ray) may be sent to Embree: its origin is inside Embree's
/// range. The cross-check counts the others apart (outside_embree) and never sends them.
inline bool embree_accepts(const Ray& r) {
  return validate_ray(r) == RayError::kNone && max_abs(r.org) < kEmbreeLarge &&
         max_abs(r.dir) < kEmbreeLarge;
}

class EmbreeScene {
 public:
  /// robust: RTC_SCENE_FLAG_ROBUST (watertight, no fast-path shortcuts); high_quality:
  /// RTC_BUILD_QUALITY_HIGH, else Embree's default (medium). Throws on error.
  EmbreeScene(const std::vector<Triangle>& tris, const std::string& device_config, bool robust,
              bool high_quality = true);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// Closest hit (prim = scene triangle index; leaf is not set). The ray must be valid; one whose
  /// origin is outside Embree's range throws std::invalid_argument instead of aborting.
  Hit intersect(const Ray& r) const;
  /// True when anything is hit in [tnear, tfar]. The same precondition as intersect.
  bool occluded(const Ray& r) const;

  double build_seconds() const { return build_seconds_; }
  /// "Embree 3.13.5, threads=1,isa=sse4.2, robust" and similar.
  std::string description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double build_seconds_ = 0;
};

}  // namespace hrpp
