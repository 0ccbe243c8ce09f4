// Cycle-accurate model of the RTL's interface behaviour (rtl/hrpp_top.sv,
// docs/microarchitecture.md). It reuses the golden model's hash (hash.h) and table (pred_table.h):
// the table's update pipeline forwards every hazard, so applying each update to a PredTable in
// the cycle the RTL writes it reproduces the RTL's table, and a lookup sees every write presented
// in the cycle of its read or earlier.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "hrpp/predictor/engine_side.h"  // Action: the skip decisions
#include "hrpp/predictor/hash.h"
#include "hrpp/predictor/pred_table.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/rtl_config_data.h"

namespace hrpp {

/// The cycle models' self-check (CycleModel, LanesCycleModel): every request in `requests` up to
/// `written` (by sequence number; the requests dropped before it too) is applied to `requested`,
/// the golden model's table with every request applied (updates, and demotes with confidence
/// bits), and popped; each set they touch must then equal `table`'s (confidence counters too).
/// The first difference is written to *error (if it is empty).
template <typename Op>
void check_against_requests(std::deque<Op>& requests, const Op& written, PredTable& requested,
                            const PredTable& table, uint32_t ways, std::string* error) {
  std::vector<uint32_t> sets;
  while (!requests.empty() && requests.front().seq <= written.seq) {
    const Op& op = requests.front();
    if (op.demote)
      requested.demote(op.idx, op.tag, 0);
    else
      requested.update(op.idx, op.tag, 0, op.node);
    sets.push_back(op.idx);
    requests.pop_front();
  }
  for (const uint32_t s : sets)
    for (uint32_t i = 0; i < ways; ++i) {
      const Way& a = table.way(s, i);
      const Way& b = requested.way(s, i);
      bool same = a.valid == b.valid && table.age(s, i) == requested.age(s, i);
      if (a.valid && same) {
        same = a.tag == b.tag && a.count == b.count && a.conf == b.conf;
        for (uint32_t k = 0; k < a.count && same; ++k) same = a.nodes[k] == b.nodes[k];
      }
      if (!same && error->empty())
        *error = "the table's set " + std::to_string(s) + " differs from the golden model's " +
                 "with every update request applied (a dropped request changed the table)";
    }
}

struct CycleConfig {
  HashConfig hash;    // index_bits = log2(table.sets); origin_cell_exp = cfg_cell_exp_i
  TableConfig table;  // finite; tag_bits = the RTL's TagWidth
  PredictMode mode = PredictMode::kClosestExact;
  int id_bits = rtl::kDefaultConfig.id_width;  // rtl_config.h: every configuration's
  int pred_fifo_depth = rtl::kDefaultConfig.pred_fifo_depth;
  int skip_fifo_depth = rtl::kDefaultConfig.skip_fifo_depth;
  int update_queue_depth = rtl::kDefaultConfig.update_queue_depth;
  // The key store in block RAM (KeyStoreBram): a predicted-walk result or final outcome waits a
  // cycle in K (its key read) before P0 / F0: one cycle more of decision and update latency.
  bool key_store_bram = rtl::kDefaultConfig.key_store_bram;
  /// Lookups and updates per cycle: 1 (hrpp_top: CycleModel), 2 or 4 (hrpp_lanes: LanesCycleModel,
  /// cycle_model_lanes.h).
  int lanes = 1;
  // table.conf_bits: 0, or 1 with threshold 1 (ConfBits: a confidence bit per way, demotes from
  // final outcomes of predicted rays that missed; hrpp_top only).
  std::string validate() const;
};

/// The DUT's inputs in one cycle.
struct DutIn {
  bool ray_valid = false;
  uint32_t ray_id = 0;
  uint8_t ray_kind = 0;
  std::array<uint32_t, 3> org{}, dir{};
  bool pred_ready = false;
  bool pw_valid = false;  // predicted-walk result
  uint32_t pw_id = 0;
  bool pw_hit = false;
  uint32_t pw_node = 0;
  bool outcome_valid = false;  // final outcome
  uint32_t outcome_id = 0;
  bool outcome_hit = false;
  uint32_t outcome_node = 0;
  bool skip_ready = false;
};

/// The DUT's outputs in one cycle (functions of the state only).
struct DutOut {
  bool ray_ready = false;
  bool pred_valid = false;
  uint32_t pred_id = 0;
  bool pred_invalid = false;
  uint32_t pred_count = 0;
  std::array<uint32_t, kMaxNodesPerEntry> pred_nodes{};
  bool pw_ready = false;
  bool outcome_ready = false;
  bool skip_valid = false;
  uint32_t skip_id = 0;
  Action skip_action = Action::kFull;
};

/// What the table saw (cumulative over resets; for the testbench's stress checks).
struct CycleStats {
  uint64_t updates = 0;           // rows written by updates (W)
  uint64_t evictions = 0;         // updates that replaced a valid entry of another tag
  uint64_t interlock_cycles = 0;  // cycles the update queue's head waited (same-set interlock)
  uint64_t dropped = 0;  // requests dropped as identical to the newer same-set one in T0/T1
  uint64_t resets = 0;   // reset() calls after construction (cycles in reset)
};

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
  /// taken applied in order, the dropped ones too (a dropped request that was not a no-op).
  const std::string& error() const { return error_; }
  const CycleStats& stats() const { return stats_; }
  DutOut outputs() const;
  /// One rising clock edge with these inputs.
  void tick(const DutIn& in);
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
    uint32_t idx = 0;
    uint64_t tag = 0;
    uint32_t node = 0;
    uint64_t seq = 0;     // the request's number in the order the update queue took them
    bool demote = false;  // a demote (confidence bits), not an update
    /// The same request: a demote of the same set and tag, or an update of the same set, tag
    /// and node (hrpp_pred_table's wr_same_as_t0 / t1).
    bool same_update(const Op& o) const {
      return idx == o.idx && tag == o.tag && demote == o.demote && (demote || node == o.node);
    }
  };
  struct KeyEntry {
    uint32_t idx = 0;
    uint64_t tag = 0;
    bool any_hit = false;
  };
  struct Msg {  // K, P0 or F0, with the ray's key read from the key store at acceptance
    bool valid = false;
    uint32_t id = 0;
    bool hit = false;
    uint32_t node = 0;
    KeyEntry key;
    bool demote = false;  // F0: the final outcome requests a demote (confidence bits)
  };
  struct Decision {  // what P0 and F0 do this cycle (combinational in the RTL)
    Action action = Action::kFull;
    bool f_req = false, p_req = false, p_advance = false, f_advance = false;
    std::optional<Op> update;   // the first request to the update queue (a final outcome's first)
    std::optional<Op> update2;  // the second, behind it (a predicted-walk result's)
    bool room1 = false, room2 = false;    // the update queue has room for one, for two requests
    bool p_take = false, f_take = false;  // P0, F0 take a message (the port's, or K's)
  };
  void take_request(Op op);
  void drop_queue_head();
  void check_against_requests(const Op& written);
  Decision decide() const;
  DutOut outputs(const Decision& d) const;
  int in_flight() const;
  // outputs() and the decision it was computed from, valid until the state changes.
  mutable bool cached_ = false;
  mutable Decision cached_dec_;
  mutable DutOut cached_out_;

  CycleConfig cfg_;
  PredTable table_;
  uint64_t cycle_ = 0;
  bool clearing_ = true;
  uint32_t clear_idx_ = 0;
  // Lookup path: A (input regs), H0..H2 (the hash's stages), B (key regs), D0..D3 (beside the
  // table's lookup). The latencies are the RTL's declared ones (rtl/config/hrpp_configs.json).
  static constexpr int kHashLatency = rtl::kHashStages;
  std::optional<DutIn> a_;
  std::array<std::optional<DutIn>, kHashLatency> h_;
  struct B {
    uint32_t id = 0, idx = 0;
    uint64_t tag = 0;
    bool invalid = false, any_hit = false;
  };
  std::optional<B> b_;
  static constexpr int kLookupLatency = rtl::kLookupStages;
  std::array<std::optional<Pred>, kLookupLatency> d_;
  std::deque<Pred> pred_fifo_;
  std::vector<KeyEntry> key_store_;      // no reset, as in the RTL
  std::vector<uint8_t> pred_given_;      // by id: the ray was given a prediction (ConfBits)
  std::vector<bool> key_store_written_;  // since the last reset
  std::string error_;
  CycleStats stats_;
  // Update path: (K: kp_, kf_ with the key store in block RAM) P0 and F0, the update queue (U),
  // then T0, T1, T2, C1, C2, C3, W.
  Msg kp_, kf_, p0_, f0_;
  std::deque<Op> update_queue_;
  // Every request the queue took, in order, until a write applies it (and the dropped ones before
  // it) to requested_: the golden model's table with every request applied, which the table must
  // equal.
  std::deque<Op> requests_;
  PredTable requested_;
  uint64_t next_seq_ = 0;
  static constexpr int kUpdateStages = rtl::kUpdateStages;
  std::array<std::optional<Op>, kUpdateStages> up_;  // [0] = T0 ... [6] = W
  std::deque<std::pair<uint32_t, Action>> skip_fifo_;
};

}  // namespace hrpp
