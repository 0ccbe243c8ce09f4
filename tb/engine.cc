#include "engine.h"

#include <algorithm>
#include <bit>
#include <string>

namespace hrpp::tb {

Engine::Engine(const Bvh& bvh, const std::vector<RayRecord>& rays, const EngineOptions& opt)
    : bvh_(bvh), rays_(rays), opt_(opt), rng_(opt.seed) {
  for (uint32_t i = 0; i < (1u << opt.id_bits); ++i) free_ids_.push_back(i);
  by_id_.resize(size_t{1} << opt.id_bits);
}

void Engine::drive(uint64_t cycle, DutIn* in) {
  *in = DutIn{};
  const bool stalled = opt_.stall_every && cycle % opt_.stall_every < opt_.stall_length;
  // Rays: once offered, a ray stays offered (same id and fields) until accepted.
  if (!offered_ray_ && next_ray_ < rays_.size() && !free_ids_.empty() && chance(opt_.p_ray)) {
    offered_ray_ = {free_ids_.front(), next_ray_++};
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
  in->pred_ready = !stalled && chance(opt_.p_pred_ready);
  in->skip_ready = !stalled && chance(opt_.p_skip_ready);
  // Outcomes: the earliest pending message whose latency has passed, held until accepted.
  for (Port* p : {&pw_, &upd_})
    if (!p->offered && !p->pending.empty() && p->pending.front().ready_cycle <= cycle) {
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
    in->upd_valid = true;
    in->upd_id = upd_.offered->id;
    in->upd_hit = upd_.offered->hit;
    in->upd_node = upd_.offered->node;
  }
}

void Engine::observe(uint64_t cycle, const DutIn& in, const DutOut& out) {
  auto schedule = [&](Port* port, uint32_t id, bool hit, uint32_t node) {
    const Message m{cycle + latency(), id, hit, node};
    auto pos = std::upper_bound(port->pending.begin(), port->pending.end(), m.ready_cycle,
                                [](uint64_t c, const Message& x) { return c < x.ready_cycle; });
    port->pending.insert(pos, m);
  };
  auto walk = [&](const InFlight& f, const Ray& r, uint32_t start, Counters* c) {
    return f.any ? any_hit(bvh_, r, c, {.start_node = start})
                 : closest_hit(bvh_, r, c, {.start_node = start});
  };

  if (in.ray_valid && out.ray_ready) {
    const auto [id, ray] = *offered_ray_;
    offered_ray_.reset();
    InFlight f;
    f.ray = ray;
    f.any = is_any_hit(rays_[ray].kind) || opt_.mode == PredictMode::kAnyHit;
    f.baseline = walk(f, rays_[ray].ray, 0, &f.base);
    by_id_[id] = std::move(f);
  }

  if (out.pred_valid && in.pred_ready) {
    if (!by_id_[out.pred_id]) {
      error_ = "prediction for ray id " + std::to_string(out.pred_id) + " that is not in flight";
      return;
    }
    InFlight& f = *by_id_[out.pred_id];
    const Ray& r = rays_[f.ray].ray;
    f.predicted = out.pred_count > 0;
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
      f.nodes[f.num_nodes++] = node;
      const Hit h = walk(f, r, node, &f.pred);
      if (h.hit() && (!f.best.hit() || h.t < f.best.t)) {
        f.best = h;
        f.best_node = node;
        if (f.any) break;
      }
    }
    f.hrpp = f.pred;
    schedule(&pw_, out.pred_id, f.best.hit(), f.best.hit() ? f.best_node : 0);
  }

  if (out.skip_valid && in.skip_ready) {
    const uint32_t id = out.skip_id;
    if (!by_id_[id]) {
      error_ = "skip decision for ray id " + std::to_string(id) + " that is not in flight";
      return;
    }
    InFlight& f = *by_id_[id];
    const Ray& r = rays_[f.ray].ray;
    if (out.skip_action == Action::kSkip) {
      finish(id, f.best, true, true);
    } else {
      Hit answer;
      uint32_t verified = kNoNode;
      if (out.skip_action == Action::kShrink) {
        Ray shrunk = r;
        shrunk.tfar = f.best.t;
        const Hit h = walk(f, shrunk, 0, &f.hrpp);
        answer = h.hit() ? h : f.best;
        for (uint32_t i = 0; i < f.num_nodes; ++i)
          if (in_subtree(bvh_, f.nodes[i], answer.leaf)) {
            verified = f.nodes[i];
            break;
          }
      } else {
        answer = f.baseline;
        f.hrpp += f.base;
      }
      const uint32_t node = verified != kNoNode ? verified
                            : answer.hit()      ? bvh_.ancestor(answer.leaf, opt_.go_up)
                                                : 0;
      f.best = answer;
      f.best_node = verified;
      schedule(&upd_, id, answer.hit(), node);
    }
  }

  if (in.pw_valid && out.pw_ready) pw_.offered.reset();
  if (in.upd_valid && out.upd_ready) {
    const uint32_t id = upd_.offered->id;
    upd_.offered.reset();
    finish(id, by_id_[id]->best, by_id_[id]->best_node != kNoNode, false);
  }
}

void Engine::finish(uint32_t id, const Hit& answer, bool verified, bool skipped) {
  const InFlight& f = *by_id_[id];
  const RayRecord& rec = rays_[f.ray];
  PredictStats s;
  s.rays = 1;
  s.baseline = f.base;
  s.hrpp = f.hrpp;
  s.predicted = f.pred;
  if (f.predicted && !verified) s.wasted = f.pred;
  s.baseline_hits = f.baseline.hit();
  s.skipped_walks = skipped;
  if (f.predicted) {
    (verified ? s.true_positive : s.false_positive) = 1;
  } else {
    (answer.hit() ? s.false_negative : s.true_negative) = 1;
  }
  if (!f.any) {
    if (!same_answer(bvh_, rec.ray, answer, f.baseline))
      (opt_.mode == PredictMode::kClosestSpec ? s.wrong_results : s.exact_mismatches) = 1;
  } else if (answer.hit() != f.baseline.hit()) {
    s.exact_mismatches = 1;
  }
  stats_ += s;
  by_id_[id].reset();
  free_ids_.push_back(id);
  ++finished_;
}

}  // namespace hrpp::tb
