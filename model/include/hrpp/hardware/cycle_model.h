// Cycle-accurate model of the RTL's interface behaviour (rtl/hrpp_top.sv,
// docs/microarchitecture.md). It reuses the golden model's hash (hash.h) and table (pred_table.h):
// the table's update pipeline forwards every hazard, so applying each update to a PredTable in
// the cycle the RTL writes it reproduces the RTL's table, and a lookup sees every write presented
// in the cycle of its read or earlier. Everything but the table is the lane (LaneModel,
// lane_model.h: rtl/hrpp_lane.sv), which LanesCycleModel (cycle_model_lanes.h) uses too.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include "hrpp/hardware/cycle_common.h"  // CycleConfig, DutIn, DutOut, CycleStats
#include "hrpp/hardware/lane_model.h"

namespace hrpp {

class CycleModel {
 public:
  /// One lane (cfg.lanes == 1; more lanes: LanesCycleModel); throws std::invalid_argument else.
  explicit CycleModel(const CycleConfig& cfg);
  /// rst_ni low for one cycle (call once per clock cycle of the reset): every register and FIFO
  /// is cleared and the table clear starts again (the table's contents are lost). The key store
  /// (distributed RAM without reset in the RTL) keeps its contents, as in the RTL; reading an
  /// entry not written since the reset is a protocol error (error()).
  void reset();
  /// A protocol violation seen: a predicted-walk result or final outcome accepted for a ray id
  /// whose key-store entry was not written since the last reset (it would read stale contents).
  /// Also set if the table ever differs from the golden model's table with every update request
  /// taken applied in order, the merged ones too (a merge that is not exact).
  const std::string& error() const { return error_; }
  const CycleStats& stats() const { return stats_; }
  DutOut outputs() const;
  /// One rising clock edge with these inputs.
  void tick(const DutIn& in);
  uint64_t cycle() const { return cycle_; }
  const PredTable& table() const { return table_; }

 private:
  using Op = LaneModel::Op;
  void check_against_requests(const Op& written);

  CycleConfig cfg_;
  PredTable table_;
  uint64_t cycle_ = 0;
  bool clearing_ = true;
  uint32_t clear_idx_ = 0;
  // The lane (lane_model.h): everything but the table; its lookups go straight to the table.
  LaneModel lane_;
  std::string error_;
  CycleStats stats_;
  // Every request the table took (issued or merged), in order, until a write applies it (with
  // those before it and those merged into it) to requested_: the golden model's table with every
  // request applied, which the table must equal.
  std::deque<Op> requests_;
  PredTable requested_;
  uint64_t next_seq_ = 0;
  // The table's update pipeline after the lane's update queue: T0, T1, T2, C1, C2, C3, W.
  static constexpr int kUpdateStages = rtl::kUpdateStages;
  std::array<std::optional<Op>, kUpdateStages> up_;  // [0] = T0 ... [6] = W
  std::optional<Op> issue_;  // the issue register I before T0 (cfg_.issue_reg)
};

}  // namespace hrpp
