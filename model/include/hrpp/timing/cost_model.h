// What accuracy costs in time (docs/cost_model.md): a cycle cost model of a ray-tracing unit
// applied to the predictor's work counters. The table update delay of the RTL pipeline is in
// hrpp/hardware/rtl_update_delay.h, the image error of speculative closest hits in
// hrpp/report/spec_image.h (the report library hrpp_report).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>

#include "hrpp/predictor/predictor.h"
#include "hrpp/rtl_config_data.h"

namespace hrpp {

/// Latencies, in cycles, of one ray's dependent chain of work on a ray-tracing unit. Every
/// constant's reasoning is in docs/cost_model.md; the sweep's Pareto fronts use these.
struct CostModel {
  uint32_t node_fetch = 32;  // one BVH node (or a leaf's triangles) from the unit's L1 cache
  uint32_t box_test = 8;     // one ray/box slab test (a node's two children in parallel)
  uint32_t tri_test = 20;    // one watertight ray/triangle test
  // The RTL's (rtl/config/hrpp_configs.json): a ray accepted to its prediction (A, the hash
  // stages, B, the lookup stages, the prediction FIFO); a predicted-walk result to its skip
  // decision (P0, the skip FIFO).
  uint32_t lookup = rtl::kPredictionLatency;
  uint32_t decision = rtl::kDecisionLatency;
  uint32_t mispredict = 4;  // a failed prediction: restart the walk at the root
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

}  // namespace hrpp
