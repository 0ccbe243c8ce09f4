// What accuracy costs in time (docs/cost_model.md): a cycle cost model of a ray-tracing unit
// applied to the predictor's work counters, the table update delay of the RTL pipeline derived
// from the cycle model, and the image error of speculative closest hits.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrpp/predictor.h"
#include "hrpp/rtl_config_data.h"
#include "hrpp/scene.h"
#include "hrpp/workload.h"

namespace hrpp {

/// Latencies, in cycles, of one ray's dependent chain of work on a ray-tracing unit. Every
/// constant's reasoning is in docs/cost_model.md; the sweep's Pareto fronts use these.
struct CostModel {
  uint32_t node_fetch = 32;   // one BVH node (or a leaf's triangles) from the unit's L1 cache
  uint32_t box_test = 8;      // one ray/box slab test (a node's two children in parallel)
  uint32_t tri_test = 20;     // one watertight ray/triangle test
  // The RTL's (rtl/config/hrpp_configs.json): a ray accepted to its prediction (A, the hash
  // stages, B, the lookup stages, the prediction FIFO); a predicted-walk result to its skip
  // decision (P0, the skip FIFO).
  uint32_t lookup = rtl::kPredictionLatency;
  uint32_t decision = rtl::kDecisionLatency;
  uint32_t mispredict = 4;    // a failed prediction: restart the walk at the root
  nlohmann::json to_json() const;
};

/// Cycles of the baseline walks and of HRPP (lookup, decision, predicted walks, full walks,
/// mispredict penalties) for these statistics.
struct CycleCost {
  double baseline = 0, hrpp = 0;
  double saved_fraction() const { return baseline > 0 ? 1.0 - hrpp / baseline : 0.0; }
};
CycleCost cycle_cost(const PredictStats& s, const CostModel& m);
/// {"baseline_cycles", "hrpp_cycles", "saved_cycle_fraction", per ray figures}.
nlohmann::json cycle_cost_json(const PredictStats& s, const CostModel& m);

/// Rays issued between a ray's lookup and the first lookup that sees its table write, in the
/// RTL (the cycle model, default configuration) at one ray per cycle, when the traversal engine
/// answers an empty prediction in 1 cycle and takes `walk_latency` cycles from the skip decision
/// to the ray's final outcome. This is PredictorConfig::update_delay for that pipeline.
uint32_t rtl_update_delay(uint32_t walk_latency);

/// Speculative closest hits against the exact image. Per camera sample, the primary ray's
/// baseline hit and the predictor's answer are shaded the same way (base colour under a light at
/// the eye); the pictures are the per-pixel means.
class SpecImage {
 public:
  SpecImage(const Scene& scene, int width, int height, int spp);
  /// Adds one primary ray's two answers (other kinds are ignored).
  void add(const RayRecord& r, const RayResult& res);
  /// Mean absolute error (0..1, over pixels and colour channels, 8-bit sRGB values / 255),
  /// share of pixels that differ, wrong primary samples. Writes DIR/spec_compare.png (exact |
  /// speculative | difference x8) when dir is not empty (throws RenderError naming the file).
  nlohmann::json finish(const std::string& dir) const;

 private:
  const Scene& scene_;
  int width_, height_, spp_;
  std::vector<float> exact_, spec_;  // linear RGB sums
  uint64_t samples_ = 0, wrong_ = 0;
};

}  // namespace hrpp
