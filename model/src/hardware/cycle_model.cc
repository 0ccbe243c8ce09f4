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
  return {};
}

CycleModel::CycleModel(const CycleConfig& cfg)
    : cfg_(cfg),
      table_(cfg.table),
      key_store_(size_t{1} << cfg.id_bits),
      pred_given_(size_t{1} << cfg.id_bits, 0),
      requested_(cfg.table) {
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
  a_.reset();
  for (auto& h : h_) h.reset();
  b_.reset();
  for (auto& d : d_) d.reset();
  pred_fifo_.clear();
  update_queue_.clear();
  requests_.clear();
  requested_.clear();
  key_store_written_.assign(size_t{1} << cfg_.id_bits, false);
  kp_ = Msg{};
  kf_ = Msg{};
  p0_ = Msg{};
  f0_ = Msg{};
  for (auto& u : up_) u.reset();
  skip_fifo_.clear();
  cached_ = false;
}

int CycleModel::in_flight() const {
  int n = int(a_.has_value()) + int(b_.has_value());
  for (const auto& h : h_) n += int(h.has_value());
  for (const auto& d : d_) n += int(d.has_value());
  return n;
}

CycleModel::Decision CycleModel::decide() const {
  Decision d;
  const KeyEntry& kp = p0_.key;
  const KeyEntry& kf = f0_.key;
  d.action = skip_action(p0_.hit, kp.any_hit, cfg_.mode);
  const bool fifo_full = skip_fifo_.size() >= size_t(cfg_.skip_fifo_depth);
  const bool p_needs = d.action == Action::kSkip;
  // The request ports: a final outcome's first (an update when it hit, else a demote when its ray
  // was given a prediction, with confidence bits), a predicted-walk result's behind it.
  d.f_req = f0_.valid && (f0_.hit || f0_.demote);
  d.p_req = p0_.valid && p_needs && !fifo_full;
  if (d.f_req)
    d.update = Op{kf.idx, kf.tag, f0_.node, 0, f0_.demote};
  else if (d.p_req)
    d.update = Op{kp.idx, kp.tag, p0_.node};
  if (d.f_req && d.p_req) d.update2 = Op{kp.idx, kp.tag, p0_.node};
  // The update queue's room, from its count alone.
  d.room1 = update_queue_.size() + 1 <= size_t(cfg_.update_queue_depth);
  d.room2 = update_queue_.size() + 2 <= size_t(cfg_.update_queue_depth);
  d.f_advance = f0_.valid && (!d.f_req || d.room1);
  d.p_advance = p0_.valid && !fifo_full && (!p_needs || (d.f_req ? d.room2 : d.room1));
  d.p_take = !clearing_ && (!p0_.valid || d.p_advance);
  d.f_take = !clearing_ && (!f0_.valid || d.f_advance);
  return d;
}

void CycleModel::take_request(Op op) {
  op.seq = next_seq_++;
  update_queue_.push_back(op);
  requests_.push_back(op);
}

void CycleModel::drop_queue_head() {
  update_queue_.pop_front();  // it stays in requests_: applied to requested_ all the same
  stats_.dropped++;
}

void CycleModel::check_against_requests(const Op& written) {
  hrpp::check_against_requests(requests_, written, requested_, table_, cfg_.table.ways, &error_);
}

DutOut CycleModel::outputs() const {
  if (!cached_) {  // a function of the state: computed once per cycle
    cached_dec_ = decide();
    cached_out_ = outputs(cached_dec_);
    cached_ = true;
  }
  return cached_out_;
}

DutOut CycleModel::outputs(const Decision& d) const {
  DutOut o;
  o.ray_ready = !clearing_ && in_flight() + int(pred_fifo_.size()) < cfg_.pred_fifo_depth;
  if (!pred_fifo_.empty()) {
    const Pred& p = pred_fifo_.front();
    o.pred_valid = true;
    o.pred_id = p.id;
    o.pred_invalid = p.invalid;
    o.pred_count = p.count;
    o.pred_nodes = p.nodes;
  }
  if (cfg_.key_store_bram) {  // K takes a message when empty or when it moves on
    o.pw_ready = !clearing_ && (!kp_.valid || d.p_take);
    o.outcome_ready = !clearing_ && (!kf_.valid || d.f_take);
  } else {
    o.pw_ready = d.p_take;
    o.outcome_ready = d.f_take;
  }
  if (!skip_fifo_.empty()) {
    o.skip_valid = true;
    o.skip_id = skip_fifo_.front().first;
    o.skip_action = skip_fifo_.front().second;
  }
  return o;
}

