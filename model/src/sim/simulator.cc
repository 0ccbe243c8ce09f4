#include "hrpp/sim/simulator.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <queue>
#include <stdexcept>
#include <unordered_map>

#include "hrpp/predictor/engine_side.h"
#include "hrpp/sim/unit_gate.h"

namespace hrpp::sim {

uint64_t triangle_base(const Bvh& bvh) {
  return (uint64_t(bvh.pairs.size()) * kPairBytes + 4095) / 4096 * 4096;
}

PredictStats SimStats::predict_total() const {
  PredictStats t;
  for (const PredictStats& s : predict) t += s;
  return t;
}

namespace {

struct Step {
  uint64_t addr;
  uint32_t bytes;
  uint32_t tests;  // triangle tests (0: a node test)
  uint32_t node;   // the node whose pair or triangles are fetched
};

// kAwaitDecision: an early root walk (SimOptions::early_root) ended before its decision came.
enum class Phase : uint8_t { kEntering, kPredWalk, kDeciding, kRootWalk, kAwaitDecision };

struct Slot {
  uint32_t ray = 0, unit = 0, warp = 0;
  bool uses_pred = false;
  bool decision_owed = false;  // an early root walk runs; the (full-walk) decision is to come
  Phase phase = Phase::kRootWalk;
  Action action = Action::kFull;
  EngineRay er;
  std::vector<Step> steps;
  uint32_t next = 0;
};

struct Warp {
  uint64_t admit = 0;  // entered its unit (repacked: formed)
  uint32_t left = 0;   // rays not yet answered
  uint64_t last = 0;   // the latest answer
};

constexpr uint64_t kMaxIdle = 50'000'000;  // cycles without an answer

struct Event {
  uint64_t time, seq;
  uint32_t slot;
  bool operator>(const Event& o) const { return time != o.time ? time > o.time : seq > o.seq; }
};

class Simulator {
 public:
  Simulator(const Bvh& bvh, const std::vector<RayRecord>& rays, const SimOptions& opt)
      : bvh_(bvh),
        rays_(rays),
        opt_(opt),
        g_(opt.gpu),
        mem_(opt.gpu),
        tri_base_(triangle_base(bvh)) {
    if (bvh.pairs.empty() && !bvh.nodes.empty() && !bvh.nodes[0].is_leaf())
      throw std::runtime_error(
          "the simulator needs the BVH's pair layout (a leaf holds more "
          "than 65535 triangles)");
    for (uint32_t u = 0; u < g_.units; ++u) {
      box_.emplace_back(g_.box);
      tri_.emplace_back(g_.triangle);
    }
    io_.resize(g_.units);
    warps_in_unit_.assign(g_.units, 0);
    repack_.resize(g_.units);
    buffered_.assign(g_.units, 0);
    repack_since_.assign(g_.units, 0);
    if (opt.kind == PredictorKind::kPort) {
      for (uint32_t u = 0; u < g_.units; ++u) {
        std::unique_ptr<PortModel> m;
        if (opt.port_model)
          m = opt.port_model(u);
        else if (opt.cycle.lanes > 1)
          m = std::make_unique<LanesCyclePortModel>(opt.cycle);
        else
          m = std::make_unique<CyclePortModel>(opt.cycle);
        pred_.push_back(std::make_unique<PortPredictor>(rays, std::move(m), opt.cycle.id_bits,
                                                        opt.cycle.table.conf_bits > 0));
      }
    } else if (opt.kind == PredictorKind::kTimed) {
      for (uint32_t u = 0; u < g_.units; ++u)
        pred_.push_back(std::make_unique<TimedPredictor>(bvh, rays, opt.pred, opt.timed));
    }
    slots_.resize(size_t(g_.units) * g_.warps_per_unit * g_.warp_size);
    for (uint32_t i = 0; i < slots_.size(); ++i)
      free_slots_.push_back(uint32_t(slots_.size()) - 1 - i);
  }

  SimStats run();

