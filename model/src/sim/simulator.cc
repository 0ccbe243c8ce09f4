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

const char* LossTally::name(Class c) {
  static const char* const kNames[kNumClasses] = {"captured", "aliased",     "compulsory",
                                                  "evicted",  "stale",       "suppressed",
                                                  "gated",    "not_offered", "unknown"};
  return kNames[c];
}

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
  bool offered = false;        // its kind uses the predictor (uses_pred at admission)
  bool bypassed = false;       // gave up entering: walked without the predictor
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
  // Repack::kMicro21: an admitted warp waits in the predictor until released; `pending`: its
  // rays not yet given a prediction; `parked`: the slots of the rays it keeps (no prediction).
  bool released = true;
  uint32_t pending = 0;
  std::vector<uint32_t> parked;
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
    originals_.assign(g_.units, 0);
    walking_.assign(g_.units, 0);
    waiting_.resize(g_.units);
    if (g_.rt.leaf_end_bytes) {  // leaves in triangle order, for their terminators' addresses
      std::vector<uint32_t> leaves;
      for (uint32_t i = 0; i < bvh.nodes.size(); ++i)
        if (bvh.nodes[i].is_leaf()) leaves.push_back(i);
      std::sort(leaves.begin(), leaves.end(), [&](uint32_t a, uint32_t b) {
        return bvh.nodes[a].right_or_first < bvh.nodes[b].right_or_first;
      });
      leaf_rank_.assign(bvh.nodes.size(), 0);
      for (uint32_t r = 0; r < leaves.size(); ++r) leaf_rank_[leaves[r]] = r;
    }
    if (opt.replay && opt.kind != PredictorKind::kTimed)
      throw std::runtime_error("replay needs the golden predictor (PredictorKind::kTimed)");
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
  void tally_loss(const Slot& s);
  void leave_warp(const Slot& s, uint64_t now);
  // A repacking buffer: its rays' slots and the cycles they arrived.
  using Buffer = std::deque<std::pair<uint32_t, uint64_t>>;
  void form_warps(uint32_t unit, uint64_t now);
  // One warp of the unit's buffered rays (only that buffer's, when set).
  void form_warp(uint32_t unit, uint64_t now, const Buffer* only);
  void release_micro21(uint32_t unit, uint64_t now);
  void retire(uint32_t warp, uint32_t unit, uint64_t now);
  bool micro21() const { return opt_.repack == SimOptions::Repack::kMicro21; }
  uint32_t warps_held(uint32_t unit) const {
    if (micro21()) return originals_[unit];
    return warps_in_unit_[unit] + (buffered_[unit] + g_.warp_size - 1) / g_.warp_size;
  }
  // A leaf's first triangle record in memory.
  uint64_t leaf_addr(uint32_t node) const {
    return tri_base_ + uint64_t(bvh_.nodes[node].right_or_first) * tri_bytes_ +
           (leaf_rank_.empty() ? 0 : uint64_t(leaf_rank_[node]) * g_.rt.leaf_end_bytes);
  }
  uint64_t load(uint32_t unit, uint64_t addr, uint32_t bytes, uint64_t now, bool* hit) {
    if (!g_.rt.request_bytes) return mem_.load(unit, addr, bytes, now, hit);
    return mem_.load(unit, addr & ~uint64_t(g_.rt.request_bytes - 1), g_.rt.request_bytes, now,
                     hit);
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
  uint32_t tri_bytes_ = g_.rt.triangle_bytes ? g_.rt.triangle_bytes : kTriangleBytes;
  std::vector<uint32_t> leaf_rank_;  // by leaf node: leaves before it (rt.leaf_end_bytes)
  std::vector<IssueSlots> box_, tri_;
  std::vector<UnitIo> io_;
  std::vector<std::unique_ptr<UnitPredictor>> pred_;
  std::vector<uint32_t> warps_in_unit_;
  // Repack::kMicro21, per unit: admitted warps not retired, released warps walking (pool warps
  // included), the warps waiting in the predictor (admission order). Its pool is the buffer of
  // category 1 (repack_, buffered_).
  std::vector<uint32_t> originals_, walking_;
  std::vector<std::deque<uint32_t>> waiting_;
  uint32_t num_original_ = 0;          // warps_[0, num_original_) are the admitted ones
  uint64_t last_original_retire_ = 0;  // SimOptions::count_original_warps
  // replay: the rays owed a decision: the action their predicted walk settled, and their unit.
  std::unordered_map<uint32_t, std::pair<Action, uint32_t>> replay_owed_;
  // Repacking: per unit, the buffers by category (slot, cycle it arrived), and their ray count.
  std::vector<std::map<uint64_t, Buffer>> repack_;
  std::vector<uint32_t> buffered_;
  std::vector<uint64_t>
      repack_since_;             // the timer's start: first ray buffered, or last warp formed
  std::vector<uint32_t> valid_;  // stream indices of the valid rays, in issue order
  std::vector<Warp> warps_;
  std::vector<size_t> warp_first_;  // admitted warp w: valid_[warp_first_[w], warp_first_[w + 1])
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
  if (start != 0 && bvh_.parent[start] != kNoNode && !opt_.replay) {
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
    if (g_.rt.triangle_records)  // one fetch and one test per triangle record
      for (uint32_t k = 0; k < tests; ++k)
        s.steps.push_back({leaf_addr(path[i]) + uint64_t(k) * tri_bytes_, tri_bytes_, 1, path[i]});
    else
      s.steps.push_back({leaf_addr(path[i]), tests * tri_bytes_, tests, path[i]});
  }
}