void CycleModel::tick(const DutIn& in) {
  const DutOut o = outputs();
  const Decision dec = cached_dec_;
  cached_ = false;  // the state changes below

  // The write presented in this cycle (W), then the lookup read presented in this cycle (B):
  // the lookup sees the write (the RTL forwards a colliding write).
  if (up_[kUpdateStages - 1]) {
    const Op& w = *up_[kUpdateStages - 1];
    bool hit = false, full = true;
    for (uint32_t i = 0; i < cfg_.table.ways; ++i) {
      const Way& way = table_.way(w.idx, i);
      hit |= way.valid && way.tag == w.tag;
      full &= way.valid;
    }
    stats_.updates++;
    if (w.demote) {  // no allocation: never an eviction
      table_.demote(w.idx, w.tag, 0);
    } else {
      stats_.evictions += !hit && full;
      table_.update(w.idx, w.tag, 0, w.node);
    }
    check_against_requests(w);
  }
  std::optional<Pred> looked_up;
  if (b_) {
    Pred p;
    p.id = b_->id;
    p.invalid = b_->invalid;
    if (!b_->invalid) {
      const Prediction pr = table_.lookup(b_->idx, b_->tag, 0);
      p.count = pr.count;
      p.nodes = pr.nodes;
    }
    looked_up = p;
  }

  // Prediction FIFO (and, with confidence bits, whether the ray was given a prediction: written
  // after this cycle's reads below, as the RTL's register array).
  if (o.pred_valid && in.pred_ready) pred_fifo_.pop_front();
  std::optional<std::pair<uint32_t, bool>> given;
  if (d_[kLookupLatency - 1]) {
    pred_fifo_.push_back(*d_[kLookupLatency - 1]);
    given.emplace(d_[kLookupLatency - 1]->id, d_[kLookupLatency - 1]->count > 0);
  }

  // The table takes the update queue's head unless it is of the set of an update accepted in
  // either of the two previous cycles (T0, T1: the same-set interlock); if it is identical to
  // the newer of those of its set, it is taken and dropped (it would change nothing).
  std::optional<Op> issued;
  if (!clearing_ && !update_queue_.empty()) {
    const Op& head = update_queue_.front();
    const std::optional<Op>& t0 = up_[0];
    const std::optional<Op>& t1 = up_[1];
    const Op* newer = t0 && t0->idx == head.idx ? &*t0 : t1 && t1->idx == head.idx ? &*t1 : nullptr;
    // With confidence bits only a demote is dropped: a demote applied twice is applied once, an
    // update is not (an insertion clears the bit, the same update again sets it; docs/hash.md).
    const bool droppable = cfg_.table.conf_bits == 0 || head.demote;
    if (!newer) {
      issued = head;
      update_queue_.pop_front();
    } else if (droppable && newer->same_update(head)) {
      drop_queue_head();
    } else {
      stats_.interlock_cycles++;
    }
  }

  // Skip controller: the update queue takes the requests of the messages that advance.
  if (dec.update && dec.room1) {
    take_request(*dec.update);
    if (dec.update2 && dec.room2) take_request(*dec.update2);
  }
  if (o.skip_valid && in.skip_ready) skip_fifo_.pop_front();
  if (dec.p_advance) skip_fifo_.emplace_back(p0_.id, dec.action);
  auto check_key = [&](bool valid, uint32_t id, const char* what) {
    if (valid && !key_store_written_[id] && error_.empty())
      error_ = std::string(what) + " for ray id " + std::to_string(id) +
               " whose key-store entry was not written since reset (stale contents)";
  };
  if (o.pw_ready) check_key(in.pw_valid, in.pw_id, "predicted-walk result accepted");
  if (o.outcome_ready) check_key(in.outcome_valid, in.outcome_id, "final outcome accepted");
  // The key is read as the message is accepted: into P0 / F0 (distributed RAM), or into K, whose
  // message and key move on to P0 / F0 when those take it (block RAM: the RAM's output holds).
  Msg& pw_to = cfg_.key_store_bram ? kp_ : p0_;
  Msg& outcome_to = cfg_.key_store_bram ? kf_ : f0_;
  // Confidence: a final outcome entering F0 requests a demote when its ray was given a
  // prediction (read by id as it enters F0) and it has no hit.
  const bool conf = cfg_.table.conf_bits > 0;
  auto demotes_in_f0 = [&](const Msg& m) {
    return conf && m.valid && !m.hit && pred_given_[m.id] != 0;
  };
  if (cfg_.key_store_bram) {
    if (dec.p_take) p0_ = kp_;
    if (dec.f_take) {
      f0_ = kf_;
      f0_.demote = demotes_in_f0(f0_);
    }
  }
  if (o.pw_ready) pw_to = Msg{in.pw_valid, in.pw_id, in.pw_hit, in.pw_node, key_store_[in.pw_id]};
  if (o.outcome_ready) {
    outcome_to = Msg{in.outcome_valid, in.outcome_id, in.outcome_hit, in.outcome_node,
                     key_store_[in.outcome_id]};
    if (!cfg_.key_store_bram) f0_.demote = demotes_in_f0(f0_);
  }

  if (given && cfg_.table.conf_bits > 0) pred_given_[given->first] = given->second;
  // Key store write (B), after U0's read above.
  if (b_) {
    key_store_[b_->id] = {b_->idx, b_->tag, b_->any_hit};
    key_store_written_[b_->id] = true;
  }

  // Pipelines advance.
  for (int i = kUpdateStages - 1; i > 0; --i) up_[i] = up_[i - 1];
  up_[0] = issued;
  for (int i = kLookupLatency - 1; i > 0; --i) d_[i] = d_[i - 1];
  d_[0] = looked_up;
  const std::optional<DutIn> hashed = h_[kHashLatency - 1];
  for (int i = kHashLatency - 1; i > 0; --i) h_[i] = h_[i - 1];
  h_[0] = a_;
  if (hashed) {
    const DutIn* a = &*hashed;
    const HashKey k = split_key(
        hash_key({a->org[0], a->org[1], a->org[2], a->dir[0], a->dir[1], a->dir[2]}, cfg_.hash),
        cfg_.hash);
    B b;
    b.id = a->ray_id;
    b.idx = k.index;
    b.tag = table_.stored_tag(k.tag);
    b.invalid = false;
    for (uint32_t v : {a->org[0], a->org[1], a->org[2], a->dir[0], a->dir[1], a->dir[2]})
      b.invalid |= ((v >> 23) & 0xFF) == 0xFF;
    b.any_hit = answers_any_hit(static_cast<RayKind>(a->ray_kind), cfg_.mode);
    b_ = b;
  } else {
    b_.reset();
  }
  if (in.ray_valid && o.ray_ready) {
    a_ = in;
  } else {
    a_.reset();
  }
  if (clearing_ && ++clear_idx_ == cfg_.table.sets) clearing_ = false;
  ++cycle_;
}

}  // namespace hrpp
