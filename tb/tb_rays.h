// tb_hrpp's rays (tb/README.md, "What tb_hrpp checks"): the scene and its BVH, and the rays of
// the run: the scene's camera rays and their shadow and AO rays (--scene), a ray-stream file
// (--stream, its scene named by its options), or a stress stream (--stress, tb/stress.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/hardware/rtl_config.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/workload/workload.h"
#include "stress.h"
#include "tb_options.h"

namespace hrpp::tb {

struct TbRays {
  std::string scene_file;  // --scene, or the scene the stream's options name
  Scene scene;
  Bvh bvh;
  std::vector<RayRecord> rays;  // at most --rays, every one valid
  uint64_t invalid = 0;         // invalid rays of the source, not issued
};

/// Loads the scene, builds its BVH and takes up to o.nrays valid rays from the stream or the
/// scene's camera (none with --stress: make_stress_rays gives them). Returns 0, or 2 after
/// printing why (a stream that names no scene or another scene).
int load_rays(const TbOptions& o, TbRays* out);

/// --stress: replaces the rays by a stress stream of the scene keyed with the configuration's
/// hash `cc.hash`, prints what it holds and checks it does what it claims. Returns 0, or 1 after
/// printing FAIL.
int make_stress_rays(const TbOptions& o, const RtlConfig& spec, const CycleConfig& cc,
                     StressKind* kind, TbRays* r);

}  // namespace hrpp::tb
