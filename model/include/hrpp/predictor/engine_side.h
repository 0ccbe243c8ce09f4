// The traversal engine's side of the predictor (docs/predictor.md, "One ray"): what the engine
// does with a prediction, in pieces that a caller strings together at its own pace.
//
//   1. walk the predicted subtrees, nearest hit kept    walk_predicted / walk_predicted_node
//                                                        (or take_predicted, for walks made
//                                                        elsewhere)
//   2. the decision: skip, shrink or full walk          decide (the untimed model's; the RTL
//                                                        makes its own)
//   3. the walks from the root                          walk_from_root (baseline_walk and
//                                                        shrunk_walk apart, to time them)
//   4. the outcome: answer and verified node            finish
//   5. the node the outcome writes to the table         update_node
//   6. the statistics: TP/FP/FN/TN, wasted work, ...    classify
//
// Users: the untimed model (Predictor::process), the testbench's traversal engine (tb/engine.cc),
// which takes its decisions from the DUT, and timed models of the engine. Nothing allocates.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "hrpp/predictor/pred_table.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/trace/ray.h"
#include "hrpp/trace/traverse.h"
#include "hrpp/workload/workload.h"

namespace hrpp {

/// What the engine does once a ray's predicted walks are done (rtl/hrpp_pkg.sv action_e).
enum class Action : uint8_t {
  kFull = 0,    // no predicted hit: the full walk from the root answers
  kShrink = 1,  // closest-exact: the predicted hit bounds the walk from the root (tfar)
  kSkip = 2,    // any-hit or closest-spec: the predicted hit is the answer, no walk from the root
};

/// True when a ray of this kind is answered as an any-hit query in this mode.
inline bool answers_any_hit(RayKind kind, PredictMode mode) {
  return is_any_hit(kind) || mode == PredictMode::kAnyHit;
}

/// Sets the query a ray of `kind` makes in `mode`: er->any (answers_any_hit) and
/// er->asks_closest (the kind wants the closest hit, whatever the mode answers).
struct EngineRay;
inline void set_query(RayKind kind, PredictMode mode, EngineRay* er);

/// The skip rule (rtl/hrpp_skip_ctrl.sv, and the cycle model's twin of it): with a predicted
/// hit, skip (any-hit queries, closest-spec) or shrink (closest-exact); without one, the full
/// walk.
inline Action skip_action(bool predicted_hit, bool any, PredictMode mode) {
  if (!predicted_hit) return Action::kFull;
  return any || mode == PredictMode::kClosestSpec ? Action::kSkip : Action::kShrink;
}

/// One ray's state on the engine's side, from its prediction to its statistics.
struct EngineRay {
  bool any = false;           // answered as an any-hit query (answers_any_hit)
  bool asks_closest = false;  // the ray's kind asks for the closest hit (set_query)
  bool predicted = false;     // the table held nodes for the ray's key
  // Predicted walks (step 1).
  std::array<uint32_t, kMaxNodesPerEntry> nodes{};  // the predicted nodes walked, in order
  uint32_t num_nodes = 0;
  Hit best;                      // nearest hit of the predicted walks
  uint32_t best_node = kNoNode;  // the predicted node whose subtree holds `best`
  Counters pred;                 // work of the predicted walks
  // Walks from the root (step 3).
  Hit baseline;  // the full walk: the reference answer of the statistics
  Counters base;
  Hit shrunk;  // kShrink: the walk from the root bounded by best.t
  Counters shrunk_work;
  // Outcome (step 4).
  Action action = Action::kFull;
  Hit answer;
  bool verified = false;             // the answer was found in a predicted subtree (or accepted)
  uint32_t verified_node = kNoNode;  // that subtree's node (kNoNode: none)
  Counters hrpp;                     // everything HRPP walked: predicted + shrunk or full walk

