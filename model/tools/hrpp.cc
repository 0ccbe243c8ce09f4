// hrpp: the project's command-line tool. `hrpp --help` and `hrpp SUBCOMMAND --help` list options.
//
// Exit codes: 0 success; 1 a check failed (e.g. check-embree found mismatches); 2 bad input
// (bad option, unreadable or malformed scene).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "hrpp/bvh.h"
#include "hrpp/crosscheck.h"
#include "hrpp/scene.h"

namespace {

using namespace hrpp;

void print_vec(const char* label, const Vec3& v) {
  std::printf("%s(%g, %g, %g)\n", label, v.x, v.y, v.z);
}

bool write_json_file(const std::string& path, const nlohmann::json& j) {
  // Written to a temporary name and renamed, so a killed run never leaves a partial file.
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) {
      std::fprintf(stderr, "hrpp: cannot write %s\n", tmp.c_str());
      return false;
    }
    out << j.dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "hrpp: error writing %s\n", tmp.c_str());
      return false;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::fprintf(stderr, "hrpp: cannot rename %s to %s\n", tmp.c_str(), path.c_str());
    return false;
  }
  return true;
}

nlohmann::json bvh_json(const Bvh& bvh) {
  const BvhStats& s = bvh.stats;
  return {{"nodes", s.nodes},
          {"interior", s.interior},
          {"leaves", s.leaves},
          {"max_depth", s.max_depth},
          {"mean_leaf_depth", s.mean_leaf_depth},
          {"leaf_size_histogram", s.leaf_size_histogram},
          {"sah_cost", s.sah_cost},
          {"build_seconds", s.build_seconds},
          {"max_leaf_size", bvh.options.max_leaf_size},
          {"memory_bytes", bvh.memory_bytes()}};
}

int cmd_info(const std::string& path, uint32_t leaf_size, const std::string& json_path) {
  Scene s = load_scene(path);
  BvhBuildOptions bo;
  bo.max_leaf_size = leaf_size;
  Bvh bvh = build_bvh(s.triangles, bo);
  std::printf("scene      %s\n", s.path.c_str());
  std::printf("triangles  %zu (%u degenerate: kept, never hit)\n", s.triangles.size(),
              s.degenerate_triangles);
  std::printf("meshes     %zu\n", s.meshes.size());
  print_vec("bounds     min ", s.bounds.lo);
  print_vec("           max ", s.bounds.hi);
  const Camera& c = s.camera;
  std::printf("camera     %s\n", c.source.c_str());
  print_vec("           eye ", c.eye);
  print_vec("           target ", c.target);
  print_vec("           up ", c.up);
  std::printf("           fov_y %.4g deg, aspect %.4g, image %dx%d\n", c.fov_y_deg, c.aspect,
              c.width, c.height);
  std::printf("lights     %zu punctual, %zu emissive triangles\n", s.lights.size(),
              s.emissive_triangles().size());
  for (const Light& l : s.lights) {
    std::printf("           %-12s %-11s intensity %g colour (%g, %g, %g)", l.name.c_str(),
                light_type_name(l.type), l.intensity, l.color.x, l.color.y, l.color.z);
    if (l.type == Light::Type::kDirectional)
      std::printf(" direction (%g, %g, %g)\n", l.direction.x, l.direction.y, l.direction.z);
    else
      std::printf(" position (%g, %g, %g)\n", l.position.x, l.position.y, l.position.z);
  }
  std::printf("materials  %zu\n", s.materials.size());
  std::vector<uint32_t> tri_count(s.materials.size(), 0);
  for (uint32_t m : s.tri_material) tri_count[m]++;
  for (size_t i = 0; i < s.materials.size(); ++i) {
    const Material& m = s.materials[i];
    std::printf("           %-18s base (%.3g, %.3g, %.3g) metallic %.3g roughness %.3g", m.name.c_str(),
                m.base_color.r, m.base_color.g, m.base_color.b, m.metallic, m.roughness);
    if (m.is_emissive())
      std::printf(" emission (%.4g, %.4g, %.4g)", m.emission().x, m.emission().y, m.emission().z);
    if (m.transmission > 0) std::printf(" transmission %.3g ior %.3g", m.transmission, m.ior);
    std::printf(" %s, %u triangles\n", m.double_sided ? "double-sided" : "one-sided", tri_count[i]);
  }
  const BvhStats& st = bvh.stats;
  std::printf("bvh        binned SAH, %u bins, max leaf %u: %u nodes (%u interior, %u leaves), "
              "depth max %u mean-leaf %.1f, SAH cost %.2f, %.1f MB, built in %.3f s\n",
              bvh.options.bins, bvh.options.max_leaf_size, st.nodes, st.interior, st.leaves,
              st.max_depth, st.mean_leaf_depth, st.sah_cost, bvh.memory_bytes() / 1e6,
              st.build_seconds);
  std::printf("           leaf sizes:");
  for (size_t k = 1; k < st.leaf_size_histogram.size(); ++k)
    std::printf(" %zu:%u", k, st.leaf_size_histogram[k]);
  std::printf("\n");
  if (!json_path.empty()) {
    nlohmann::json j = {{"scene", s.path},
                        {"triangles", s.triangles.size()},
                        {"degenerate_triangles", s.degenerate_triangles},
                        {"bounds", {{"min", {s.bounds.lo.x, s.bounds.lo.y, s.bounds.lo.z}},
                                    {"max", {s.bounds.hi.x, s.bounds.hi.y, s.bounds.hi.z}}}},
                        {"camera", c.source},
                        {"lights", s.lights.size()},
                        {"emissive_triangles", s.emissive_triangles().size()},
                        {"materials", s.materials.size()},
                        {"bvh", bvh_json(bvh)}};
    if (!write_json_file(json_path, j)) return 2;
  }
  return 0;
}

