#include "hrpp/sim/unit_predictor.h"

#include <bit>

#include "hrpp/rtl_config_data.h"

namespace hrpp::sim {

// ---- PortPredictor ---------------------------------------------------------------------------

PortPredictor::PortPredictor(const std::vector<RayRecord>& rays, std::unique_ptr<PortModel> model,
                             int id_bits, bool confidence)
    : rays_(rays),
      model_(std::move(model)),
      ray_of_(size_t{1} << id_bits, 0),
      in_use_(size_t{1} << id_bits, 0),
      confidence_(confidence),
      predicted_(size_t{1} << id_bits, 0) {
  for (uint32_t i = 0; i < (1u << id_bits); ++i) free_ids_.push_back(i);
}

bool PortPredictor::busy() const {
  if (offered_) return true;
  for (uint8_t u : in_use_)
    if (u) return true;
  return false;
}

std::string PortPredictor::error() const {
  if (!error_.empty()) return error_;
  return model_->error();
}

void PortPredictor::cycle(uint64_t now, UnitIo* io) {
  DutIn in;
  // A ray, once offered, stays offered (same id and fields) until taken.
  if (!offered_ && !io->entering.empty() && !free_ids_.empty()) {
    offered_ = {free_ids_.front(), io->entering.front()};
    free_ids_.pop_front();
    io->entering.pop_front();
  }
  const bool waiting = offered_ || !io->entering.empty();
  if (offered_) {
    const RayRecord& r = rays_[offered_->second];
    in.ray_valid = true;
    in.ray_id = offered_->first;
    in.ray_kind = static_cast<uint8_t>(r.kind);
    for (int i = 0; i < 3; ++i) {
      in.org[i] = std::bit_cast<uint32_t>(r.ray.org[i]);
      in.dir[i] = std::bit_cast<uint32_t>(r.ray.dir[i]);
    }
  }
  in.pred_ready = true;
  in.skip_ready = true;
  // The head of a message queue, offered on a port (held there until taken).
  auto offer = [&](const std::deque<EngineMsg>& q, bool* valid, uint32_t* id, bool* hit,
                   uint32_t* node) {
    if (q.empty()) return;
    *valid = true;
    *id = id_of_.at(q.front().ray);
    *hit = q.front().hit;
    *node = q.front().node;
  };
  offer(io->pw, &in.pw_valid, &in.pw_id, &in.pw_hit, &in.pw_node);
  offer(io->outcomes, &in.outcome_valid, &in.outcome_id, &in.outcome_hit, &in.outcome_node);
  const DutOut out = model_->outputs();
  auto release = [&](uint32_t id) {
    id_of_.erase(ray_of_[id]);
    in_use_[id] = 0;
    free_ids_.push_back(id);
  };
  bool took = false;
  if (in.ray_valid && out.ray_ready) {
    const auto [id, ray] = *offered_;
    ray_of_[id] = ray;
    in_use_[id] = 1;
    id_of_[ray] = id;
    offered_.reset();
    stats_.lookups++;
    took = true;
  }
  if (waiting && !took) stats_.stall_cycles++;
  if (out.pred_valid) {
    if (out.pred_id >= in_use_.size() || !in_use_[out.pred_id]) {
      error_ = "cycle " + std::to_string(now) + ": prediction for ray id " +
               std::to_string(out.pred_id) + " that is not in flight";
    } else {
      Prediction p;
      p.count = out.pred_invalid ? 0 : out.pred_count;
      if (p.count > uint32_t(kMaxNodesPerEntry)) {
        error_ = "cycle " + std::to_string(now) + ": prediction of " + std::to_string(p.count) +
                 " nodes";
        p.count = 0;
      }
      for (uint32_t i = 0; i < p.count; ++i) p.nodes[i] = out.pred_nodes[i];
      predicted_[out.pred_id] = p.count > 0;
      io->predictions.emplace_back(ray_of_[out.pred_id], p);
    }
  }
  if (out.skip_valid) {
    if (out.skip_id >= in_use_.size() || !in_use_[out.skip_id]) {
      error_ = "cycle " + std::to_string(now) + ": skip decision for ray id " +
               std::to_string(out.skip_id) + " that is not in flight";
    } else {
      io->decisions.emplace_back(ray_of_[out.skip_id], out.skip_action);
      if (out.skip_action == Action::kSkip) {  // the final result: no outcome follows
        release(out.skip_id);
        stats_.updates++;  // the skip controller refreshes the verified node
      }
    }
  }
  if (in.pw_valid && out.pw_ready) {
    if (in.pw_hit) predicted_[in.pw_id] = 0;  // not a failed prediction
    io->pw.pop_front();
  }
  if (in.outcome_valid && out.outcome_ready) {
    stats_.updates += in.outcome_hit;
    // With confidence counters, a failed prediction without a node to write demotes its entry.
    stats_.demotes += !in.outcome_hit && predicted_[in.outcome_id] && confidence_;
    io->outcomes.pop_front();
    release(in.outcome_id);
  }
  stats_.entry_wait += io->entering.size() + (offered_ ? 1 : 0);  // the ray on offer waits too
  stats_.mismatches = model_->mismatches();
  model_->tick(in);
}

// ---- TimedPredictor --------------------------------------------------------------------------

nlohmann::json TimedConfig::to_json() const {
  return {{"lookup_latency", lookup_latency},
          {"decision_latency", decision_latency},
          {"update_latency", update_latency},
          {"lookups_per_cycle", lookups_per_cycle},
          {"updates_per_cycle", updates_per_cycle},
          {"credits", credits},
          {"oracle", oracle}};
}

TimedConfig preset_timing(const std::string& preset) {
  TimedConfig t;
  if (preset == "micro21") {
    // ubc-aamodt-group/ray-intersection-predictor, configs/tested-cfgs/MOBILE/gpgpusim.config:
    // -gpgpu_rt_predictor_lookup_latency 1, -gpgpu_rt_predictor_lookup_bandwidth 4 (a warp's
    // 32 rays over 8 cycles), -gpgpu_rt_predictor_update_bandwidth 4; a warp is held by the
    // predictor (up to 16, the unit's ray buffer: no credit limit of its own). The skip is
    // decided by the RT unit when the predicted walk ends (no decision latency). When a write
    // becomes visible is not found in their code: assumed the cycle after the outcome.
    t.lookup_latency = 1;
    t.lookups_per_cycle = 4;
    t.decision_latency = 0;
    t.update_latency = 1;
    t.updates_per_cycle = 4;
    t.credits = 0;
    return t;
  }
  // An RTL configuration's latencies (a key store in block RAM adds a cycle to the decision and
  // the update: rtl_config.h); any other preset, the default configuration's.
  bool bram = false;
  for (const rtl::ConfigData& c : rtl::kConfigs)
    if (preset == std::string("rtl-") + c.name) bram = c.key_store_bram;
  t.lookup_latency = rtl::kPredictionLatency;
  t.decision_latency = rtl::kDecisionLatency + int(bram);
  t.update_latency = rtl::kUpdateLanding + int(bram);
  t.lookups_per_cycle = 1;
  t.updates_per_cycle = 1;
  t.credits = 0;
  return t;
}

TimedPredictor::TimedPredictor(const Bvh& bvh, const std::vector<RayRecord>& rays,
                               const PredictorConfig& pc, const TimedConfig& tc)
    : bvh_(bvh), rays_(rays), pc_(pc), tc_(tc), table_(pc.table) {}

bool TimedPredictor::busy() const {
  return held_ > 0 || !preds_.empty() || !decisions_.empty() || !writes_.empty();
}

Prediction TimedPredictor::predict(uint32_t ray) {
  const RayRecord& r = rays_[ray];
  Prediction p;
  if (tc_.oracle) {  // the baseline walk's hit, told at no cost
    Counters c;
    const Hit h = engine_walk(bvh_, r.ray, answers_any_hit(r.kind, pc_.mode), 0, &c);
    if (h.hit()) {
      p.count = 1;
      p.nodes[0] = bvh_.ancestor(h.leaf, pc_.go_up);
    }
    return p;
  }
  const HashKey key = hash_ray(r.ray, pc_.hash);
  p = table_.lookup(key.index, key.tag, key.key);
  held_of_[ray] = {key, p.count > 0, false};
  stats_.suppressed_lookups += p.suppressed;
  return p;
}

void TimedPredictor::cycle(uint64_t now, UnitIo* io) {
  // Writes visible by this cycle land before this cycle's lookups (updates and demotes in the
  // order the rays finished).
  while (!writes_.empty() && writes_.front().due <= now) {
    const Write& w = writes_.front();
    if (w.demote)
      table_.demote(w.key.index, w.key.tag, w.key.key);
    else
      table_.update(w.key.index, w.key.tag, w.key.key, w.node);
    writes_.pop_front();
  }
  const bool waiting = !io->entering.empty();
  uint32_t took = 0;
  while (took < tc_.lookups_per_cycle && !io->entering.empty() &&
         (tc_.credits == 0 || held_ < tc_.credits)) {
    const uint32_t ray = io->entering.front();
    io->entering.pop_front();
    preds_.push_back({now + tc_.lookup_latency, ray, predict(ray)});
    ++held_;
    ++took;
    stats_.lookups++;
  }
  if (waiting && took == 0) stats_.stall_cycles++;
  stats_.entry_wait += io->entering.size();
  while (!preds_.empty() && preds_.front().due <= now) {
    io->predictions.emplace_back(preds_.front().ray, preds_.front().p);
    preds_.pop_front();
  }
  auto write = [&](uint32_t ray, uint32_t node) {
    if (tc_.oracle) return;
    writes_.push_back({now + tc_.update_latency, held_of_.at(ray).key, node});
    stats_.updates++;
  };
  // Confidence: a ray given a prediction whose predicted walks found no hit and whose outcome is
  // a miss (no node to write) demotes its entry (PredTable::demote).
  auto demote = [&](uint32_t ray) {
    if (tc_.oracle) return;
    const Held& h = held_of_.at(ray);
    if (!demotes(pc_.table, h.predicted, h.pw_hit, kNoNode)) return;
    writes_.push_back({now + tc_.update_latency, h.key, 0, true});
    stats_.demotes++;
  };
  auto release = [&](uint32_t ray) {
    held_of_.erase(ray);
    --held_;
  };
  for (uint32_t n = 0; n < tc_.lookups_per_cycle && !io->pw.empty(); ++n) {
    const EngineMsg m = io->pw.front();
    io->pw.pop_front();
    const RayRecord& r = rays_[m.ray];
    if (const auto h = held_of_.find(m.ray); h != held_of_.end()) h->second.pw_hit = m.hit;
    const Action a = skip_action(m.hit, answers_any_hit(r.kind, pc_.mode), pc_.mode);
    decisions_.push_back({now + tc_.decision_latency, m.ray, a, m.node});
  }
  while (!decisions_.empty() && decisions_.front().due <= now) {
    const Decision& d = decisions_.front();
    io->decisions.emplace_back(d.ray, d.action);
    if (d.action == Action::kSkip) {  // the verified node's recency refreshed; no outcome follows
      write(d.ray, d.node);
      release(d.ray);
    }
    decisions_.pop_front();
  }
  for (uint32_t n = 0; n < tc_.updates_per_cycle && !io->outcomes.empty(); ++n) {
    const EngineMsg m = io->outcomes.front();
    io->outcomes.pop_front();
    if (m.hit)
      write(m.ray, m.node);
    else
      demote(m.ray);
    release(m.ray);
  }
}

}  // namespace hrpp::sim
