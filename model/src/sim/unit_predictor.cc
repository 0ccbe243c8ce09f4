#include "hrpp/sim/unit_predictor.h"

#include <algorithm>
#include <bit>
#include <functional>

#include "hrpp/hardware/rtl_config.h"
#include "hrpp/rtl_config_data.h"

namespace hrpp::sim {

// ---- PortPredictor ---------------------------------------------------------------------------

PortPredictor::PortPredictor(const std::vector<RayRecord>& rays, std::unique_ptr<PortModel> model,
                             int id_bits, bool confidence)
    : rays_(rays), model_(std::move(model)), confidence_(confidence) {
  lanes_.resize(size_t(model_->lanes()));
  for (Lane& l : lanes_) {
    l.ray_of.assign(size_t{1} << id_bits, 0);
    l.in_use.assign(size_t{1} << id_bits, 0);
    l.predicted.assign(size_t{1} << id_bits, 0);
    for (uint32_t i = 0; i < (1u << id_bits); ++i) l.free_ids.push_back(i);
  }
}

bool PortPredictor::busy() const {
  for (const Lane& l : lanes_) {
    if (l.offered) return true;
    for (uint8_t u : l.in_use)
      if (u) return true;
  }
  return false;
}

std::string PortPredictor::error() const {
  if (!error_.empty()) return error_;
  return model_->error();
}

void PortPredictor::cycle(uint64_t now, UnitIo* io) {
  const size_t nl = lanes_.size();
  std::vector<DutIn> in(nl);
  // A ray, once offered, stays offered (same id and fields) until taken; each lane without one
  // takes the next entering ray, lanes in order.
  for (Lane& l : lanes_) {
    if (!l.offered && !io->entering.empty() && !l.free_ids.empty()) {
      l.offered = {l.free_ids.front(), io->entering.front()};
      l.free_ids.pop_front();
      io->entering.pop_front();
    }
  }
  bool waiting = !io->entering.empty();
  for (size_t k = 0; k < nl; ++k) {
    const Lane& l = lanes_[k];
    in[k].pred_ready = true;
    in[k].skip_ready = true;
    if (!l.offered) continue;
    waiting = true;
    const RayRecord& r = rays_[l.offered->second];
    in[k].ray_valid = true;
    in[k].ray_id = l.offered->first;
    in[k].ray_kind = static_cast<uint8_t>(r.kind);
    for (int i = 0; i < 3; ++i) {
      in[k].org[i] = std::bit_cast<uint32_t>(r.ray.org[i]);
      in[k].dir[i] = std::bit_cast<uint32_t>(r.ray.dir[i]);
    }
  }
  // Per lane, the oldest message of its rays, offered on its port (held there until taken);
  // at[k]: its place in the queue, or -1. One lane: the queue's head.
  auto offer = [&](const std::deque<EngineMsg>& q, std::vector<int>* at, bool DutIn::*valid,
                   uint32_t DutIn::*id, bool DutIn::*hit, uint32_t DutIn::*node) {
    at->assign(nl, -1);
    size_t open = nl;
    for (size_t i = 0; i < q.size() && open > 0; ++i) {
      const LaneId li = id_of_.at(q[i].ray);
      if ((*at)[li.lane] >= 0) continue;
      (*at)[li.lane] = int(i);
      --open;
      DutIn& d = in[li.lane];
      d.*valid = true;
      d.*id = li.id;
      d.*hit = q[i].hit;
      d.*node = q[i].node;
    }
  };
  std::vector<int> pw_at, outcome_at;
  offer(io->pw, &pw_at, &DutIn::pw_valid, &DutIn::pw_id, &DutIn::pw_hit, &DutIn::pw_node);
  offer(io->outcomes, &outcome_at, &DutIn::outcome_valid, &DutIn::outcome_id, &DutIn::outcome_hit,
        &DutIn::outcome_node);
  std::vector<int> pw_taken, outcomes_taken;  // places in the queues, removed after the lanes
  bool took = false;
  for (size_t k = 0; k < nl; ++k) {
    Lane& l = lanes_[k];
    const DutOut out = model_->outputs(int(k));
    auto release = [&](uint32_t id) {
      id_of_.erase(l.ray_of[id]);
      l.in_use[id] = 0;
      l.free_ids.push_back(id);
    };
    if (in[k].ray_valid && out.ray_ready) {
      const auto [id, ray] = *l.offered;
      l.ray_of[id] = ray;
      l.in_use[id] = 1;
      id_of_[ray] = {uint32_t(k), id};
      l.offered.reset();
      stats_.lookups++;
      took = true;
    }
    const std::string where = nl > 1 ? " on lane " + std::to_string(k) : "";
    if (out.pred_valid) {
      if (out.pred_id >= l.in_use.size() || !l.in_use[out.pred_id]) {
        error_ = "cycle " + std::to_string(now) + ": prediction for ray id " +
                 std::to_string(out.pred_id) + where + " that is not in flight";
      } else {
        Prediction p;
        p.count = out.pred_invalid ? 0 : out.pred_count;
        if (p.count > uint32_t(kMaxNodesPerEntry)) {
          error_ = "cycle " + std::to_string(now) + ": prediction of " + std::to_string(p.count) +
                   " nodes" + where;
          p.count = 0;
        }
        for (uint32_t i = 0; i < p.count; ++i) p.nodes[i] = out.pred_nodes[i];
        l.predicted[out.pred_id] = p.count > 0;
        io->predictions.emplace_back(l.ray_of[out.pred_id], p);
      }
    }
    if (out.skip_valid) {
      if (out.skip_id >= l.in_use.size() || !l.in_use[out.skip_id]) {
        error_ = "cycle " + std::to_string(now) + ": skip decision for ray id " +
                 std::to_string(out.skip_id) + where + " that is not in flight";
      } else {
        io->decisions.emplace_back(l.ray_of[out.skip_id], out.skip_action);
        if (out.skip_action == Action::kSkip) {  // the final result: no outcome follows
          release(out.skip_id);
          stats_.updates++;  // the skip controller refreshes the verified node
        }
      }
    }
    if (in[k].pw_valid && out.pw_ready) {
      if (in[k].pw_hit) l.predicted[in[k].pw_id] = 0;  // not a failed prediction
      pw_taken.push_back(pw_at[k]);
    }
    if (in[k].outcome_valid && out.outcome_ready) {
      stats_.updates += in[k].outcome_hit;
      // With confidence counters, a failed prediction without a node to write demotes its entry.
      stats_.demotes += !in[k].outcome_hit && l.predicted[in[k].outcome_id] && confidence_;
      outcomes_taken.push_back(outcome_at[k]);
      release(in[k].outcome_id);
    }
  }
  if (waiting && !took) stats_.stall_cycles++;
  auto remove = [](std::deque<EngineMsg>* q, std::vector<int> at) {
    std::sort(at.begin(), at.end(), std::greater<>());
    for (int i : at) q->erase(q->begin() + i);
  };
  remove(&io->pw, pw_taken);
  remove(&io->outcomes, outcomes_taken);
  // The rays on offer wait too.
  for (const Lane& l : lanes_) stats_.entry_wait += l.offered ? 1 : 0;
  stats_.entry_wait += io->entering.size();
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
  // An RTL configuration's latencies (RtlConfig's: the key store in block RAM, its read register
  // and the table's issue register add to the declared ones, a table of RAM banks to the lookup's);
  // any other preset, the declared ones.
  t.lookup_latency = rtl::kPredictionLatency;
  t.decision_latency = rtl::kDecisionLatency;
  t.update_latency = rtl::kUpdateLanding;
  for (const rtl::ConfigData& c : rtl::kConfigs)
    if (preset == std::string("rtl-") + c.name) {
      const RtlConfig r = make_rtl_config(c);
      t.lookup_latency = r.prediction_latency();
      t.decision_latency = r.decision_latency();
      t.update_latency = r.update_landing();
    }
  t.lookups_per_cycle = 1;
  t.updates_per_cycle = 1;
  t.credits = 0;
  return t;
}

LookupClass TimedPredictor::take_class(uint32_t ray) {
  const auto it = class_of_.find(ray);
  if (it == class_of_.end()) return LookupClass::kUnknown;
  const LookupClass c = it->second;
  class_of_.erase(it);
  return c;
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
  class_of_[ray] = p.count > 0                 ? LookupClass::kPredicted
                   : p.suppressed              ? LookupClass::kSuppressed
                   : in_flight_.count(key.key) ? LookupClass::kStale
                   : written_.count(key.key)   ? LookupClass::kEvicted
                                               : LookupClass::kCompulsory;
  stats_.suppressed_lookups += p.suppressed;
  return p;
}

void TimedPredictor::cycle(uint64_t now, UnitIo* io) {
  // Writes visible by this cycle land before this cycle's lookups (updates and demotes in the
  // order the rays finished).
  while (!writes_.empty() && writes_.front().due <= now) {
    const Write& w = writes_.front();
    if (w.demote) {
      table_.demote(w.key.index, w.key.tag, w.key.key);
    } else {
      table_.update(w.key.index, w.key.tag, w.key.key, w.node);
      if (auto it = in_flight_.find(w.key.key); it != in_flight_.end() && --it->second == 0)
        in_flight_.erase(it);
    }
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
    const HashKey& key = held_of_.at(ray).key;
    writes_.push_back({now + tc_.update_latency, key, node});
    written_.insert(key.key);
    in_flight_[key.key]++;
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
