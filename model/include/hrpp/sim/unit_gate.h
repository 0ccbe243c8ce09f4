// The RT unit's gate (docs/timing_model.md, "The gate"; SimOptions::gate): the unit gets its
// predictor out of the way when the predictor brings nothing. It is the unit's, not the
// predictor's: one counter per unit, loaded with N on a predicted hit (a skip or shrink decision),
// decremented by every answered lookup, saturating at 0. At 0 the gate is closed: a ray that
// cannot enter the predictor in its first cycle walks from the root without it; rays that enter
// at once keep looking up, and the next predicted hit opens the gate. N = 0: no gate. Before the
// unit's first predicted hit the counter starts at `first` (default N): a shorter first probe
// costs a predictor that never predicts fewer waits.
#pragma once

#include <cstdint>
#include <optional>

namespace hrpp::sim {

class UnitGate {
 public:
  explicit UnitGate(uint32_t n = 0, std::optional<uint32_t> first = {})
      : n_(n), left_(first.value_or(n)) {}
  /// A lookup's prediction came back.
  void on_lookup() {
    if (left_ > 0) --left_;
  }
  /// A predicted hit (the skip decision was skip or shrink); true when it opened a closed gate.
  bool on_predicted_hit() {
    const bool opened = closed();
    left_ = n_;
    return opened;
  }
  bool closed() const { return n_ > 0 && left_ == 0; }

 private:
  uint32_t n_, left_;
};

}  // namespace hrpp::sim