  /// Records one predicted subtree walk's result (its work already added to `pred`); keeps the
  /// nearest hit. Returns false when the ray needs no further predicted walk (an any-hit query
  /// found a hit).
  bool take_predicted(uint32_t node, const Hit& h) {
    nodes[num_nodes++] = node;
    if (h.hit() && (!best.hit() || h.t < best.t)) {
      best = h;
      best_node = node;
      if (any) return false;
    }
    return true;
  }
};

inline void set_query(RayKind kind, PredictMode mode, EngineRay* er) {
  er->any = answers_any_hit(kind, mode);
  er->asks_closest = !is_any_hit(kind);
}

// The small pieces are inline: the untimed model runs them for every ray (make bench).

/// A walk of the golden traversal from `start`: any hit or closest hit. `path`, if set, receives
/// every visited node in order (timed models replay it through their memory system).
inline Hit engine_walk(const Bvh& bvh, const Ray& ray, bool any, uint32_t start, Counters* c,
                       std::vector<uint32_t>* path = nullptr) {
  const TraceRequest req{.start_node = start, .path = path};
  return any ? any_hit(bvh, ray, c, req) : closest_hit(bvh, ray, c, req);
}

/// Walks the subtree of one predicted node with the golden traversal (closest or any hit) and
/// takes its result (EngineRay::take_predicted, whose answer it returns).
inline bool walk_predicted_node(const Bvh& bvh, const Ray& ray, uint32_t node, EngineRay* er,
                                std::vector<uint32_t>* path = nullptr) {
  return er->take_predicted(node, engine_walk(bvh, ray, er->any, node, &er->pred, path));
}

/// Walks the predicted nodes in order (most recently used first) until an any-hit query finds
/// a hit; sets `predicted` (count > 0).
inline void walk_predicted(const Bvh& bvh, const Ray& ray, const uint32_t* nodes, uint32_t count,
                           EngineRay* er) {
  er->predicted = count > 0;
  for (uint32_t i = 0; i < count; ++i)
    if (!walk_predicted_node(bvh, ray, nodes[i], er)) break;
}

/// The untimed model's decision: with a predicted hit, skip (any-hit queries, closest-spec) or
/// shrink (closest-exact); without one, the full walk.
inline Action decide(const EngineRay& er, PredictMode mode) {
  return skip_action(er.best.hit(), er.any, mode);
}

/// The full walk from the root: `baseline`, `base` (`path`: as engine_walk's).
void baseline_walk(const Bvh& bvh, const Ray& ray, EngineRay* er,
                   std::vector<uint32_t>* path = nullptr);
/// The walk from the root with tfar = best.t: `shrunk`, `shrunk_work`.
void shrunk_walk(const Bvh& bvh, const Ray& ray, EngineRay* er,
                 std::vector<uint32_t>* path = nullptr);
/// The walks from the root for a decision: the baseline walk always (the statistics' reference)
/// and, for kShrink, the shrunk walk, both in one pass when it is a closest-hit walk bounded by
/// a predicted hit (closest_hit_pair: the same hits and counters as two walks).
void walk_from_root(const Bvh& bvh, const Ray& ray, Action action, EngineRay* er);

/// The outcome of a decision, its walks from the root made: `action`, `answer`, `verified`,
/// `verified_node`, `hrpp`. kSkip: the predicted hit, accepted; kShrink: the shrunk walk's hit,
/// else the predicted one, verified when it lies in a predicted subtree (in_subtree); kFull: the
/// baseline's answer.
inline void finish(const Bvh& bvh, Action action, EngineRay* er) {
  er->action = action;
  er->hrpp = er->pred;
  er->verified = false;
  er->verified_node = kNoNode;
  switch (action) {
    case Action::kSkip:  // the predicted hit is accepted
      er->answer = er->best;
      er->verified = true;
      er->verified_node = er->best_node;
      break;
    case Action::kShrink:
      er->hrpp += er->shrunk_work;
      er->answer = er->shrunk.hit() ? er->shrunk : er->best;
      // Verified when the closest hit lies in one of the predicted subtrees.
      for (uint32_t i = 0; i < er->num_nodes; ++i)
        if (in_subtree(bvh, er->nodes[i], er->answer.leaf)) {
          er->verified = true;
          er->verified_node = er->nodes[i];
          break;
        }
      break;
    case Action::kFull:  // the full walk is the baseline walk
      er->hrpp += er->base;
      er->answer = er->baseline;
      break;
  }
}

/// The node the outcome writes to the table: the verified node (its recency refreshed), else the
/// answer's hit leaf's go_up-th ancestor; kNoNode when the ray hit nothing.
inline uint32_t update_node(const Bvh& bvh, const EngineRay& er, uint32_t go_up) {
  if (er.verified_node != kNoNode) return er.verified_node;
  return er.answer.hit() ? bvh.ancestor(er.answer.leaf, go_up) : kNoNode;
}

/// Adds a finished ray to the statistics: rays, baseline and HRPP work, predicted and wasted
/// walks, skipped walks, baseline hits, TP/FP/FN/TN, and answers that differ from the baseline
/// (wrong_results in closest-spec, else exact_mismatches). Table updates and timings are the
/// caller's (it owns the table and the clock).
inline void classify(const Bvh& bvh, const Ray& ray, const EngineRay& er, PredictMode mode,
                     PredictStats* s) {
  s->rays += 1;
  s->baseline += er.base;
  s->baseline_hits += er.baseline.hit();
  s->hrpp += er.hrpp;
  s->predicted += er.pred;
  if (er.predicted && !er.verified) s->wasted += er.pred;
  s->skipped_walks += er.action == Action::kSkip;
  if (er.predicted) {
    (er.verified ? s->true_positive : s->false_positive) += 1;
  } else {
    (er.answer.hit() ? s->false_negative : s->true_negative) += 1;
  }
  if (!er.any) {
    if (!same_answer(bvh, ray, er.answer, er.baseline))
      (mode == PredictMode::kClosestSpec ? s->wrong_results : s->exact_mismatches) += 1;
    return;
  }
  if (er.answer.hit() != er.baseline.hit()) s->exact_mismatches += 1;
  if (er.asks_closest) {
    // A closest-hit ray answered as an any-hit query: its answer is wrong unless it is the
    // closest hit (a walk for the statistics only; its work is counted nowhere).
    Counters unused;
    const Hit closest = engine_walk(bvh, ray, false, 0, &unused);
    s->wrong_results += !same_answer(bvh, ray, er.answer, closest);
    s->baseline_wrong_results += !same_answer(bvh, ray, er.baseline, closest);
  }
}

}  // namespace hrpp
