// Cycle-accurate model of the multi-lane RTL (rtl/hrpp_lanes.sv; docs/microarchitecture.md,
// "Lanes"): Lanes (2 or 4) copies of hrpp_top's lane (input registers, hash, key store, skip
// controller, prediction and skip FIFOs, update queue) around a table split by set into Lanes
// banks, each with hrpp_pred_table's lookup and update pipelines, and a lookup queue per lane.
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
  struct Pred {
    uint32_t id = 0;
    bool invalid = false;
    uint32_t count = 0;
    std::array<uint32_t, kMaxNodesPerEntry> nodes{};
  };
  struct Op {
    uint32_t idx = 0;  // the full set index (bank = idx mod lanes)
    uint64_t tag = 0;
    uint32_t node = 0;
    uint64_t seq = 0;     // the request's number in the order its bank took them
    bool demote = false;  // never: lanes have no confidence bits (check_against_requests reads it)
    bool same_update(const Op& o) const { return idx == o.idx && tag == o.tag && node == o.node; }
  };
  struct KeyEntry {
    uint32_t idx = 0;
    uint64_t tag = 0;
    bool any_hit = false;
  };
  struct Msg {
    bool valid = false;
    uint32_t id = 0;
    bool hit = false;
    uint32_t node = 0;
    KeyEntry key;
  };
  struct Decision {
    Action action = Action::kFull;
    bool f_req = false, p_req = false, p_advance = false, f_advance = false;
    std::optional<Op> update, update2;
    bool room1 = false, room2 = false;
  };
  struct B {  // key registers, and a lookup-queue entry
    uint32_t id = 0, idx = 0;
    uint64_t tag = 0;
    bool invalid = false, any_hit = false;
  };
  static constexpr int kHashLatency = rtl::kHashStages;
  static constexpr int kLookupLatency = rtl::kLookupStages;
  static constexpr int kUpdateStages = rtl::kUpdateStages;
  struct Lane {
    std::optional<DutIn> a;
    std::array<std::optional<DutIn>, kHashLatency> h;
    std::optional<B> b;
    std::deque<B> lookup_queue;
    std::array<std::optional<Pred>, kLookupLatency> d;
    std::deque<Pred> pred_fifo;
    std::vector<KeyEntry> key_store;      // no reset, as in the RTL
    std::vector<bool> key_store_written;  // since the last reset
    Msg p0, f0;
    std::deque<Op> update_queue;
    std::deque<std::pair<uint32_t, Action>> skip_fifo;
  };
  struct Bank {
    std::array<std::optional<Op>, kUpdateStages> up;  // [0] = T0 ... [6] = W
    std::deque<Op> requests;  // taken (issued or dropped), not yet applied to requested_
    int lookup_rr = 0, update_rr = 0;
  };

  Decision decide(const Lane& l) const;
  DutOut outputs(const Lane& l, const Decision& d) const;
  int in_flight(const Lane& l) const;
  uint32_t bank_of(uint32_t idx) const { return idx & uint32_t(cfg_.lanes - 1); }
  void check_against_requests(Bank& bank, const Op& written);

  CycleConfig cfg_;
  PredTable table_;
  PredTable requested_;  // the golden model's table with every request taken applied
  uint64_t cycle_ = 0;
  bool clearing_ = true;
  uint32_t clear_idx_ = 0;
  std::vector<Lane> lanes_;
  std::vector<Bank> banks_;
  uint64_t next_seq_ = 0;
  std::string error_;
  CycleStats stats_;
  LanesStats lanes_stats_;
};

}  // namespace hrpp
