#include "tb_config.h"

#include <cstdio>
#include <string>

namespace hrpp::tb {

int configure_for_scene(const RtlConfig& spec, PredictMode mode, const Scene& scene, const Bvh& bvh,
                        CycleConfig* cc) {
  *cc = spec.cycle(mode);
  std::string cfg_err =
      resolve_for_scene(scene, bvh, &cc->hash, &cc->table,
                        {.node_bits = spec.node_id_width, .tag_bits = spec.table.tag_bits});
  if (cfg_err.empty()) cfg_err = cc->validate();
  if (!cfg_err.empty()) {
    std::fprintf(stderr, "tb_hrpp: configuration %s: %s\n", spec.name.c_str(), cfg_err.c_str());
    return 2;
  }
  return 0;
}

}  // namespace hrpp::tb