 private:
  void admit(uint32_t warp, uint32_t unit, uint64_t now);
  void schedule(uint32_t slot, uint64_t t) { events_.push({t, seq_++, slot}); }
  void step(uint32_t slot, uint64_t now);
  void walk_end(uint32_t slot, uint64_t now);
  // The ray's outcome to its unit's predictor (when it used it and did not skip); it finishes.
  void send_outcome(uint32_t slot, uint64_t now);
  void finish_ray(uint32_t slot, uint64_t now);
  void leave_warp(const Slot& s, uint64_t now);
  void form_warps(uint32_t unit, uint64_t now);
  uint32_t warps_held(uint32_t unit) const {
    return warps_in_unit_[unit] + (buffered_[unit] + g_.warp_size - 1) / g_.warp_size;
  }
  void add_walk(Slot& s, uint32_t start, const std::vector<uint32_t>& path, const Hit& hit);
  void on_prediction(uint32_t ray, const Prediction& p, uint64_t now);
  void on_decision(uint32_t ray, Action a, uint64_t now);
  void start_root_walk(Slot& s, Action a);
  uint32_t slot_of(uint32_t ray) const {
    auto it = slot_of_.find(ray);
    if (it == slot_of_.end())
      throw std::runtime_error("the predictor answered ray " + std::to_string(ray) +
                               ", which is not in flight");
    return it->second;
  }

