#include "tb_config.h"

#include <cstdio>
#include <string>

namespace hrpp::tb {

int configure_for_scene(const RtlConfig& spec, PredictMode mode, const Scene& scene, const Bvh& bvh,
                        CycleConfig* cc) {
  const std::string err = spec.cycle_for_scene(mode, scene, bvh, cc);
  if (err.empty()) return 0;
  std::fprintf(stderr, "tb_hrpp: configuration %s: %s\n", spec.name.c_str(), err.c_str());
  return 2;
}

}  // namespace hrpp::tb
