// Cycle-accurate model of one lane of the RTL (rtl/hrpp_lane.sv; docs/microarchitecture.md):
// input registers, hash, key store (with K in front of the skip controller when it is in block
// RAM), lookup queue, prediction FIFO, skip controller, skip FIFO and update queue: everything
// but the table. CycleModel (cycle_model.h, hrpp_top) is one lane whose lookups the table takes
// at once; LanesCycleModel (cycle_model_lanes.h, hrpp_lanes) is 2 or 4 lanes around a banked
// table, whose lookups may wait in the lane's lookup queue.
//
// A clock edge of the model that owns the lane calls, in this order: begin() (this cycle's
// decisions and outputs, from the state), lookup() (the lookup head goes, or waits), pred_fifo(),
// pop_update() if the table takes the update queue's head, then finish() (the skip controller,
// the key store, the pipelines advance).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hrpp/hardware/cycle_common.h"

namespace hrpp {

class LaneModel {
 public:
  struct Pred {
    uint32_t id = 0;
    bool invalid = false;
    uint32_t count = 0;
    std::array<uint32_t, kMaxNodesPerEntry> nodes{};
  };
  /// A table write request (update or demote) of the update queue.
  struct Op {
    uint32_t idx = 0;  // the full set index (with lanes: bank = idx mod lanes)
    uint64_t tag = 0;
    uint32_t node = 0;
    uint64_t seq = 0;     // the request's number in the order the table took them
    bool demote = false;  // a demote (confidence bits), not an update
    /// A later request of the same set merged into this one while it was in T0 or T1 (at most
    /// one per cycle: two): the table applies it right after this one, in the same write.
    struct Merged {
      uint32_t node = 0;
      uint64_t seq = 0;
      bool demote = false;
    };
    std::array<Merged, 2> merged{};
    int merged_count = 0;
    /// What a later request of the set is compared with (hrpp_pred_table's T0 / T1 request
    /// after its merges): the last update among this one and those merged, else a demote.
    bool last_demote() const {
      for (int i = merged_count - 1; i >= 0; --i)
        if (!merged[i].demote) return false;
      return demote;
    }
    uint32_t last_node() const {
      for (int i = merged_count - 1; i >= 0; --i)
        if (!merged[i].demote) return merged[i].node;
      return node;
    }
    /// Whether `o`, the next request of this set, merges into this one (hrpp_pred_table's
    /// wr_merge): same set and tag, and a demote, or an update after a demote, or an update of
    /// the same node as the last update. What the pair leaves is then what one pass of the
    /// table's update pipeline computes (docs/microarchitecture.md, "Hazards"). Without
    /// confidence bits only identical updates occur, which change nothing.
    bool merges(const Op& o) const {
      return idx == o.idx && tag == o.tag && (o.demote || last_demote() || o.node == last_node());
    }
    void merge(const Op& o) { merged[merged_count++] = Merged{o.node, o.seq, o.demote}; }
  };
  struct B {  // key registers, and a lookup-queue entry
    uint32_t id = 0, idx = 0;
    uint64_t tag = 0;
    bool invalid = false, any_hit = false;
  };

  /// where: how error() names the lane ("" with one lane, " on lane 1" ...).
  LaneModel(const CycleConfig& cfg, std::string where);
  /// rst_ni low: every register and FIFO cleared; the key store keeps its contents (distributed
  /// RAM without reset in the RTL), its entries count as not written since the reset.
  void reset();
  /// This cycle's outputs (functions of the state; clearing: the table's reset clear runs).
  const DutOut& outputs(bool clearing) const;
  /// This cycle's lookup request (the lookup queue's oldest entry, else B), if any.
  const B* lookup_head() const;
  /// The update queue's head, if any.
  const Op* update_head() const { return update_queue_.empty() ? nullptr : &update_queue_.front(); }
  size_t lookup_queue_size() const { return lookup_queue_.size(); }

  // One clock edge, in this order.
  /// The decisions and outputs of this cycle, before any state changes.
  void begin(bool clearing);
  /// The lookup head leaves (it is invalid, or granted: its bank reads it now, in `table`), else
  /// waits in the lookup queue; B enters the queue unless it leaves at once. True: a head waited.
  bool lookup(bool granted, PredTable& table);
  /// The prediction FIFO pops (pred_ready) and takes the lookup result that is due.
  void pred_fifo(const DutIn& in);
  /// The table takes (or drops) the update queue's head.
  void pop_update() { update_queue_.pop_front(); }
  /// The skip controller and its update requests, the key store, the pipelines advance. A
  /// protocol violation goes to *error (if it is empty).
  void finish(const DutIn& in, const PredTable& table, std::string* error);

 private:
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
    bool room1 = false, room2 = false;      // the update queue has room for one, for two requests
    bool p_take = false, f_take = false;    // P0, F0 take a message (the port's, K's or J's)
    bool jp_take = false, jf_take = false;  // J takes K's message (key_store_reg)
  };
  Decision decide(bool clearing) const;
  DutOut outputs(const Decision& d, bool clearing) const;
  int in_flight() const;

  CycleConfig cfg_;
  std::string where_;
  // outputs() and the decision it was computed from, valid until the state changes.
  mutable bool cached_ = false;
  mutable bool cached_clearing_ = false;
  mutable Decision cached_dec_;
  mutable DutOut cached_out_;
  // This clock edge's (begin() to finish()).
  Decision dec_;
  DutOut out_;
  std::optional<Pred> looked_up_;
  std::optional<std::pair<uint32_t, bool>> given_;

  // Lookup path: A (input regs), H0..H2 (the hash's stages), B (key regs), the lookup queue,
  // D0..D3 (beside the table's lookup; D4 too for a table of RAM banks). The latencies are the
  // RTL's declared ones (rtl/config/hrpp_configs.json; CycleConfig::lookup_latency()).
  static constexpr int kHashLatency = rtl::kHashStages;
  static constexpr int kMaxLookupLatency = rtl::kLookupStages + 1;
  int lookup_latency_;
  std::optional<DutIn> a_;
  std::array<std::optional<DutIn>, kHashLatency> h_;
  std::optional<B> b_;
  std::deque<B> lookup_queue_;
  std::array<std::optional<Pred>, kMaxLookupLatency> d_;  // the first lookup_latency_ used
  std::deque<Pred> pred_fifo_;
  std::vector<KeyEntry> key_store_;      // no reset, as in the RTL
  std::vector<uint8_t> pred_given_;      // by id: the ray was given a prediction (ConfBits)
  std::vector<bool> key_store_written_;  // since the last reset
  // Update path: (K: kp_, kf_ with the key store in block RAM; J: jp_, jf_ with its read
  // register) P0 and F0, the update queue (U).
  Msg kp_, kf_, jp_, jf_, p0_, f0_;
  std::deque<Op> update_queue_;
  std::deque<std::pair<uint32_t, Action>> skip_fifo_;
};

}  // namespace hrpp