  const Bvh& bvh_;
  const std::vector<RayRecord>& rays_;
  const SimOptions& opt_;
  const GpuConfig& g_;
  MemorySystem mem_;
  uint64_t tri_base_;
  std::vector<IssueSlots> box_, tri_;
  std::vector<UnitIo> io_;
  std::vector<std::unique_ptr<UnitPredictor>> pred_;
  std::vector<uint32_t> warps_in_unit_;
  // Repacking: per unit, the buffers by category (slot, cycle it arrived), and their ray count.
  std::vector<std::map<uint64_t, std::deque<std::pair<uint32_t, uint64_t>>>> repack_;
  std::vector<uint32_t> buffered_;
  std::vector<uint64_t>
      repack_since_;             // the timer's start: first ray buffered, or last warp formed
  std::vector<uint32_t> valid_;  // stream indices of the valid rays, in issue order
  std::vector<Warp> warps_;
  std::vector<Slot> slots_;
  std::vector<uint32_t> free_slots_;
  std::unordered_map<uint32_t, uint32_t> slot_of_;  // ray -> slot
  std::vector<uint64_t> admitted_at_;               // by slot
  std::vector<UnitGate> gate_;                      // SimOptions::gate, by unit
  std::priority_queue<Event, std::vector<Event>, std::greater<>> events_;
  uint64_t seq_ = 0;
  std::vector<uint32_t> path_;
  SimStats st_;
  uint64_t finished_ = 0, in_flight_ = 0;
  bool retired_ = false;  // a warp left its unit in this cycle
};

void Simulator::add_walk(Slot& s, uint32_t start, const std::vector<uint32_t>& path,
                         const Hit& hit) {
  // A walk from a node other than the root first tests the node's own box, which sits in its
  // parent's pair; the root's box is the scene's, held by the unit.
  if (start != 0 && bvh_.parent[start] != kNoNode) {
    s.steps.push_back({uint64_t(bvh_.pair_of[bvh_.parent[start]]) * kPairBytes, kPairBytes, 0,
                       bvh_.parent[start]});
    st_.start_fetches++;
  }
  for (size_t i = 0; i < path.size(); ++i) {
    const BvhNode& n = bvh_.nodes[path[i]];
    if (!n.is_leaf()) {
      s.steps.push_back({uint64_t(bvh_.pair_of[path[i]]) * kPairBytes, kPairBytes, 0, path[i]});
      continue;
    }
    uint32_t tests = n.count;
    // An any-hit walk stops at its hit: the last leaf's triangles up to the hit one.
    if (s.er.any && hit.hit() && i + 1 == path.size())
      for (uint32_t k = 0; k < n.count; ++k)
        if (bvh_.prim_ids[n.right_or_first + k] == hit.prim) {
          tests = k + 1;
          break;
        }
    s.steps.push_back({tri_base_ + uint64_t(n.right_or_first) * kTriangleBytes,
                       tests * kTriangleBytes, tests, path[i]});
  }
}

void Simulator::admit(uint32_t w, uint32_t unit, uint64_t now) {
  warps_in_unit_[unit]++;
  Warp& warp = warps_[w];
  warp.admit = now;
  const size_t first = size_t(w) * g_.warp_size;
  const size_t end = std::min(valid_.size(), first + g_.warp_size);
  warp.left = uint32_t(end - first);
  st_.warps++;
  for (size_t i = first; i < end; ++i) {
    const uint32_t ray = valid_[i];
    const uint32_t si = free_slots_.back();
    free_slots_.pop_back();
    Slot& s = slots_[si];
    const RayRecord& r = rays_[ray];
    s.ray = ray;
    s.unit = unit;
    s.warp = w;
    s.er = EngineRay{};
    s.decision_owed = false;
    set_query(r.kind, opt_.pred.mode, &s.er);
    s.steps.clear();
    s.next = 0;
    s.uses_pred = opt_.kind != PredictorKind::kNone && (!opt_.any_hit_only || s.er.any);
    slot_of_[ray] = si;
    admitted_at_[si] = now;
    ++in_flight_;
    if (s.uses_pred) {
      s.phase = Phase::kEntering;
      io_[unit].entering.push_back(ray);
    } else {
      start_root_walk(s, Action::kFull);
      schedule(si, now);
    }
  }
}

void Simulator::start_root_walk(Slot& s, Action a) {
  const Ray& ray = rays_[s.ray].ray;
  s.phase = Phase::kRootWalk;
  s.action = a;
  s.steps.clear();
  s.next = 0;
  path_.clear();
  switch (a) {
    case Action::kFull:
      baseline_walk(bvh_, ray, &s.er, &path_);
      add_walk(s, 0, path_, s.er.baseline);
      break;
    case Action::kShrink:
      baseline_walk(bvh_, ray, &s.er);
      shrunk_walk(bvh_, ray, &s.er, &path_);
      add_walk(s, 0, path_, s.er.shrunk);
      break;
    case Action::kSkip:  // the predicted hit is the answer; the baseline walk for the statistics
      baseline_walk(bvh_, ray, &s.er);
      break;
  }
}

void Simulator::on_prediction(uint32_t ray, const Prediction& p, uint64_t now) {
  const uint32_t si = slot_of(ray);
  Slot& s = slots_[si];
  if (s.phase != Phase::kEntering)
    throw std::runtime_error("a second prediction for ray " + std::to_string(ray));
  s.phase = Phase::kPredWalk;
  gate_[s.unit].on_lookup();
  s.steps.clear();
  s.next = 0;
  const Ray& r = rays_[ray].ray;
  s.er.predicted = p.count > 0;
  for (uint32_t i = 0; i < p.count; ++i) {
    if (p.nodes[i] >= bvh_.nodes.size())
      throw std::runtime_error("predicted node " + std::to_string(p.nodes[i]) + " outside the BVH");
    path_.clear();
    const bool more = walk_predicted_node(bvh_, r, p.nodes[i], &s.er, &path_);
    // The walk's own hit: the ray's best when this walk found a nearer one.
    const Hit h = s.er.best_node == p.nodes[i] ? s.er.best : Hit{};
    add_walk(s, p.nodes[i], path_, h);
    if (!more) break;
  }
  if (opt_.repack == SimOptions::Repack::kNone) return schedule(si, now + 1);
  // The ray leaves its warp for its category's buffer.
  const uint64_t key = p.count == 0                                    ? 0
                       : opt_.repack == SimOptions::Repack::kPredicted ? 1
                                                                       : uint64_t(p.nodes[0]) + 1;
  leave_warp(s, now);
  if (buffered_[s.unit] == 0) repack_since_[s.unit] = now;  // the timer starts
  repack_[s.unit][key].emplace_back(si, now);
  buffered_[s.unit]++;
}

void Simulator::form_warps(uint32_t unit, uint64_t now) {
  auto& cats = repack_[unit];
  // A new warp of up to warp_size rays taken from the categories in key order (0, not
  // predicted, first, as their `retrieve` takes unpredicted rays before predicted ones).
  auto form = [&](std::deque<std::pair<uint32_t, uint64_t>>* only) {
    const uint32_t w = uint32_t(warps_.size());
    uint32_t n = 0;
    for (auto it = cats.begin(); it != cats.end() && n < g_.warp_size;) {
      auto& q = it->second;
      if (only && &q != only) {
        ++it;
        continue;
      }
      while (!q.empty() && n < g_.warp_size) {
        const uint32_t si = q.front().first;
        q.pop_front();
        slots_[si].warp = w;
        schedule(si, now + 1);
        ++n;
      }
      it = q.empty() ? cats.erase(it) : std::next(it);
    }
    warps_.push_back({now, n, now});
    warps_in_unit_[unit]++;
    st_.warps++;
    st_.repacked_warps++;
    buffered_[unit] -= n;
    repack_since_[unit] = now;  // the timer restarts after every warp formed
  };
  // A category with a warp's worth of rays forms a full warp at once.
  for (bool again = true; again;) {
    again = false;
    for (auto& [key, q] : cats)
      if (q.size() >= g_.warp_size) {
        form(&q);
        again = true;
        break;
      }
  }
  // When the timer expires, one warp of the oldest categories' rays.
  if (buffered_[unit] > 0 && now - repack_since_[unit] >= opt_.repack_timer) form(nullptr);
}

void Simulator::on_decision(uint32_t ray, Action a, uint64_t now) {
  const uint32_t si = slot_of(ray);
  Slot& s = slots_[si];
  if (s.decision_owed) {  // its root walk started at the predicted walks' miss
    if (a != Action::kFull)
      throw std::runtime_error("a skip decision other than the full walk for ray " +
                               std::to_string(ray) + ", whose predicted walks found no hit");
    s.decision_owed = false;
    if (s.phase == Phase::kAwaitDecision) send_outcome(si, now);
    return;
  }
  if (s.phase != Phase::kDeciding)
    throw std::runtime_error("a skip decision for ray " + std::to_string(ray) +
                             " before its predicted-walk result");
  if (a != Action::kFull) st_.predictor.gate_openings += gate_[s.unit].on_predicted_hit();
  start_root_walk(s, a);
  schedule(si, now + 1);
}

void Simulator::step(uint32_t si, uint64_t now) {
  Slot& s = slots_[si];
  if (s.next == s.steps.size()) return walk_end(si, now);
  const Step& st = s.steps[s.next++];
  bool hit;
  const uint64_t ready = mem_.load(s.unit, st.addr, st.bytes, now, &hit);
  uint64_t done;
  if (st.tests == 0) {
    st_.node_fetches++;
    if (bvh_.depth[st.node] < SimStats::kTopLevels) {
      st_.top_fetches++;
      st_.top_hits += hit;
    } else {
      st_.deep_fetches++;
      st_.deep_hits += hit;
    }
    done = box_[s.unit].issue(now, ready, 1);
  } else {
    st_.triangle_fetches += st.tests;
    done = tri_[s.unit].issue(now, ready, st.tests);
  }
  schedule(si, done);
}

void Simulator::walk_end(uint32_t si, uint64_t now) {
  Slot& s = slots_[si];
  if (s.phase == Phase::kPredWalk) {
    s.phase = Phase::kDeciding;
    io_[s.unit].pw.push_back({s.ray, s.er.best.hit(), s.er.best.hit() ? s.er.best_node : 0});
    if (opt_.early_root && !s.er.best.hit()) {  // the decision can only be the full walk
      s.decision_owed = true;
      start_root_walk(s, Action::kFull);
      schedule(si, now + 1);
    }
    return;
  }
  finish(bvh_, s.action, &s.er);
  if (s.decision_owed) {  // the outcome follows the decision (the predictor's order)
    s.phase = Phase::kAwaitDecision;
    return;
  }
  send_outcome(si, now);
}

void Simulator::send_outcome(uint32_t si, uint64_t now) {
  Slot& s = slots_[si];
  if (s.uses_pred && s.action != Action::kSkip) {
    const uint32_t node = update_node(bvh_, s.er, opt_.pred.go_up);
    io_[s.unit].outcomes.push_back({s.ray, s.er.answer.hit(), node != kNoNode ? node : 0});
  }
  finish_ray(si, now);
}

void Simulator::finish_ray(uint32_t si, uint64_t now) {
  Slot& s = slots_[si];
  const RayRecord& r = rays_[s.ray];
  classify(bvh_, r.ray, s.er, opt_.pred.mode, &st_.predict[int(r.kind)]);
  if (opt_.answers) (*opt_.answers)[s.ray] = s.er.answer;
  const uint64_t lat = now - admitted_at_[si];
  st_.latency += lat;
  st_.by_kind[int(r.kind)].rays++;
  st_.by_kind[int(r.kind)].latency += lat;
  leave_warp(s, now);
  slot_of_.erase(s.ray);
  free_slots_.push_back(si);
  --in_flight_;
  ++finished_;
  st_.cycles = std::max(st_.cycles, now);
  if (opt_.progress && (finished_ & 0x3FFF) == 0)
    opt_.progress({finished_, uint64_t(valid_.size()), now});
}

void Simulator::leave_warp(const Slot& s, uint64_t now) {
  Warp& w = warps_[s.warp];
  st_.lane_cycles += now - w.admit;
  w.last = std::max(w.last, now);
  if (--w.left == 0) {
    st_.warp_cycles += uint64_t(g_.warp_size) * (w.last - w.admit);
    warps_in_unit_[s.unit]--;
    retired_ = true;
  }
}

SimStats Simulator::run() {
  for (uint32_t i = 0; i < rays_.size(); ++i) {
    if (validate_ray(rays_[i].ray) != RayError::kNone) {
      st_.invalid_rays++;
      st_.predict[int(rays_[i].kind)].rays++;
      st_.predict[int(rays_[i].kind)].invalid_rays++;
      continue;
    }
    valid_.push_back(i);
  }
  st_.rays = valid_.size();
  if (opt_.answers) opt_.answers->assign(rays_.size(), Hit{});
  admitted_at_.assign(slots_.size(), 0);
  gate_.assign(g_.units, UnitGate(opt_.gate, opt_.gate_first));
  const uint32_t num_warps = uint32_t((valid_.size() + g_.warp_size - 1) / g_.warp_size);
  warps_.resize(num_warps);  // repacking appends the warps it forms
  uint32_t next_warp = 0;
  uint64_t now = 0, idle = 0;
  const bool clocked = !pred_.empty();
  while (finished_ < valid_.size()) {
    // 1. Warps enter units with a free slot, in issue order, units in order.
    for (uint32_t u = 0; u < g_.units; ++u)
      while (warps_held(u) < g_.warps_per_unit && next_warp < num_warps) admit(next_warp++, u, now);
    const uint64_t finished_before = finished_;
    // 2. The steps due now.
    while (!events_.empty() && events_.top().time <= now) {
      const Event e = events_.top();
      events_.pop();
      step(e.slot, now);
    }
    // 3. The predictors' ports.
    for (uint32_t u = 0; u < pred_.size(); ++u) {
      UnitIo& io = io_[u];
      pred_[u]->cycle(now, &io);
      if (const std::string e = pred_[u]->error(); !e.empty())
        throw std::runtime_error("unit " + std::to_string(u) + "'s predictor: " + e);
      // Rays still waiting to enter after entry_timeout cycles (1 while the unit's gate is
      // closed) walk without the predictor (the queue is in admission order, so the oldest is at
      // its front).
      const bool closed = gate_[u].closed();
      st_.predictor.gate_closed_cycles += closed;
      const uint32_t timeout = closed ? 1 : opt_.entry_timeout;
      while (timeout > 0 && !io.entering.empty() &&
             admitted_at_[slot_of(io.entering.front())] + timeout <= now) {
        const uint32_t si = slot_of(io.entering.front());
        io.entering.pop_front();
        Slot& s = slots_[si];
        s.uses_pred = false;
        start_root_walk(s, Action::kFull);
        schedule(si, now + 1);
        st_.predictor.bypassed++;
      }
      for (const auto& [ray, p] : io.predictions) on_prediction(ray, p, now);
      for (const auto& [ray, a] : io.decisions) on_decision(ray, a, now);
      io.predictions.clear();
      io.decisions.clear();
      if (opt_.repack != SimOptions::Repack::kNone) form_warps(u, now);
    }
    // 4. The next cycle: the next one while a predictor is clocked or a warp left (its slot
    // takes a warp next cycle); otherwise the next step's.
    uint64_t next = now + 1;
    if (!clocked && !(retired_ && next_warp < num_warps) && !events_.empty())
      next = std::max(next, events_.top().time);
    retired_ = false;
    st_.in_flight_area += in_flight_ * (next - now);
    // No answer for kMaxIdle cycles, or nothing left that could make progress: a deadlock.
    idle = finished_ != finished_before ? 0 : idle + (next - now);
    if (idle > kMaxIdle ||
        (!clocked && events_.empty() && next_warp == num_warps && finished_ < valid_.size()))
      throw std::runtime_error("the simulation stopped making progress at cycle " +
                               std::to_string(now) + " with " +
                               std::to_string(valid_.size() - finished_) + " rays left");
    now = next;
  }
  // Cycles: the last answer's cycle + 1 (cycles 0 .. last). in_flight_area counted every ray in
  // the units from its admission up to, not including, its answer's cycle.
  st_.cycles = valid_.empty() ? 0 : st_.cycles + 1;
  st_.memory = mem_.stats();
  for (auto& p : pred_) {
    const UnitPredictorStats& ps = p->stats();
    st_.predictor.lookups += ps.lookups;
    st_.predictor.stall_cycles += ps.stall_cycles;
    st_.predictor.updates += ps.updates;
    st_.predictor.demotes += ps.demotes;
    st_.predictor.suppressed_lookups += ps.suppressed_lookups;
    st_.predictor.mismatches += ps.mismatches;
    st_.predictor.entry_wait += ps.entry_wait;
  }
  return st_;
}

}  // namespace

SimStats simulate(const Bvh& bvh, const std::vector<RayRecord>& rays, const SimOptions& opt) {
  if (const std::string e = opt.gpu.validate(); !e.empty())
    throw std::runtime_error("GPU configuration: " + e);
  const auto t0 = std::chrono::steady_clock::now();
  Simulator s(bvh, rays, opt);
  SimStats st = s.run();
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return st;
}

}  // namespace hrpp::sim

