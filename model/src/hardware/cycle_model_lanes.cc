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
  lanes_.resize(size_t(cfg.lanes));
  for (Lane& l : lanes_) l.key_store.resize(size_t{1} << cfg.id_bits);
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
  for (Lane& l : lanes_) {
    std::vector<KeyEntry> ks = std::move(l.key_store);  // the key store keeps its contents
    l = Lane{};
    l.key_store = std::move(ks);
    l.key_store_written.assign(l.key_store.size(), false);
  }
  for (Bank& b : banks_) b = Bank{};
}

int LanesCycleModel::in_flight(const Lane& l) const {
  int n = int(l.a.has_value()) + int(l.b.has_value()) + int(l.lookup_queue.size());
  for (const auto& h : l.h) n += int(h.has_value());
  for (const auto& d : l.d) n += int(d.has_value());
  return n;
}

// As CycleModel::decide: one lane's skip controller and its update queue's room.
LanesCycleModel::Decision LanesCycleModel::decide(const Lane& l) const {
  Decision d;
  const KeyEntry& kp = l.p0.key;
  const KeyEntry& kf = l.f0.key;
  d.action = skip_action(l.p0.hit, kp.any_hit, cfg_.mode);
  const bool fifo_full = l.skip_fifo.size() >= size_t(cfg_.skip_fifo_depth);
  const bool p_needs = d.action == Action::kSkip;
  d.f_req = l.f0.valid && l.f0.hit;
  d.p_req = l.p0.valid && p_needs && !fifo_full;
  if (d.f_req)
    d.update = Op{kf.idx, kf.tag, l.f0.node};
  else if (d.p_req)
    d.update = Op{kp.idx, kp.tag, l.p0.node};
  if (d.f_req && d.p_req) d.update2 = Op{kp.idx, kp.tag, l.p0.node};
  d.room1 = l.update_queue.size() + 1 <= size_t(cfg_.update_queue_depth);
  d.room2 = l.update_queue.size() + 2 <= size_t(cfg_.update_queue_depth);
  d.f_advance = l.f0.valid && (!l.f0.hit || d.room1);
  d.p_advance = l.p0.valid && !fifo_full && (!p_needs || (d.f_req ? d.room2 : d.room1));
  return d;
}

DutOut LanesCycleModel::outputs(const Lane& l, const Decision& d) const {
  DutOut o;
  o.ray_ready = !clearing_ && in_flight(l) + int(l.pred_fifo.size()) < cfg_.pred_fifo_depth;
  if (!l.pred_fifo.empty()) {
    const Pred& p = l.pred_fifo.front();
    o.pred_valid = true;
    o.pred_id = p.id;
    o.pred_invalid = p.invalid;
    o.pred_count = p.count;
    o.pred_nodes = p.nodes;
  }
  o.pw_ready = !clearing_ && (!l.p0.valid || d.p_advance);
  o.outcome_ready = !clearing_ && (!l.f0.valid || d.f_advance);
  if (!l.skip_fifo.empty()) {
    o.skip_valid = true;
    o.skip_id = l.skip_fifo.front().first;
    o.skip_action = l.skip_fifo.front().second;
  }
  return o;
}

