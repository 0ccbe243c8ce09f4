// What the cycle models of the RTL share (cycle_model.h: one lane, hrpp_top; lane_model.h: one
// lane of it; cycle_model_lanes.h: 2 or 4 lanes, hrpp_lanes): their configuration, the DUT's
// ports in one cycle, the table's statistics and the self-check against the golden model's table.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "hrpp/predictor/engine_side.h"  // Action: the skip decisions
#include "hrpp/predictor/hash.h"
#include "hrpp/predictor/pred_table.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/rtl_config_data.h"

namespace hrpp {

/// A table write request applied to `table` by the golden rule: a demote or an update.
inline void apply_request(PredTable& table, uint32_t idx, uint64_t tag, uint32_t node,
                          bool demote) {
  if (demote)
    table.demote(idx, tag, 0);
  else
    table.update(idx, tag, 0, node);
}

/// The cycle models' self-check (CycleModel, LanesCycleModel): every request in `requests` up to
/// `written` (by sequence number) is applied to `requested`, the golden model's table with every
/// request applied in order (updates, and demotes with confidence bits), and popped, then the
/// requests merged into `written` (taken later, with no request of their set between them and
/// it, so applying them now leaves their set as applying them in turn would); each set they touch
/// must then equal `table`'s (confidence counters too). The first difference is written to
/// *error (if it is empty).
template <typename Op>
void check_against_requests(std::deque<Op>& requests, const Op& written, PredTable& requested,
                            const PredTable& table, uint32_t ways, std::string* error) {
  std::vector<uint32_t> sets;
  auto apply = [&](uint32_t idx, uint64_t tag, uint32_t node, bool demote) {
    apply_request(requested, idx, tag, node, demote);
    sets.push_back(idx);
  };
  while (!requests.empty() && requests.front().seq <= written.seq) {
    const Op& op = requests.front();
    apply(op.idx, op.tag, op.node, op.demote);
    requests.pop_front();
  }
  for (int i = 0; i < written.merged_count; ++i) {
    const auto& m = written.merged[i];
    auto it =
        std::find_if(requests.begin(), requests.end(), [&](const Op& r) { return r.seq == m.seq; });
    if (it == requests.end()) {
      if (error->empty()) *error = "a merged request is missing from the requests taken";
      return;
    }
    apply(written.idx, written.tag, m.node, m.demote);
    requests.erase(it);
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
                 "with every update request applied (a merge that is not exact)";
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
  // Its read register (KeyStoreReg, with key_store_bram): the message and its key wait one more
  // cycle in J between K and P0 / F0: one more cycle of decision and update latency.
  bool key_store_reg = rtl::kDefaultConfig.key_store_reg;
  // The table's issue register (IssueReg): a request taken from the update queue waits a cycle in
  // I, where the interlock judges it, before T0: one cycle more of update latency.
  bool issue_reg = rtl::kDefaultConfig.issue_reg;
  /// Lookups and updates per cycle: 1 (hrpp_top: CycleModel), 2 or 4 (hrpp_lanes: LanesCycleModel,
  /// cycle_model_lanes.h).
  int lanes = 1;
  /// The table's lookup latency: the declared one, and one cycle more for a table of more sets
  /// than a RAM bank holds (hrpp_pred_table's L3b; hrpp_lanes has no such table: validate()).
  int lookup_latency() const { return rtl::kLookupStages + int(table.sets > rtl::kTableBankDepth); }
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
  uint64_t interlock_cycles = 0;  // cycles the judged request waited (same-set interlock)
  uint64_t merged = 0;  // requests merged into the newer same-set one in T0/T1 (not issued)
  uint64_t resets = 0;  // reset() calls after construction (cycles in reset)
};

/// The table's write (W) of a request taken from the update pipeline: an update, or a demote
/// (confidence bits; no allocation, never an eviction), then the requests merged into it, in
/// order; counted in `stats`.
template <typename Op>
void write_table(PredTable& table, const Op& w, CycleStats& stats) {
  auto apply = [&](uint32_t node, bool demote) {
    if (!demote) {  // an update that allocates in a full set evicts
      bool hit = false, full = true;
      for (uint32_t i = 0; i < table.config().ways; ++i) {
        const Way& way = table.way(w.idx, i);
        hit |= way.valid && way.tag == w.tag;
        full &= way.valid;
      }
      stats.evictions += !hit && full;
    }
    apply_request(table, w.idx, w.tag, node, demote);
  };
  stats.updates++;
  apply(w.node, w.demote);
  for (int i = 0; i < w.merged_count; ++i) apply(w.merged[i].node, w.merged[i].demote);
}

}  // namespace hrpp
