// Embree 3 as the reference tracer (cross-check and benchmark only). Rays must be valid
// (validate_ray): Debian's Embree 3.13.5 aborts on NaN/inf fields and tnear < 0.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hrpp/geometry.h"
#include "hrpp/ray.h"
#include "hrpp/traverse.h"

namespace hrpp {

/// The pinned configuration the cross-check compares against: one thread, SSE4.2 kernels (the
/// AVX2 and SSE4.2 paths differ in the last ulp of t), robust scene flag, high build quality.
constexpr const char* kEmbreeReferenceConfig = "threads=1,isa=sse4.2";

class EmbreeScene {
 public:
  /// robust: RTC_SCENE_FLAG_ROBUST (watertight, no fast-path shortcuts); high_quality:
  /// RTC_BUILD_QUALITY_HIGH, else Embree's default (medium). Throws on error.
  EmbreeScene(const std::vector<Triangle>& tris, const std::string& device_config, bool robust,
              bool high_quality = true);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// Closest hit (prim = scene triangle index; leaf is not set).
  Hit intersect(const Ray& r) const;
  /// True when anything is hit in [tnear, tfar].
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