void Simulator::admit(uint32_t w, uint32_t unit, uint64_t now) {
  warps_in_unit_[unit]++;
  Warp& warp = warps_[w];
  warp.admit = now;
  const size_t first = warp_first_[w];
  const size_t end = warp_first_[w + 1];
  warp.left = uint32_t(end - first);
  st_.warps++;
  if (micro21()) {
    // The warp waits in the predictor; a warp entering an empty one starts its timer.
    if (waiting_[unit].empty() && buffered_[unit] == 0) repack_since_[unit] = now;
    waiting_[unit].push_back(w);
    originals_[unit]++;
    warp.released = false;
  }
  for (size_t i = first; i < end; ++i) {
    const uint32_t ray = valid_[i];
    // Repack::kMicro21: a unit holds its admitted warps' rays and its pool's, which has no bound
    // (theirs has none either).
    if (free_slots_.empty()) {
      free_slots_.push_back(uint32_t(slots_.size()));
      slots_.emplace_back();
      admitted_at_.push_back(0);
    }
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
    s.offered = s.uses_pred;
    s.bypassed = false;
    slot_of_[ray] = si;
    admitted_at_[si] = now;
    ++in_flight_;
    if (s.uses_pred) {
      s.phase = Phase::kEntering;
      io_[unit].entering.push_back(ray);
      warp.pending++;
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
  if (micro21()) {  // a ray given no prediction stays in its warp, which waits
    Warp& w = warps_[s.warp];
    w.pending--;
    if (p.count == 0) return w.parked.push_back(si);
  }
  // The ray leaves its warp for its category's buffer.
  const uint64_t key = p.count == 0                               ? 0
                       : opt_.repack == SimOptions::Repack::kNode ? uint64_t(p.nodes[0]) + 1
                                                                  : 1;
  leave_warp(s, now);
  st_.pooled_rays++;
  // The timer starts (kMicro21: when a warp enters an empty predictor, admit).
  if (buffered_[s.unit] == 0 && !micro21()) repack_since_[s.unit] = now;
  repack_[s.unit][key].emplace_back(si, now);
  buffered_[s.unit]++;
}

void Simulator::release_micro21(uint32_t unit, uint64_t now) {
  const uint32_t pooled = buffered_[unit];
  std::deque<uint32_t>& waiting = waiting_[unit];
  if ((waiting.empty() && pooled == 0) || walking_[unit] >= g_.warps_per_unit) return;
  const bool expired = now - repack_since_[unit] >= opt_.repack_timer;
  const bool full = pooled > g_.warp_size || (expired && pooled == g_.warp_size);
  // The pool's last rays go when no warp waits (theirs never go) or when the oldest waiting
  // warp still has rays waiting to enter (they may wait for credits the pool's rays hold).
  const bool rest =
      expired && pooled > 0 && (waiting.empty() || warps_[waiting.front()].pending > 0);
  if (full || rest) return form_warp(unit, now, nullptr);  // a warp of pooled rays
  if (!expired || warps_[waiting.front()].pending > 0) return;
  // The oldest waiting warp goes on with the rays it kept.
  const uint32_t w = waiting.front();
  waiting.pop_front();
  Warp& warp = warps_[w];
  warp.released = true;
  walking_[unit]++;
  for (const uint32_t si : warp.parked) schedule(si, now + 1);
  warp.parked.clear();
  repack_since_[unit] = now;
  if (warp.left == 0) retire(w, unit, now);  // every ray left for the pool
}

void Simulator::form_warp(uint32_t unit, uint64_t now, const Buffer* only) {
  // A new warp of up to warp_size rays taken from the categories in key order (0, not
  // predicted, first, as their `retrieve` takes unpredicted rays before predicted ones).
  auto& cats = repack_[unit];
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
  Warp formed;
  formed.admit = formed.last = now;
  formed.left = n;
  warps_.push_back(formed);
  warps_in_unit_[unit]++;
  if (micro21()) walking_[unit]++;
  st_.warps++;
  st_.repacked_warps++;
  buffered_[unit] -= n;
  repack_since_[unit] = now;  // the timer restarts after every warp formed
}

void Simulator::form_warps(uint32_t unit, uint64_t now) {
  if (micro21()) return release_micro21(unit, now);
  // A category with a warp's worth of rays forms a full warp at once.
  for (bool again = true; again;) {
    again = false;
    for (auto& [key, q] : repack_[unit])
      if (q.size() >= g_.warp_size) {
        form_warp(unit, now, &q);
        again = true;
        break;
      }
  }
  // When the timer expires, one warp of the oldest categories' rays.
  if (buffered_[unit] > 0 && now - repack_since_[unit] >= opt_.repack_timer)
    form_warp(unit, now, nullptr);
}

void Simulator::on_decision(uint32_t ray, Action a, uint64_t now) {
  if (const auto it = replay_owed_.find(ray); it != replay_owed_.end()) {
    if (it->second.first != a)
      throw std::runtime_error("replay: the predictor's decision for ray " + std::to_string(ray) +
                               " differs from the predicted walk's result");
    if (a != Action::kFull)
      st_.predictor.gate_openings += gate_[it->second.second].on_predicted_hit();
    replay_owed_.erase(it);
    return;
  }
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
  bool hit = true;
  uint64_t ready = now;
  if (st.tests > 1 && g_.rt.request_bytes) {  // one request per triangle record of the leaf
    for (uint32_t k = 0; k < st.tests; ++k) {
      bool h;
      ready =
          std::max(ready, load(s.unit, st.addr + uint64_t(k) * tri_bytes_, tri_bytes_, now, &h));
      hit = hit && h;
    }
  } else {
    ready = load(s.unit, st.addr, st.bytes, now, &hit);
  }
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
    if (opt_.replay) {  // the fetch list goes on at once; the decision must agree when it comes
      const Action a = skip_action(s.er.best.hit(), s.er.any, opt_.pred.mode);
      replay_owed_[s.ray] = {a, s.unit};
      start_root_walk(s, a);
      return a == Action::kSkip ? walk_end(si, now) : step(si, now);
    }
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
  if (opt_.kind != PredictorKind::kNone && !opt_.timed.oracle) tally_loss(s);
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

void Simulator::tally_loss(const Slot& s) {
  LossTally& t = st_.loss;
  const EngineRay& er = s.er;
  const LookupClass lc =
      s.offered && !s.bypassed ? pred_[s.unit]->take_class(s.ray) : LookupClass::kUnknown;
  if (er.predicted && !er.verified) {
    t.wrong_rays++;
    t.wrong_tests += er.pred.interior_tests;
  }
  if (er.verified) t.right_tests += er.pred.interior_tests;
  if (!er.baseline.hit()) return;
  LossTally::Class c = LossTally::kUnknown;
  if (!s.offered)
    c = LossTally::kNotOffered;
  else if (s.bypassed)
    c = LossTally::kGated;
  else if (er.predicted)
    c = er.verified ? LossTally::kCaptured : LossTally::kAliased;
  else if (lc == LookupClass::kCompulsory)
    c = LossTally::kCompulsory;
  else if (lc == LookupClass::kEvicted)
    c = LossTally::kEvicted;
  else if (lc == LookupClass::kStale)
    c = LossTally::kStale;
  else if (lc == LookupClass::kSuppressed)
    c = LossTally::kSuppressed;
  t.rays[c]++;
  t.tests[c] += er.base.interior_tests;
}

void Simulator::leave_warp(const Slot& s, uint64_t now) {
  Warp& w = warps_[s.warp];
  st_.lane_cycles += now - w.admit;
  w.last = std::max(w.last, now);
  if (--w.left == 0 && w.released) retire(s.warp, s.unit, now);
}

void Simulator::retire(uint32_t wi, uint32_t unit, uint64_t now) {
  Warp& w = warps_[wi];
  w.last = std::max(w.last, now);
  st_.warp_cycles += uint64_t(g_.warp_size) * (w.last - w.admit);
  warps_in_unit_[unit]--;
  retired_ = true;
  if (wi < num_original_) last_original_retire_ = std::max(last_original_retire_, now);
  if (micro21()) {
    walking_[unit]--;
    if (wi < num_original_) originals_[unit]--;
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
  // The warps: the warm-up kernel's rays, then the others, warp_size at a time.
  size_t warm = 0;
  while (warm < valid_.size() && valid_[warm] < opt_.warmup_rays) ++warm;
  for (size_t i = 0; i < warm; i += g_.warp_size) warp_first_.push_back(i);
  const uint32_t warm_warps = uint32_t(warp_first_.size());
  for (size_t i = warm; i < valid_.size(); i += g_.warp_size) warp_first_.push_back(i);
  const uint32_t num_warps = uint32_t(warp_first_.size());
  warp_first_.push_back(valid_.size());
  warps_.resize(num_warps);  // repacking appends the warps it forms
  num_original_ = num_warps;
  uint64_t start = 0;  // the measured kernel's first cycle
  uint32_t next_warp = 0;
  uint64_t now = 0, idle = 0;
  const bool clocked = !pred_.empty();
  while (finished_ < valid_.size()) {
    // 1. Warps enter units with a free slot, in issue order, units in order.
    for (uint32_t u = 0; u < g_.units; ++u)
      while (warps_held(u) < g_.warps_per_unit && next_warp < num_warps &&
             (next_warp != warm_warps || finished_ >= warm)) {
        if (next_warp == warm_warps) start = now;  // the measured kernel begins
        admit(next_warp++, u, now);
      }
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
        s.bypassed = true;
        if (micro21()) warps_[s.warp].pending--;  // it walks at once, as its warp waits
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
  if (opt_.count_original_warps) st_.cycles = last_original_retire_;
  st_.cycles = valid_.empty() ? 0 : st_.cycles + 1 - start + g_.rt.launch_latency;
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
