// The table update delay of the RTL pipeline (docs/cost_model.md, "Pipeline latency"), derived
// from the cycle model of the RTL's default configuration.
#pragma once

#include <cstdint>

namespace hrpp {

/// Rays issued between a ray's lookup and the first lookup that sees its table write, in the
/// RTL (the cycle model, default configuration) at one ray per cycle, when the traversal engine
/// answers an empty prediction in 1 cycle and takes `walk_latency` cycles from the skip decision
/// to the ray's final outcome. This is PredictorConfig::update_delay for that pipeline.
uint32_t rtl_update_delay(uint32_t walk_latency);

}  // namespace hrpp
