#include "tb_rays.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "hrpp/workload/ray_stream.h"
#include "hrpp/workload/sampling.h"

namespace hrpp::tb {

int load_rays(const TbOptions& o, TbRays* out) {
  std::vector<RayRecord>& rays = out->rays;
  const std::string& stream_path = o.stream_path;
  const uint64_t nrays = o.nrays;
  std::string scene_file = o.scene_path;
  std::unique_ptr<RayStreamReader> reader;
  if (!stream_path.empty()) {
    reader = std::make_unique<RayStreamReader>(stream_path);
    // The stream's options name its scene.
    const auto opts = nlohmann::json::parse(reader->header().options, nullptr, false);
    if (opts.is_object() && opts.contains("scene") && opts["scene"].is_string())
      scene_file = opts["scene"].get<std::string>();
    if (scene_file.empty()) {
      std::fprintf(stderr, "tb_hrpp: %s does not name its scene\n", stream_path.c_str());
      return 2;
    }
  }
  out->scene_file = scene_file;
  out->scene = load_scene(scene_file);
  out->bvh = build_bvh(out->scene.triangles);
  const Scene& scene = out->scene;
  const Bvh& bvh = out->bvh;
  uint64_t& invalid = out->invalid;
  auto take = [&](const RayRecord& r) {
    if (rays.size() >= nrays) return;
    if (validate_ray(r.ray) != RayError::kNone) {
      ++invalid;  // the engine never issues invalid rays (counted, reported)
      return;
    }
    rays.push_back(r);
  };
  if (reader) {
    if (reader->header().scene_fingerprint != scene_fingerprint(scene)) {
      std::fprintf(stderr, "tb_hrpp: %s was not generated from %s (scene fingerprint differs)\n",
                   stream_path.c_str(), scene_file.c_str());
      return 2;
    }
    RayRecord r;
    while (rays.size() < nrays && reader->next(&r)) take(r);
  } else {
    WorkloadOptions wo;
    resolution_for(scene.camera, std::max<uint64_t>(1, nrays / 2), 1, &wo.width, &wo.height);
    if (o.stress.empty())
      generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit*) { take(r); });
  }
  return 0;
}

int make_stress_rays(const TbOptions& o, const RtlConfig& spec, const CycleConfig& cc,
                     StressKind* kind, TbRays* r) {
  const std::string& stress = o.stress;
  // Synthetic rays of the scene, keyed with the RTL's hash configuration; the stream must do
  // what it claims.
  parse_stress(stress, kind);
  StressStream ss = make_stress_stream(*kind, r->scene, cc.hash, o.nrays, o.seed);
  std::printf(
      "stress %s: %zu rays (%llu distinct), %llu distinct keys in %llu sets; "
      "set %u: %llu rays, %llu keys; longest run of one set %llu rays\n",
      stress.c_str(), ss.rays.size(), (unsigned long long)ss.distinct_rays,
      (unsigned long long)ss.distinct_keys, (unsigned long long)ss.distinct_sets, ss.target_set,
      (unsigned long long)ss.target_set_rays, (unsigned long long)ss.target_set_keys,
      (unsigned long long)ss.longest_set_run);
  const std::string e = check_stress_stream(*kind, ss, spec.table.sets, spec.table.ways);
  if (!e.empty()) {
    std::printf("FAIL: the %s stream is not what it claims: %s\n", stress.c_str(), e.c_str());
    return 1;
  }
  r->rays = std::move(ss.rays);
  return 0;
}

}  // namespace hrpp::tb
