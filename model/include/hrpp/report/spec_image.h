// The image error of speculative closest hits (docs/cost_model.md): the exact and the
// speculative picture of the primary rays and their difference. In the report library
// (hrpp_report): it writes pictures.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrpp/predictor/predictor.h"
#include "hrpp/scene/scene.h"
#include "hrpp/workload/workload.h"

namespace hrpp {

/// Speculative closest hits against the exact image. Per camera sample, the primary ray's
/// baseline hit and the predictor's answer are shaded the same way (base colour under a light at
/// the eye); the pictures are the per-pixel means.
class SpecImage {
 public:
  /// CONFIG names the predictor configuration in the picture ("preset rtl-primary: hash ...",
  /// or config_caption's line of hrpp/report/render.h); empty: the picture says it is unknown.
  SpecImage(const Scene& scene, int width, int height, int spp, std::string config = "");
  /// Adds one primary ray's two answers (other kinds are ignored).
  void add(const RayRecord& r, const RayResult& res);
  /// Mean absolute error (0..1, over pixels and colour channels, 8-bit sRGB values / 255),
  /// share of pixels that differ, wrong primary samples. Writes DIR/spec_compare.png (exact |
  /// speculative | difference x8, each panel named, with a legend band that explains them and
  /// names the scene, the workload and the configuration; its lines in "legend") when dir is not
  /// empty (throws RenderError naming the file).
  nlohmann::json finish(const std::string& dir) const;

 private:
  const Scene& scene_;
  int width_, height_, spp_;
  std::string config_;
  std::vector<float> exact_, spec_;  // linear RGB sums
  uint64_t samples_ = 0, wrong_ = 0;
};

}  // namespace hrpp
