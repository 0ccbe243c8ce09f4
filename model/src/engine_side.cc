#include "hrpp/engine_side.h"

namespace hrpp {

namespace {

Hit walk(const Bvh& bvh, const Ray& ray, bool any, uint32_t start, Counters* c) {
  return any ? any_hit(bvh, ray, c, {.start_node = start})
             : closest_hit(bvh, ray, c, {.start_node = start});
}

}  // namespace

bool walk_predicted_node(const Bvh& bvh, const Ray& ray, uint32_t node, EngineRay* er) {
  return er->take_predicted(node, walk(bvh, ray, er->any, node, &er->pred));
}

void walk_predicted(const Bvh& bvh, const Ray& ray, const uint32_t* nodes, uint32_t count,
                    EngineRay* er) {
  er->predicted = count > 0;
  for (uint32_t i = 0; i < count; ++i)
    if (!walk_predicted_node(bvh, ray, nodes[i], er)) break;
}

void baseline_walk(const Bvh& bvh, const Ray& ray, EngineRay* er) {
  er->baseline = walk(bvh, ray, er->any, 0, &er->base);
}

void shrunk_walk(const Bvh& bvh, const Ray& ray, EngineRay* er) {
  Ray shrunk = ray;
  shrunk.tfar = er->best.t;
  er->shrunk = walk(bvh, shrunk, er->any, 0, &er->shrunk_work);
}

void walk_from_root(const Bvh& bvh, const Ray& ray, Action action, EngineRay* er) {
  if (action != Action::kShrink) {
    baseline_walk(bvh, ray, er);
  } else if (!er->any && er->best.hit()) {
    closest_hit_pair(bvh, ray, er->best.t, &er->baseline, &er->base, &er->shrunk,
                     &er->shrunk_work);
  } else {  // not a closest-hit walk bounded by a hit (only a faulty decision asks for it)
    baseline_walk(bvh, ray, er);
    shrunk_walk(bvh, ray, er);
  }
}

void finish(const Bvh& bvh, Action action, EngineRay* er) {
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

void classify(const Bvh& bvh, const Ray& ray, const EngineRay& er, PredictMode mode,
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
  } else if (er.answer.hit() != er.baseline.hit()) {
    s->exact_mismatches += 1;
  }
}

}  // namespace hrpp
