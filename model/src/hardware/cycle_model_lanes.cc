#include "hrpp/hardware/cycle_model_lanes.h"

#include <algorithm>
#include <stdexcept>

namespace hrpp {

LanesCycleModel::LanesCycleModel(const CycleConfig& cfg)
    : cfg_(cfg), table_(cfg.table), requested_(cfg.table) {
  if (cfg.lanes != 2 && cfg.lanes != 4)
    throw std::invalid_argument("LanesCycleModel models 2 or 4 lanes, not " +
                                std::to_string(cfg.lanes) + " (one lane: CycleModel)");
  if (const std::string e = cfg.validate(); !e.empty())
    throw std::invalid_argument("LanesCycleModel: " + e);
  lanes_.reserve(size_t(cfg.lanes));
  for (int l = 0; l < cfg.lanes; ++l) lanes_.emplace_back(cfg, " on lane " + std::to_string(l));
  banks_.resize(size_t(cfg.lanes));
  reset();
  stats_ = CycleStats{};
}

void LanesCycleModel::reset() {
  ++stats_.resets;
  table_.clear();
  requested_.clear();
  cycle_ = 0;
  clearing_ = true;
  clear_idx_ = 0;
  for (LaneModel& l : lanes_) l.reset();  // the key stores keep their contents
  for (Bank& b : banks_) b = Bank{};
}

DutOut LanesCycleModel::outputs(int lane) const {
  return lanes_.at(size_t(lane)).outputs(clearing_);
}

void LanesCycleModel::check_against_requests(Bank& bank, const Op& written) {
  // As CycleModel, over the bank's requests (a set's requests all go to its bank).
  hrpp::check_against_requests(bank.requests, written, requested_, table_, cfg_.table.ways,
                               &error_);
}

void LanesCycleModel::tick(const std::vector<DutIn>& in) {
  const size_t n = lanes_.size();
  if (in.size() != n)
    throw std::invalid_argument("LanesCycleModel::tick: " + std::to_string(in.size()) +
                                " lanes' inputs for " + std::to_string(n) + " lanes");
  for (LaneModel& l : lanes_) l.begin(clearing_);

  // Each bank's write (W), then the lookups read in this cycle see it.
  for (Bank& bank : banks_) {
    if (!bank.up[kUpdateStages - 1]) continue;
    write_table(table_, *bank.up[kUpdateStages - 1], stats_);
    check_against_requests(bank, *bank.up[kUpdateStages - 1]);
  }

  // Lookup crossbar: each lane's head (the lookup queue's oldest entry, else B); per bank the
  // first lane asking for it from the round-robin pointer on.
  std::vector<bool> granted(n, false);
  for (uint32_t b = 0; b < banks_.size(); ++b) {
    Bank& bank = banks_[b];
    for (size_t k = 0; k < n; ++k) {
      const size_t i = (size_t(bank.lookup_rr) + k) % n;
      const LaneModel::B* head = lanes_[i].lookup_head();
      if (head && !head->invalid && bank_of(head->idx) == b) {
        granted[i] = true;
        bank.lookup_rr = int((i + 1) % n);
        lanes_stats_.lookups++;
        break;
      }
    }
  }
  for (size_t i = 0; i < n; ++i) {
    if (lanes_[i].lookup(granted[i], table_)) lanes_stats_.lookup_waits++;
    lanes_stats_.max_lookup_queue =
        std::max<uint64_t>(lanes_stats_.max_lookup_queue, lanes_[i].lookup_queue_size());
  }

  // Prediction FIFOs.
  for (size_t i = 0; i < n; ++i) lanes_[i].pred_fifo(in[i]);

  // Update crossbar: per bank the first lane whose queue head is of the bank, from the
  // round-robin pointer on. The bank's interlock judges that head, or with the issue register
  // (IssueReg) the request in the bank's I, which then takes that head when it is empty or its
  // request leaves in this cycle. The judged request waits while its same-set interlock holds it
  // (then no lane's head goes), and is dropped (merged) if identical to the newer same-set update
  // in T0/T1.
  // The heads of this cycle (a lane's queue gives at most one request per cycle).
  std::vector<std::optional<Op>> uq_head(n);
  for (size_t i = 0; i < n; ++i)
    if (const Op* h = lanes_[i].update_head()) uq_head[i] = *h;
  std::vector<std::optional<Op>> issued(banks_.size());
  for (uint32_t b = 0; b < banks_.size(); ++b) {
    Bank& bank = banks_[b];
    std::optional<size_t> sel;
    for (size_t k = 0; k < n && !sel; ++k) {
      const size_t i = (size_t(bank.update_rr) + k) % n;
      if (uq_head[i] && bank_of(uq_head[i]->idx) == b) sel = i;
    }
    for (size_t i = 0; i < n; ++i)
      if (uq_head[i] && bank_of(uq_head[i]->idx) == b && sel != i) lanes_stats_.update_waits++;
    if (clearing_) continue;
    auto take_head = [&] {
      lanes_[*sel].pop_update();
      bank.update_rr = int((*sel + 1) % n);
    };
    std::optional<Op> judged = cfg_.issue_reg ? bank.issue : sel ? uq_head[*sel] : std::nullopt;
    if (judged) {
      Op head_op = *judged;
      std::optional<Op>& t0 = bank.up[0];
      std::optional<Op>& t1 = bank.up[1];
      Op* newer = t0 && t0->idx == head_op.idx   ? &*t0
                  : t1 && t1->idx == head_op.idx ? &*t1
                                                 : nullptr;
      if (newer && !newer->merges(head_op)) {
        stats_.interlock_cycles++;
        continue;
      }
      if (cfg_.issue_reg)
        bank.issue.reset();
      else
        take_head();
      head_op.seq = next_seq_++;
      bank.requests.push_back(head_op);
      if (newer) {  // merged (no confidence bits: identical, changes nothing), not issued
        newer->merge(head_op);
        stats_.merged++;
      } else {
        issued[b] = head_op;
      }
    }
    if (cfg_.issue_reg && !bank.issue && sel) {
      bank.issue = uq_head[*sel];
      take_head();
    }
  }

  // Each lane's skip controller, key store and pipelines.
  for (size_t i = 0; i < n; ++i) lanes_[i].finish(in[i], table_, &error_);

  // The banks' update pipelines advance.
  for (uint32_t b = 0; b < banks_.size(); ++b) {
    auto& up = banks_[b].up;
    for (int s = kUpdateStages - 1; s > 0; --s) up[s] = up[s - 1];
    up[0] = issued[b];
  }
  if (clearing_ && ++clear_idx_ == cfg_.table.sets / uint32_t(cfg_.lanes)) clearing_ = false;
  ++cycle_;
}

}  // namespace hrpp
