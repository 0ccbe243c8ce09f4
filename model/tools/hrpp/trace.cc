// hrpp trace: generate a scene's ray workload and write it as a ray-stream file.
#include <array>
#include <chrono>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "common.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/util/progress.h"
#include "hrpp/workload/ray_stream.h"
#include "hrpp/workload/workload.h"
#include "subcommands.h"

namespace hrpp::cli {
namespace {

struct TraceArgs {
  std::string scene, out, json_path, bvh = "sah";
  WorkloadArgs w;
};

int cmd_trace(const TraceArgs& a) {
  if (!check_workload_args("trace", a.w) ||
      !check_output_path("trace", "--out", a.out, OutputKind::kFile) ||
      (!a.json_path.empty() &&
       !check_output_path("trace", "--json", a.json_path, OutputKind::kJson)))
    return 2;
  Scene scene = load_scene(a.scene);
  Bvh bvh = build_bvh(scene.triangles, bvh_build_options(a.bvh));
  WorkloadOptions wo;
  if (!make_workload("trace", a.w, scene, &wo)) return 2;
  nlohmann::json options = workload_json(scene, wo);
  options["effects_spec"] = a.w.effects;
  options["generator"] = "hrpp trace";
  options["bvh"] = bvh_builder_name(bvh.options.builder);  // the hits that spawn secondary rays
  StreamHeader header;
  header.scene_fingerprint = scene_fingerprint(scene);
  header.options = options.dump();
  std::printf("trace %s: %s\n", scene.path.c_str(), workload_line(wo).c_str());
  print_effects(scene, wo, a.w.effects);
  std::printf("%s", bvh_line(bvh).c_str());

  auto t0 = std::chrono::steady_clock::now();
  RayStreamWriter writer(a.out, header);
  std::array<uint64_t, kNumRayKinds> by_kind{};
  Progress progress(stderr, "trace", "camera samples", uint64_t(wo.width) * wo.height * wo.spp, t0);
  uint64_t samples = 0;
  generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit*) {
    writer.write(r);
    by_kind[static_cast<int>(r.kind)]++;
    if (r.kind == RayKind::kPrimary && (++samples & 0xFFF) == 0) progress.update(samples);
  });
  progress.finish();
  writer.close();
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::string counts;
  nlohmann::json jk = nlohmann::json::object();
  for (int k = 0; k < kNumRayKinds; ++k)
    if (by_kind[k]) {
      const std::string name(ray_kind_name(RayKind(k)));
      counts += (counts.empty() ? "" : ", ") + name + " " + std::to_string(by_kind[k]);
      jk[name] = by_kind[k];
    }
  std::printf("wrote %s: %llu rays (%s), %.1f MB, %.1f s\n", a.out.c_str(),
              (unsigned long long)writer.count(), counts.c_str(), (64.0 * writer.count()) / 1e6,
              secs);
  if (!a.json_path.empty()) {
    nlohmann::json j = {{"stream", a.out},
                        {"scene", scene.path},
                        {"scene_fingerprint", header.scene_fingerprint},
                        {"options", options},
                        {"effects", describe_effects(scene, wo, a.w.effects)},
                        {"bvh", bvh_json(bvh)},
                        {"rays", writer.count()},
                        {"by_kind", jk},
                        {"seconds", secs}};
    j["tool"] = tool_json();
    if (!write_json_file(a.json_path, j)) return 2;
  }
  return 0;
}

}  // namespace

Subcommand add_trace(CLI::App& app) {
  auto ta = std::make_shared<TraceArgs>();
  auto* tr = app.add_subcommand("trace",
                                "Generate a scene's ray workload and write it as a "
                                "ray-stream file (docs/ray_stream.md)");
  tr->add_option("scene", ta->scene, "glTF scene (.glb or .gltf)")->required();
  add_workload_options(tr, ta->w, "auto");
  add_bvh_option(tr, ta->bvh);
  tr->add_option("--out", ta->out, "ray-stream file to write")->required();
  tr->add_option("--json", ta->json_path,
                 "also write a summary (effects, ray counts) as JSON ('-': to standard output, the "
                 "text report then to standard error)");
  return {tr, [ta] { return cmd_trace(*ta); }};
}

}  // namespace hrpp::cli
