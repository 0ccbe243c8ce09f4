#include "hrpp/timing/cost_model.h"

#include <algorithm>

namespace hrpp {

nlohmann::json CostModel::to_json() const {
  return {{"node_fetch", node_fetch}, {"box_test", box_test}, {"tri_test", tri_test},
          {"lookup", lookup},         {"decision", decision}, {"mispredict", mispredict}};
}

// A walk's cycles: every interior node and every leaf is fetched; a node's two child boxes are
// tested in parallel, and a walk's start node has its own box tested first
// (box_tests - interior_tests box-test latencies in all); triangles one after another.
static double walk_cycles(const Counters& c, const CostModel& m) {
  return double(c.interior_tests + c.leaf_visits) * m.node_fetch +
         double(c.box_tests - c.interior_tests) * m.box_test + double(c.tri_tests) * m.tri_test;
}

CycleCost cycle_cost(const PredictStats& s, const CostModel& m) {
  CycleCost c;
  c.baseline = walk_cycles(s.baseline, m);
  const uint64_t valid = s.rays - s.invalid_rays;
  const uint64_t predicted = s.true_positive + s.false_positive;
  c.hrpp = walk_cycles(s.hrpp, m) + double(valid) * m.lookup + double(predicted) * m.decision +
           double(s.false_positive) * m.mispredict;
  return c;
}

nlohmann::json cycle_cost_json(const PredictStats& s, const CostModel& m) {
  const CycleCost c = cycle_cost(s, m);
  const double n = std::max<uint64_t>(1, s.rays);
  return {{"baseline_cycles", c.baseline},
          {"hrpp_cycles", c.hrpp},
          {"baseline_cycles_per_ray", c.baseline / n},
          {"hrpp_cycles_per_ray", c.hrpp / n},
          {"saved_cycle_fraction", c.saved_fraction()}};
}

}  // namespace hrpp
