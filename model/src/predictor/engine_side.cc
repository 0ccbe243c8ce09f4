#include "hrpp/predictor/engine_side.h"

namespace hrpp {

void baseline_walk(const Bvh& bvh, const Ray& ray, EngineRay* er, std::vector<uint32_t>* path) {
  er->baseline = engine_walk(bvh, ray, er->any, 0, &er->base, path);
}

void shrunk_walk(const Bvh& bvh, const Ray& ray, EngineRay* er, std::vector<uint32_t>* path) {
  Ray shrunk = ray;
  shrunk.tfar = er->best.t;
  er->shrunk = engine_walk(bvh, shrunk, er->any, 0, &er->shrunk_work, path);
}

void walk_from_root(const Bvh& bvh, const Ray& ray, Action action, EngineRay* er) {
  if (action != Action::kShrink) {
    baseline_walk(bvh, ray, er);
  } else if (!er->any && er->best.hit()) {
    closest_hit_pair(bvh, ray, er->best.t, &er->baseline, &er->base, &er->shrunk, &er->shrunk_work);
  } else {  // not a closest-hit walk bounded by a hit (only a faulty decision asks for it)
    baseline_walk(bvh, ray, er);
    shrunk_walk(bvh, ray, er);
  }
}

}  // namespace hrpp
