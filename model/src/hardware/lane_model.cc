#include "hrpp/hardware/lane_model.h"

namespace hrpp {

LaneModel::LaneModel(const CycleConfig& cfg, std::string where)
    : cfg_(cfg),
      where_(std::move(where)),
      lookup_latency_(cfg.lookup_latency()),
      key_store_(size_t{1} << cfg.id_bits),
      pred_given_(size_t{1} << cfg.id_bits, 0) {
  reset();
}

void LaneModel::reset() {
  cached_ = false;
  a_.reset();
  for (auto& h : h_) h.reset();
  b_.reset();
  lookup_queue_.clear();
  for (auto& d : d_) d.reset();
  pred_fifo_.clear();
  key_store_written_.assign(size_t{1} << cfg_.id_bits, false);
  kp_ = Msg{};
  kf_ = Msg{};
  jp_ = Msg{};
  jf_ = Msg{};
  p0_ = Msg{};
  f0_ = Msg{};
  update_queue_.clear();
  skip_fifo_.clear();
}

int LaneModel::in_flight() const {
  int n = int(a_.has_value()) + int(b_.has_value()) + int(lookup_queue_.size());
  for (const auto& h : h_) n += int(h.has_value());
  for (const auto& d : d_) n += int(d.has_value());
  return n;
}

LaneModel::Decision LaneModel::decide(bool clearing) const {
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
  d.p_take = !clearing && (!p0_.valid || d.p_advance);
  d.f_take = !clearing && (!f0_.valid || d.f_advance);
  d.jp_take = !clearing && (!jp_.valid || d.p_take);
  d.jf_take = !clearing && (!jf_.valid || d.f_take);
  return d;
}

const DutOut& LaneModel::outputs(bool clearing) const {
  if (!cached_ || cached_clearing_ != clearing) {  // a function of the state: once per cycle
    cached_dec_ = decide(clearing);
    cached_out_ = outputs(cached_dec_, clearing);
    cached_clearing_ = clearing;
    cached_ = true;
  }
  return cached_out_;
}

DutOut LaneModel::outputs(const Decision& d, bool clearing) const {
  DutOut o;
  o.ray_ready = !clearing && in_flight() + int(pred_fifo_.size()) < cfg_.pred_fifo_depth;
  if (!pred_fifo_.empty()) {
    const Pred& p = pred_fifo_.front();
    o.pred_valid = true;
    o.pred_id = p.id;
    o.pred_invalid = p.invalid;
    o.pred_count = p.count;
    o.pred_nodes = p.nodes;
  }
  if (cfg_.key_store_bram) {  // K takes a message when empty or when it moves on
    const bool reg = cfg_.key_store_reg;
    o.pw_ready = !clearing && (!kp_.valid || (reg ? d.jp_take : d.p_take));
    o.outcome_ready = !clearing && (!kf_.valid || (reg ? d.jf_take : d.f_take));
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

const LaneModel::B* LaneModel::lookup_head() const {
  if (!lookup_queue_.empty()) return &lookup_queue_.front();
  return b_ ? &*b_ : nullptr;
}

void LaneModel::begin(bool clearing) {
  out_ = outputs(clearing);
  dec_ = cached_dec_;
  cached_ = false;  // the state changes below
}

bool LaneModel::lookup(bool granted, PredTable& table) {
  looked_up_.reset();
  const B* head = lookup_head();
  if (!head) return false;  // the queue is empty and B too
  const bool go = head->invalid || granted;
  if (go) {
    Pred p;
    p.id = head->id;
    p.invalid = head->invalid;
    if (!p.invalid) {
      const Prediction pr = table.lookup(head->idx, head->tag, 0);
      p.count = pr.count;
      p.nodes = pr.nodes;
    }
    looked_up_ = p;
  }
  const bool queue_was_empty = lookup_queue_.empty();
  if (go && !queue_was_empty) lookup_queue_.pop_front();
  if (b_ && !(queue_was_empty && go)) lookup_queue_.push_back(*b_);
  return !go;
}

void LaneModel::pred_fifo(const DutIn& in) {
  // With confidence bits, whether the ray was given a prediction is written after this cycle's
  // reads in finish(), as the RTL's register array.
  if (out_.pred_valid && in.pred_ready) pred_fifo_.pop_front();
  given_.reset();
  if (const std::optional<Pred>& due = d_[lookup_latency_ - 1]) {
    pred_fifo_.push_back(*due);
    given_.emplace(due->id, due->count > 0);
  }
}

void LaneModel::finish(const DutIn& in, const PredTable& table, std::string* error) {
  const DutOut& o = out_;
  const Decision& dec = dec_;
  // Skip controller: the update queue takes the requests of the messages that advance.
  if (dec.update && dec.room1) {
    update_queue_.push_back(*dec.update);
    if (dec.update2 && dec.room2) update_queue_.push_back(*dec.update2);
  }
  if (o.skip_valid && in.skip_ready) skip_fifo_.pop_front();
  if (dec.p_advance) skip_fifo_.emplace_back(p0_.id, dec.action);
  auto check_key = [&](bool valid, uint32_t id, const char* what) {
    if (valid && !key_store_written_[id] && error->empty())
      *error = std::string(what) + where_ + " for ray id " + std::to_string(id) +
               " whose key-store entry was not written since reset (stale contents)";
  };
  if (o.pw_ready) check_key(in.pw_valid, in.pw_id, "predicted-walk result accepted");
  if (o.outcome_ready) check_key(in.outcome_valid, in.outcome_id, "final outcome accepted");
  // The key is read as the message is accepted: into P0 / F0 (distributed RAM), or into K, whose
  // message and key move on to P0 / F0 when those take it (block RAM: the RAM's output holds),
  // through J with the read register (the key in the RAM's output register).
  Msg& pw_to = cfg_.key_store_bram ? kp_ : p0_;
  Msg& outcome_to = cfg_.key_store_bram ? kf_ : f0_;
  // Confidence: a final outcome entering F0 requests a demote when its ray was given a
  // prediction (read by id as it enters F0) and it has no hit.
  const bool conf = cfg_.table.conf_bits > 0;
  auto demotes_in_f0 = [&](const Msg& m) {
    return conf && m.valid && !m.hit && pred_given_[m.id] != 0;
  };
  if (cfg_.key_store_bram) {
    const bool reg = cfg_.key_store_reg;
    if (dec.p_take) p0_ = reg ? jp_ : kp_;
    if (dec.f_take) {
      f0_ = reg ? jf_ : kf_;
      f0_.demote = demotes_in_f0(f0_);
    }
    if (reg && dec.jp_take) jp_ = kp_;
    if (reg && dec.jf_take) jf_ = kf_;
  }
  if (o.pw_ready) pw_to = Msg{in.pw_valid, in.pw_id, in.pw_hit, in.pw_node, key_store_[in.pw_id]};
  if (o.outcome_ready) {
    outcome_to = Msg{in.outcome_valid, in.outcome_id, in.outcome_hit, in.outcome_node,
                     key_store_[in.outcome_id]};
    if (!cfg_.key_store_bram) f0_.demote = demotes_in_f0(f0_);
  }

  if (given_ && conf) pred_given_[given_->first] = given_->second;
  // Key store write (B), after the reads above.
  if (b_) {
    key_store_[b_->id] = {b_->idx, b_->tag, b_->any_hit};
    key_store_written_[b_->id] = true;
  }

  // Pipelines advance.
  for (int i = lookup_latency_ - 1; i > 0; --i) d_[i] = d_[i - 1];
  d_[0] = looked_up_;
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
    b.tag = table.stored_tag(k.tag);
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
}

}  // namespace hrpp
