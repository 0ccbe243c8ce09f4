#include "engine.h"

#include <algorithm>
#include <bit>
#include <string>

namespace hrpp::tb {

Engine::Engine(const Bvh& bvh, const std::vector<RayRecord>& rays, const EngineOptions& opt)
    : bvh_(bvh),
      rays_(rays),
      opt_(opt),
      rng_(opt.seed),
      reports_(rays.size(), 0),
      stall_rng_(opt.seed ^ 0x5741'4c4c'5354'414cull) {
  for (uint32_t i = 0; i < (1u << opt.id_bits); ++i) free_ids_.push_back(i);
  by_id_.resize(size_t{1} << opt.id_bits);
}

void Engine::step_stalls(uint64_t cycle) {
  if (!opt_.stall_gap) return;
  for (int p = 0; p < kNumStallPorts; ++p) {
    if (cycle >= stall_until_[p] &&
        std::uniform_int_distribution<uint64_t>(1, opt_.stall_gap)(stall_rng_) == 1) {
      const uint64_t len = std::uniform_int_distribution<uint64_t>(
          1, std::max<uint64_t>(1, opt_.stall_max))(stall_rng_);
      stall_until_[p] = cycle + len;
      stall_[p].stalls++;
      stall_[p].longest = std::max(stall_[p].longest, len);
    }
    stalled_[p] = cycle < stall_until_[p];
    stall_[p].cycles += stalled_[p];
  }
}

uint64_t Engine::reset() {
  std::vector<size_t> dropped;
  uint64_t in_flight = 0;
  if (offered_ray_) dropped.push_back(offered_ray_->second);  // offered, not taken: offer again
  offered_ray_.reset();
  for (auto& f : by_id_)
    if (f) {
      dropped.push_back(f->ray);
      f.reset();
      ++in_flight;
    }
  if (opt_.fault == 1) {
    const size_t n = dropped.size();
    for (size_t i = 0; i < n; ++i) dropped.push_back(dropped[i]);
  }
  dropped.insert(dropped.end(), redo_.begin(), redo_.end());
  std::sort(dropped.begin(), dropped.end());
  redo_.assign(dropped.begin(), dropped.end());
  free_ids_.clear();
  for (uint32_t i = 0; i < by_id_.size(); ++i) free_ids_.push_back(i);
  in_flight_ = 0;
  for (Port* p : {&pw_, &upd_}) {
    p->pending.clear();
    p->offered.reset();
  }
  reoffered_ += in_flight;
  return in_flight;
}

std::string Engine::check_exactly_once() const {
  uint64_t lost = 0, twice = 0;
  std::string first;
  for (size_t i = 0; i < reports_.size(); ++i) {
    if (reports_[i] == 1) continue;
    (reports_[i] == 0 ? lost : twice)++;
    if (first.empty())
      first = "ray " + std::to_string(i) + " of the stream has " + std::to_string(reports_[i]) +
              " final results";
  }
  if (first.empty()) return {};
  return std::to_string(lost) + " rays lost, " + std::to_string(twice) +
         " reported more than once (first: " + first + ")";
}

void Engine::drive(uint64_t cycle, DutIn* in) {
  *in = DutIn{};
  step_stalls(cycle);
  const bool stalled = opt_.stall_every && cycle % opt_.stall_every < opt_.stall_length;
  // Rays: once offered, a ray stays offered (same id and fields) until accepted. Rays dropped by
  // a reset go first.
  const bool can_offer =
      !offered_ray_ && (!redo_.empty() || next_ray_ < rays_.size()) && !free_ids_.empty();
  if (can_offer && stalled_[kStallRay]) stall_[kStallRay].blocked++;
  if (opt_.fault == 2 && offered_ray_ && stalled_[kStallRay]) {
    free_ids_.push_back(offered_ray_->first);
    offered_ray_.reset();
  }
  if (can_offer && !stalled_[kStallRay] && chance(opt_.p_ray)) {
    size_t ray;
    if (!redo_.empty()) {
      ray = redo_.front();
      redo_.pop_front();
    } else {
      ray = next_ray_++;
    }
    offered_ray_ = {free_ids_.front(), ray};
    free_ids_.pop_front();
  }
  if (offered_ray_) {
    const RayRecord& r = rays_[offered_ray_->second];
    in->ray_valid = true;
    in->ray_id = offered_ray_->first;
    in->ray_kind = static_cast<uint8_t>(r.kind);
    for (int i = 0; i < 3; ++i) {
      in->org[i] = std::bit_cast<uint32_t>(r.ray.org[i]);
      in->dir[i] = std::bit_cast<uint32_t>(r.ray.dir[i]);
    }
  }
  in->pred_ready = !stalled && !stalled_[kStallPred] && chance(opt_.p_pred_ready);
  in->skip_ready = !stalled && !stalled_[kStallSkip] && chance(opt_.p_skip_ready);
  // Outcomes: the earliest pending message whose latency has passed, held until accepted.
  for (auto [p, port] : {std::pair{&pw_, kStallPw}, std::pair{&upd_, kStallUpd}})
    if (!p->offered && !p->pending.empty() && p->pending.front().ready_cycle <= cycle) {
      if (stalled_[port]) {
        stall_[port].blocked++;
        continue;
      }
      p->offered = p->pending.front();
      p->pending.pop_front();
    }
  if (pw_.offered) {
    in->pw_valid = true;
    in->pw_id = pw_.offered->id;
    in->pw_hit = pw_.offered->hit;
    in->pw_node = pw_.offered->node;
  }
  if (upd_.offered) {
    in->outcome_valid = true;
    in->outcome_id = upd_.offered->id;
    in->outcome_hit = upd_.offered->hit;
    in->outcome_node = upd_.offered->node;
  }
}

void Engine::observe(uint64_t cycle, const DutIn& in, const DutOut& out) {
  auto schedule = [&](Port* port, uint32_t id, bool hit, uint32_t node) {
    const Message m{cycle + latency(), id, hit, node};
    auto pos = std::upper_bound(port->pending.begin(), port->pending.end(), m.ready_cycle,
                                [](uint64_t c, const Message& x) { return c < x.ready_cycle; });
    port->pending.insert(pos, m);
  };

  if (out.pred_valid && stalled_[kStallPred]) stall_[kStallPred].blocked++;
  if (out.skip_valid && stalled_[kStallSkip]) stall_[kStallSkip].blocked++;

  if (in.ray_valid && out.ray_ready) {
    const auto [id, ray] = *offered_ray_;
    offered_ray_.reset();
    InFlight f;
    f.ray = ray;
    set_query(rays_[ray].kind, opt_.mode, &f.er);
    by_id_[id] = f;  // the baseline walk is made with the skip decision
    max_in_flight_ = std::max(max_in_flight_, ++in_flight_);
  }

  if (out.pred_valid && in.pred_ready) {
    if (!by_id_[out.pred_id]) {
      error_ = "prediction for ray id " + std::to_string(out.pred_id) + " that is not in flight";
      return;
    }
    EngineRay& er = by_id_[out.pred_id]->er;
    const Ray& r = rays_[by_id_[out.pred_id]->ray].ray;
    er.predicted = out.pred_count > 0;
    if (out.pred_count > uint32_t(kMaxNodesPerEntry)) {
      error_ = "prediction of " + std::to_string(out.pred_count) + " nodes";
      return;
    }
    for (uint32_t i = 0; i < out.pred_count; ++i) {
      const uint32_t node = out.pred_nodes[i];
      if (node >= bvh_.nodes.size()) {
        error_ = "predicted node " + std::to_string(node) + " outside the BVH";
        return;
      }
      if (!walk_predicted_node(bvh_, r, node, &er)) break;
    }
    schedule(&pw_, out.pred_id, er.best.hit(), er.best.hit() ? er.best_node : 0);
  }

  if (out.skip_valid && in.skip_ready) {
    const uint32_t id = out.skip_id;
    if (!by_id_[id]) {
      error_ = "skip decision for ray id " + std::to_string(id) + " that is not in flight";
      return;
    }
    EngineRay& er = by_id_[id]->er;
    const Ray& r = rays_[by_id_[id]->ray].ray;
    // The baseline walk (the statistics' reference and the exactness check) is made here, once
    // the decision is known, so that a shortened closest-hit walk rides along with it
    // (walk_from_root: both walks' hits and counters, exactly; docs/predictor.md).
    walk_from_root(bvh_, r, out.skip_action, &er);
    finish(bvh_, out.skip_action, &er);
    if (out.skip_action == Action::kSkip) {
      report(id);
    } else {
      const uint32_t node = update_node(bvh_, er, opt_.go_up);
      schedule(&upd_, id, er.answer.hit(), node != kNoNode ? node : 0);
    }
  }

  if (in.pw_valid && out.pw_ready) pw_.offered.reset();
  if (in.outcome_valid && out.outcome_ready) {
    const uint32_t id = upd_.offered->id;
    upd_.offered.reset();
    if (!by_id_[id]) {
      error_ = "final outcome of ray id " + std::to_string(id) + " that is not in flight";
      return;
    }
    report(id);
  }
}

void Engine::report(uint32_t id) {
  const InFlight& f = *by_id_[id];
  classify(bvh_, rays_[f.ray].ray, f.er, opt_.mode, &stats_);
  ++reports_[f.ray];
  by_id_[id].reset();
  free_ids_.push_back(id);
  ++finished_;
  --in_flight_;
}

}  // namespace hrpp::tb