namespace hrpp::sim {

nlohmann::json SimStats::to_json(const GpuConfig& g) const {
  const PredictStats p = predict_total();
  auto rate = [](uint64_t a, uint64_t b) { return b ? double(a) / double(b) : 0.0; };
  nlohmann::json kinds = nlohmann::json::object();
  for (int k = 0; k < kNumRayKinds; ++k)
    if (by_kind[k].rays) {
      // The predictor's statistics of the kind (PredictStats::to_json), and its time.
      nlohmann::json v = predict[k].to_json();
      v.erase("baseline_ns");
      v.erase("hrpp_ns");
      // Counted by the unit's predictor, not per kind: "predictor" holds them (demotes,
      // suppressed_lookups).
      v.erase("table_demotes");
      v.erase("suppressed_lookups");
      v["rays"] = by_kind[k].rays;
      v["mean_latency"] = rate(by_kind[k].latency, by_kind[k].rays);
      kinds[std::string(ray_kind_name(RayKind(k)))] = v;
    }
  return {{"rays", rays},
          {"invalid_rays", invalid_rays},
          {"run_seconds", seconds},
          {"rays_per_second", seconds > 0 ? rays / seconds : 0.0},
          {"cycles", cycles},
          {"rays_per_cycle", rate(rays, cycles)},
          {"mean_latency", mean_latency()},
          {"mean_in_flight", mean_in_flight()},
          {"node_fetches", node_fetches},
          {"start_fetches", start_fetches},
          {"triangle_fetches", triangle_fetches},
          {"l1_accesses", memory.l1.accesses},
          {"l1_hit_rate", memory.l1.hit_rate()},
          {"l1_merged", memory.l1.merged},
          {"l1_mshr_wait_cycles", memory.l1.mshr_cycles},
          {"top_levels", kTopLevels},
          {"top_node_fetches", top_fetches},
          {"top_node_l1_hit_rate", rate(top_hits, top_fetches)},
          {"deep_node_fetches", deep_fetches},
          {"deep_node_l1_hit_rate", rate(deep_hits, deep_fetches)},
          {"l1_port_wait_cycles", memory.port_wait_cycles},
          {"l2_accesses", memory.l2.accesses},
          {"l2_hit_rate", memory.l2.hit_rate()},
          {"l2_merged", memory.l2.merged},
          {"dram_bytes", memory.dram_bytes},
          {"warps", warps},
          {"simd_efficiency", simd_efficiency()},
          {"repacked_warps", repacked_warps},
          {"interior_tests", p.hrpp.interior_tests},
          {"tri_tests", p.hrpp.tri_tests},
          {"predictor",
           {{"precision", p.precision()},
            {"recall", p.recall()},
            {"skipped_interior_fraction", p.skipped_interior_fraction()},
            {"lookups", predictor.lookups},
            {"updates", predictor.updates},
            {"demotes", predictor.demotes},
            {"suppressed_lookups", predictor.suppressed_lookups},
            {"stall_cycles", predictor.stall_cycles},
            {"entry_wait_cycles", predictor.entry_wait},
            {"bypassed_rays", predictor.bypassed},
            {"gate_closed_cycles", predictor.gate_closed_cycles},
            {"gate_openings", predictor.gate_openings},
            {"true_positive", p.true_positive},
            {"false_positive", p.false_positive},
            {"false_negative", p.false_negative},
            {"true_negative", p.true_negative}}},
          {"wrong_results", p.wrong_results},
          {"exact_mismatches", p.exact_mismatches},
          {"by_kind", kinds},
          {"units", g.units}};
}

}  // namespace hrpp::sim
