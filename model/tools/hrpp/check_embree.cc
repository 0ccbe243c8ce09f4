// hrpp check-embree: trace the same rays with our BVH and with Embree 3 and compare them.
#include <cstdio>
#include <memory>
#include <string>

#include "common.h"
#include "hrpp/reference/crosscheck.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/trace/ray.h"
#include "hrpp/util/progress.h"
#include "subcommands.h"

namespace hrpp::cli {
namespace {

struct CheckEmbreeArgs {
  std::string scene, json_path;
  uint64_t rays = 100000, seed = 1;
  std::string kind = "all", config = kEmbreeReferenceConfig, bvh = "sah";
};

int cmd_check_embree(const CheckEmbreeArgs& a) {
  const std::string& json_path = a.json_path;
  if (!json_path.empty() &&
      !check_output_path("check-embree", "--json", json_path, OutputKind::kJson))
    return 2;
  Scene s = load_scene(a.scene);
  Bvh bvh = build_bvh(s.triangles, bvh_build_options(a.bvh));
  const std::string& kind = a.kind;
  CrossCheckOptions opt;
  opt.rays = a.rays;
  opt.seed = a.seed;
  opt.embree_config = a.config;
  if (kind != "all") {
    RayKind k;
    parse_ray_kind(kind, &k);  // validated by CLI11
    opt.kinds = {k};
  }
  std::unique_ptr<Progress> progress;
  opt.progress = [&](uint64_t done, uint64_t total) {
    if (!progress)
      progress = std::make_unique<Progress>(stderr, "check-embree", "camera samples", total);
    progress->update(done);
  };
  CrossCheckResult r = cross_check(s, bvh, opt);
  progress.reset();
  std::printf("check-embree %s: %s\n", s.path.c_str(), r.embree.c_str());
  std::printf("%s", bvh_line(bvh).c_str());
  std::printf("  %dx%d camera samples, %.2f s\n", r.width, r.height, r.seconds);
  std::printf("  %-8s %9s %8s %8s %9s %13s %8s %7s %6s %6s %6s\n", "kind", "rays", "invalid",
              "no-embr", "hits", "hit-agreement", "hit-mis", "grazes", "t-mis", "p-mis", "ties");
  auto row = [](const char* name, const CrossCheckCounts& c) {
    std::printf("  %-8s %9llu %8llu %8llu %9llu %13.7f %8llu %7llu %6llu %6llu %6llu\n", name,
                (unsigned long long)c.rays, (unsigned long long)c.invalid_rays,
                (unsigned long long)c.outside_embree, (unsigned long long)c.hits, c.hit_agreement(),
                (unsigned long long)c.hit_mismatches, (unsigned long long)c.grazes,
                (unsigned long long)c.t_mismatches, (unsigned long long)c.prim_mismatches,
                (unsigned long long)c.ties);
  };
  for (int k = 0; k < kNumRayKinds; ++k)
    if (r.by_kind[k].rays) row(std::string(ray_kind_name(RayKind(k))).c_str(), r.by_kind[k]);
  row("all", r.total);
  for (const auto& e : r.examples) std::printf("  %s\n", e.c_str());
  std::printf(
      "  (no-embr: valid rays outside Embree's range, never sent to it; a check must "
      "compare at least %g%% of the rays and at least one)\n",
      100 * kMinComparedFraction);
  if (r.passed()) {
    std::printf("  PASS: our traversal agrees with Embree\n");
  } else {
    std::printf("  FAIL: %s\n", r.failure().c_str());
    std::fprintf(stderr, "hrpp check-embree: FAIL: %s\n", r.failure().c_str());
  }
  if (!json_path.empty()) {
    nlohmann::json j = {{"tool", tool_json()}};
    j.update(r.to_json());
    j["bvh"] = bvh_json(bvh);
    if (!write_json_file(json_path, j)) return 2;
  }
  return r.passed() ? 0 : 1;
}

}  // namespace

Subcommand add_check_embree(CLI::App& app) {
  auto a = std::make_shared<CheckEmbreeArgs>();
  auto* ce = app.add_subcommand(
      "check-embree", "Trace the same rays with our BVH and with Embree 3 and compare them");
  ce->add_option("scene", a->scene, "glTF scene (.glb or .gltf)")->required();
  ce->add_option("--rays", a->rays, "number of camera samples (shadow and AO rays come on top)")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 32));
  ce->add_option("--kind", a->kind, "ray kinds to compare")
      ->check(CLI::IsMember({"primary", "shadow", "ao", "all"}));
  ce->add_option("--seed", a->seed, "random seed of the ray generator");
  ce->add_option("--embree-config", a->config, "Embree device configuration string");
  add_bvh_option(ce, a->bvh);
  ce->add_option("--json", a->json_path,
                 "write the results as JSON to this file ('-': to standard output, the text report "
                 "then to standard error)");
  return {ce, [a] { return cmd_check_embree(*a); }};
}

}  // namespace hrpp::cli
