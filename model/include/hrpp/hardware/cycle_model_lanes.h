// Cycle-accurate model of the multi-lane RTL (rtl/hrpp_lanes.sv; docs/microarchitecture.md,
// "Lanes"): Lanes (2 or 4) copies of hrpp_top's lane (LaneModel, lane_model.h: input registers,
// hash, key store, lookup queue, skip controller, prediction and skip FIFOs, update queue) around
// a table split by set into Lanes banks, each with hrpp_pred_table's lookup and update pipelines.
// Per bank and cycle one lookup and one update: round-robin among the lanes whose head asks for
// the bank, the pointer moving past the lane taken. CycleModel (cycle_model.h) is the one-lane
// design (hrpp_top); the interfaces of each lane are its DutIn / DutOut.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/hardware/lane_model.h"

namespace hrpp {

/// What the crossbars saw (cumulative over resets).
struct LanesStats {
  uint64_t lookups = 0;           // lookups issued to the banks
  uint64_t lookup_waits = 0;      // lane-cycles a lookup-queue head waited for its bank
  uint64_t max_lookup_queue = 0;  // the longest lookup queue seen
  uint64_t update_waits = 0;      // lane-cycles an update-queue head waited for another lane's
};

class LanesCycleModel {
 public:
  /// cfg.lanes 2 or 4; throws std::invalid_argument otherwise or for an invalid configuration.
  explicit LanesCycleModel(const CycleConfig& cfg);
  /// rst_ni low for one cycle (as CycleModel::reset).
  void reset();
  /// A protocol violation (a result for an id whose key-store entry was not written since the
  /// reset), or the table differing from the golden model's with every request applied.
  const std::string& error() const { return error_; }
  const CycleStats& stats() const { return stats_; }
  const LanesStats& lanes_stats() const { return lanes_stats_; }
  int lanes() const { return cfg_.lanes; }
  /// Lane `lane`'s outputs in this cycle (functions of the state only).
  DutOut outputs(int lane) const;
  /// One rising clock edge with each lane's inputs (in.size() == lanes()).
  void tick(const std::vector<DutIn>& in);
  uint64_t cycle() const { return cycle_; }
  const PredTable& table() const { return table_; }

 private:
  using Op = LaneModel::Op;
  static constexpr int kUpdateStages = rtl::kUpdateStages;
  struct Bank {
    std::array<std::optional<Op>, kUpdateStages> up;  // [0] = T0 ... [6] = W
    std::optional<Op> issue;  // the issue register I before T0 (cfg_.issue_reg)
    std::deque<Op> requests;  // taken (issued or merged), not yet applied to requested_
    int lookup_rr = 0, update_rr = 0;
  };

  uint32_t bank_of(uint32_t idx) const { return idx & uint32_t(cfg_.lanes - 1); }
  void check_against_requests(Bank& bank, const Op& written);

  CycleConfig cfg_;
  PredTable table_;
  PredTable requested_;  // the golden model's table with every request taken applied
  uint64_t cycle_ = 0;
  bool clearing_ = true;
  uint32_t clear_idx_ = 0;
  std::vector<LaneModel> lanes_;  // lane_model.h
  std::vector<Bank> banks_;
  uint64_t next_seq_ = 0;
  std::string error_;
  CycleStats stats_;
  LanesStats lanes_stats_;
};

}  // namespace hrpp