int cmd_check_embree(const std::string& path, uint64_t rays, const std::string& kind,
                     uint64_t seed, const std::string& config, const std::string& json_path) {
  Scene s = load_scene(path);
  Bvh bvh = build_bvh(s.triangles);
  CrossCheckOptions opt;
  opt.rays = rays;
  opt.seed = seed;
  opt.embree_config = config;
  if (kind != "all") {
    RayKind k;
    parse_ray_kind(kind, &k);  // validated by CLI11
    opt.kinds = {k};
  }
  CrossCheckResult r = cross_check(s, bvh, opt);
  std::printf("check-embree %s: %s\n", s.path.c_str(), r.embree.c_str());
  std::printf("  %dx%d camera samples, %.2f s\n", r.width, r.height, r.seconds);
  std::printf("  %-8s %9s %8s %9s %13s %8s %7s %6s %6s %6s\n", "kind", "rays", "invalid",
              "hits", "hit-agreement", "hit-mis", "grazes", "t-mis", "p-mis", "ties");
  auto row = [](const char* name, const CrossCheckCounts& c) {
    std::printf("  %-8s %9llu %8llu %9llu %13.7f %8llu %7llu %6llu %6llu %6llu\n", name,
                (unsigned long long)c.rays, (unsigned long long)c.invalid_rays,
                (unsigned long long)c.hits, c.hit_agreement(),
                (unsigned long long)c.hit_mismatches, (unsigned long long)c.grazes,
                (unsigned long long)c.t_mismatches, (unsigned long long)c.prim_mismatches,
                (unsigned long long)c.ties);
  };
  for (int k = 0; k < kNumRayKinds; ++k)
    if (r.by_kind[k].rays) row(std::string(ray_kind_name(RayKind(k))).c_str(), r.by_kind[k]);
  row("all", r.total);
  for (const auto& e : r.examples) std::printf("  %s\n", e.c_str());
  std::printf("  %s\n", r.passed() ? "PASS: our traversal agrees with Embree"
                                   : "FAIL: disagreements beyond genuine ties and grazes");
  if (!json_path.empty() && !write_json_file(json_path, r.to_json())) return 2;
  return r.passed() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"HRPP: hash-based ray path prediction - golden model tool"};
  app.require_subcommand(1);

  std::string scene, json_path;
  uint32_t leaf_size = 4;
  auto* info = app.add_subcommand("info", "Print a scene's triangles, bounds, camera, lights, "
                                          "materials and BVH statistics");
  info->add_option("scene", scene, "glTF scene (.glb or .gltf)")->required();
  info->add_option("--leaf-size", leaf_size, "maximum triangles per BVH leaf")
      ->check(CLI::Range(1, 64));
  info->add_option("--json", json_path, "also write the summary as JSON to this file");

  uint64_t rays = 100000, seed = 1;
  std::string kind = "all", config = kEmbreeReferenceConfig;
  auto* ce = app.add_subcommand(
      "check-embree", "Trace the same rays with our BVH and with Embree 3 and compare them");
  ce->add_option("scene", scene, "glTF scene (.glb or .gltf)")->required();
  ce->add_option("--rays", rays, "number of camera samples (shadow and AO rays come on top)")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 32));
  ce->add_option("--kind", kind, "ray kinds to compare")
      ->check(CLI::IsMember({"primary", "shadow", "ao", "all"}));
  ce->add_option("--seed", seed, "random seed of the ray generator");
  ce->add_option("--embree-config", config, "Embree device configuration string");
  ce->add_option("--json", json_path, "write the results as JSON to this file");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (*info) return cmd_info(scene, leaf_size, json_path);
    if (*ce) return cmd_check_embree(scene, rays, kind, seed, config, json_path);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "hrpp: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrpp: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