DutOut LanesCycleModel::outputs(int lane) const {
  const Lane& l = lanes_.at(size_t(lane));
  return outputs(l, decide(l));
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
  std::vector<Decision> dec(n);
  std::vector<DutOut> out(n);
  for (size_t i = 0; i < n; ++i) {
    dec[i] = decide(lanes_[i]);
    out[i] = outputs(lanes_[i], dec[i]);
  }

  // Each bank's write (W), then the lookups read in this cycle see it.
  for (Bank& bank : banks_) {
    if (!bank.up[kUpdateStages - 1]) continue;
    const Op& w = *bank.up[kUpdateStages - 1];
    bool hit = false, full = true;
    for (uint32_t i = 0; i < cfg_.table.ways; ++i) {
      const Way& way = table_.way(w.idx, i);
      hit |= way.valid && way.tag == w.tag;
      full &= way.valid;
    }
    stats_.updates++;
    stats_.evictions += !hit && full;
    table_.update(w.idx, w.tag, 0, w.node);
    check_against_requests(bank, w);
  }

  // Lookup crossbar: each lane's head (the lookup queue's oldest entry, else B); per bank the
  // first lane asking for it from the round-robin pointer on.
  std::vector<std::optional<B>> head(n);
  for (size_t i = 0; i < n; ++i) {
    const Lane& l = lanes_[i];
    if (!l.lookup_queue.empty())
      head[i] = l.lookup_queue.front();
    else
      head[i] = l.b;
  }
  std::vector<bool> granted(n, false);
  for (uint32_t b = 0; b < banks_.size(); ++b) {
    Bank& bank = banks_[b];
    for (size_t k = 0; k < n; ++k) {
      const size_t i = (size_t(bank.lookup_rr) + k) % n;
      if (head[i] && !head[i]->invalid && bank_of(head[i]->idx) == b) {
        granted[i] = true;
        bank.lookup_rr = int((i + 1) % n);
        lanes_stats_.lookups++;
        break;
      }
    }
  }
  std::vector<std::optional<Pred>> looked_up(n);
  for (size_t i = 0; i < n; ++i) {
    Lane& l = lanes_[i];
    const bool go = head[i] && (head[i]->invalid || granted[i]);
    if (head[i] && !go) lanes_stats_.lookup_waits++;
    if (go) {
      Pred p;
      p.id = head[i]->id;
      p.invalid = head[i]->invalid;
      if (!p.invalid) {
        const Prediction pr = table_.lookup(head[i]->idx, head[i]->tag, 0);
        p.count = pr.count;
        p.nodes = pr.nodes;
      }
      looked_up[i] = p;
    }
    const bool queue_was_empty = l.lookup_queue.empty();
    if (go && !queue_was_empty) l.lookup_queue.pop_front();
    if (l.b && !(queue_was_empty && go)) l.lookup_queue.push_back(*l.b);
    lanes_stats_.max_lookup_queue =
        std::max<uint64_t>(lanes_stats_.max_lookup_queue, l.lookup_queue.size());
  }

  // Prediction FIFOs.
  for (size_t i = 0; i < n; ++i) {
    Lane& l = lanes_[i];
    if (out[i].pred_valid && in[i].pred_ready) l.pred_fifo.pop_front();
    if (l.d[kLookupLatency - 1]) l.pred_fifo.push_back(*l.d[kLookupLatency - 1]);
  }

  // Update crossbar: per bank the first lane whose queue head is of the bank, from the
  // round-robin pointer on; the bank takes it unless its same-set interlock holds it (then no
  // lane's head goes), and drops it if identical to the newer same-set update in T0/T1.
  // The heads of this cycle (a lane's queue gives at most one request per cycle).
  std::vector<std::optional<Op>> uq_head(n);
  for (size_t i = 0; i < n; ++i)
    if (!lanes_[i].update_queue.empty()) uq_head[i] = lanes_[i].update_queue.front();
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
    if (!sel || clearing_) continue;
    Lane& l = lanes_[*sel];
    Op head_op = *uq_head[*sel];
    const std::optional<Op>& t0 = bank.up[0];
    const std::optional<Op>& t1 = bank.up[1];
    const Op* newer = t0 && t0->idx == head_op.idx   ? &*t0
                      : t1 && t1->idx == head_op.idx ? &*t1
                                                     : nullptr;
    if (newer && !newer->same_update(head_op)) {
      stats_.interlock_cycles++;
      continue;
    }
    l.update_queue.pop_front();
    bank.update_rr = int((*sel + 1) % n);
    head_op.seq = next_seq_++;
    bank.requests.push_back(head_op);
    if (newer)
      stats_.dropped++;  // it stays in bank.requests: applied to requested_ all the same
    else
      issued[b] = head_op;
  }

  // Skip controllers: each lane's update queue takes the requests of the messages that advance.
  for (size_t i = 0; i < n; ++i) {
    Lane& l = lanes_[i];
    const Decision& d = dec[i];
    if (d.update && d.room1) {
      l.update_queue.push_back(*d.update);
      if (d.update2 && d.room2) l.update_queue.push_back(*d.update2);
    }
    if (out[i].skip_valid && in[i].skip_ready) l.skip_fifo.pop_front();
    if (d.p_advance) l.skip_fifo.emplace_back(l.p0.id, d.action);
    auto check_key = [&](bool valid, uint32_t id, const char* what) {
      if (valid && !l.key_store_written[id] && error_.empty())
        error_ = std::string(what) + " on lane " + std::to_string(i) + " for ray id " +
                 std::to_string(id) + " whose key-store entry was not written since reset";
    };
    if (out[i].pw_ready) check_key(in[i].pw_valid, in[i].pw_id, "predicted-walk result accepted");
    if (out[i].outcome_ready)
      check_key(in[i].outcome_valid, in[i].outcome_id, "final outcome accepted");
    if (out[i].pw_ready)
      l.p0 =
          Msg{in[i].pw_valid, in[i].pw_id, in[i].pw_hit, in[i].pw_node, l.key_store[in[i].pw_id]};
    if (out[i].outcome_ready)
      l.f0 = Msg{in[i].outcome_valid, in[i].outcome_id, in[i].outcome_hit, in[i].outcome_node,
                 l.key_store[in[i].outcome_id]};
    if (l.b) {
      l.key_store[l.b->id] = {l.b->idx, l.b->tag, l.b->any_hit};
      l.key_store_written[l.b->id] = true;
    }
  }

  // Pipelines advance.
  for (uint32_t b = 0; b < banks_.size(); ++b) {
    auto& up = banks_[b].up;
    for (int s = kUpdateStages - 1; s > 0; --s) up[s] = up[s - 1];
    up[0] = issued[b];
  }
  for (size_t i = 0; i < n; ++i) {
    Lane& l = lanes_[i];
    for (int s = kLookupLatency - 1; s > 0; --s) l.d[s] = l.d[s - 1];
    l.d[0] = looked_up[i];
    const std::optional<DutIn> hashed = l.h[kHashLatency - 1];
    for (int s = kHashLatency - 1; s > 0; --s) l.h[s] = l.h[s - 1];
    l.h[0] = l.a;
    if (hashed) {
      const DutIn* a = &*hashed;
      const HashKey k = split_key(
          hash_key({a->org[0], a->org[1], a->org[2], a->dir[0], a->dir[1], a->dir[2]}, cfg_.hash),
          cfg_.hash);
      B b;
      b.id = a->ray_id;
      b.idx = k.index;
      b.tag = table_.stored_tag(k.tag);
      for (uint32_t v : {a->org[0], a->org[1], a->org[2], a->dir[0], a->dir[1], a->dir[2]})
        b.invalid |= ((v >> 23) & 0xFF) == 0xFF;
      b.any_hit = answers_any_hit(static_cast<RayKind>(a->ray_kind), cfg_.mode);
      l.b = b;
    } else {
      l.b.reset();
    }
    if (in[i].ray_valid && out[i].ray_ready)
      l.a = in[i];
    else
      l.a.reset();
  }
  if (clearing_ && ++clear_idx_ == cfg_.table.sets / uint32_t(cfg_.lanes)) clearing_ = false;
  ++cycle_;
}

}  // namespace hrpp
