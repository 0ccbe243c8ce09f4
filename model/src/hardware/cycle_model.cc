#include "hrpp/hardware/cycle_model.h"

#include <bit>
#include <stdexcept>

namespace hrpp {

std::string CycleConfig::validate() const {
  if (auto e = hash.validate(); !e.empty()) return e;
  if (auto e = table.validate(); !e.empty()) return e;
  if (table.unbounded) return "the RTL has a finite table";
  if (table.sets < 2) return "the RTL needs at least 2 sets";
  if (table.ways < 2) return "the RTL needs at least 2 ways";
  if (hash.index_bits != std::countr_zero(table.sets)) return "index bits must be log2(sets)";
  if (table.tag_bits < 1 || table.tag_bits > hash.tag_bits())
    return "stored tag bits must be 1.." + std::to_string(hash.tag_bits());
  if (id_bits < 1 || id_bits > 16) return "id bits must be 1..16";
  if (lanes != 1 && lanes != 2 && lanes != 4) return "lanes must be 1, 2 or 4";
  if (table.sets / uint32_t(lanes) < 2) return "the RTL needs at least 2 sets per bank (lane)";
  if (table.conf_bits != 0 && (table.conf_bits != 1 || table.conf_threshold != 1))
    return "the RTL has 0 or 1 confidence bits per way (threshold 1), not " +
           std::to_string(table.conf_bits) + " bits, threshold " +
           std::to_string(table.conf_threshold);
  if (table.conf_bits != 0 && lanes != 1) return "confidence bits need one lane (hrpp_top)";
  if (lanes != 1 && table.sets > rtl::kTableBankDepth)
    return "more than " + std::to_string(rtl::kTableBankDepth) +
           " sets (a table of RAM banks) need one lane (hrpp_top)";
  if (key_store_reg && !key_store_bram)
    return "the key store's read register needs it in block RAM";
  return {};
}

CycleModel::CycleModel(const CycleConfig& cfg)
    : cfg_(cfg), table_(cfg.table), lane_(cfg, ""), requested_(cfg.table) {
  if (cfg.lanes != 1)
    throw std::invalid_argument("CycleModel models one lane; " + std::to_string(cfg.lanes) +
                                " lanes: LanesCycleModel (hrpp/hardware/cycle_model_lanes.h)");
  reset();
  stats_ = CycleStats{};
}

void CycleModel::reset() {
  ++stats_.resets;
  table_.clear();
  cycle_ = 0;
  clearing_ = true;
  clear_idx_ = 0;
  lane_.reset();
  requests_.clear();
  requested_.clear();
  for (auto& u : up_) u.reset();
  issue_.reset();
}

void CycleModel::check_against_requests(const Op& written) {
  hrpp::check_against_requests(requests_, written, requested_, table_, cfg_.table.ways, &error_);
}

DutOut CycleModel::outputs() const { return lane_.outputs(clearing_); }

void CycleModel::tick(const DutIn& in) {
  lane_.begin(clearing_);

  // The write presented in this cycle (W), then the lookup read presented in this cycle (B):
  // the lookup sees the write (the RTL forwards a colliding write).
  if (up_[kUpdateStages - 1]) {
    write_table(table_, *up_[kUpdateStages - 1], stats_);
    check_against_requests(*up_[kUpdateStages - 1]);
  }
  lane_.lookup(true, table_);  // the table takes every lookup at once
  lane_.pred_fifo(in);

  // The table's interlock judges the update queue's head, or with the issue register (IssueReg)
  // the request in I: it leaves unless it is of the set of an update accepted in either of the
  // two previous cycles (T0, T1: the same-set interlock); if it merges into the newer of those of
  // its set (LaneModel::Op::merges), it leaves merged, not issued.
  std::optional<Op> issued;
  const Op* judged = cfg_.issue_reg ? (issue_ ? &*issue_ : nullptr) : lane_.update_head();
  if (!clearing_ && judged) {
    Op head = *judged;
    std::optional<Op>& t0 = up_[0];
    std::optional<Op>& t1 = up_[1];
    Op* newer = t0 && t0->idx == head.idx ? &*t0 : t1 && t1->idx == head.idx ? &*t1 : nullptr;
    const bool merge = newer && newer->merges(head);
    if (!newer || merge) {
      head.seq = next_seq_++;
      requests_.push_back(head);  // a merged one too: the self-check applies it with `newer`
      if (cfg_.issue_reg)
        issue_.reset();
      else
        lane_.pop_update();
      if (merge) {
        newer->merge(head);
        stats_.merged++;
      } else {
        issued = head;
      }
    } else {
      stats_.interlock_cycles++;
    }
  }
  // I takes the update queue's head when it is empty or its request left in this cycle.
  if (cfg_.issue_reg && !clearing_ && !issue_ && lane_.update_head()) {
    issue_ = *lane_.update_head();
    lane_.pop_update();
  }

  // The skip controller, the key store, the lane's pipelines.
  lane_.finish(in, table_, &error_);

  // The table's update pipeline advances.
  for (int i = kUpdateStages - 1; i > 0; --i) up_[i] = up_[i - 1];
  up_[0] = issued;
  if (clearing_ && ++clear_idx_ == cfg_.table.sets) clearing_ = false;
  ++cycle_;
}

}  // namespace hrpp
