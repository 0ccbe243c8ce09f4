// hrpp info: a scene's triangles, bounds, camera, lights, materials and BVH statistics.
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "common.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/trace/bvh_micro21.h"
#include "subcommands.h"

namespace hrpp::cli {
namespace {

void print_vec(const char* label, const Vec3& v) {
  std::printf("%s(%g, %g, %g)\n", label, v.x, v.y, v.z);
}

struct InfoArgs {
  std::string scene, json_path, bvh = "sah";
  uint32_t leaf_size = 4;
  CLI::Option* leaf_size_opt = nullptr;
};

int cmd_info(const InfoArgs& a) {
  const std::string& json_path = a.json_path;
  BvhBuildOptions bo = bvh_build_options(a.bvh);
  if (bo.builder != BvhBuilder::kSah && a.leaf_size_opt->count()) {
    std::fprintf(stderr,
                 "hrpp info: --leaf-size applies only to our SAH build (--bvh sah); this run uses "
                 "--bvh %s (leaves of up to %u triangles, as Embree's builder makes them)\n",
                 a.bvh.c_str(), kMicro21MaxLeafSize);
    return 2;
  }
  if (!json_path.empty() && !check_output_path("info", "--json", json_path, OutputKind::kJson))
    return 2;
  Scene s = load_scene(a.scene);
  bo.max_leaf_size = a.leaf_size;
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
    std::printf("           %-18s base (%.3g, %.3g, %.3g) metallic %.3g roughness %.3g",
                m.name.c_str(), m.base_color.r, m.base_color.g, m.base_color.b, m.metallic,
                m.roughness);
    if (m.is_emissive())
      std::printf(" emission (%.4g, %.4g, %.4g)", m.emission().x, m.emission().y, m.emission().z);
    if (m.transmission > 0) std::printf(" transmission %.3g ior %.3g", m.transmission, m.ior);
    std::printf(" %s, %u triangles\n", m.double_sided ? "double-sided" : "one-sided", tri_count[i]);
  }
  const BvhStats& st = bvh.stats;
  if (bvh.options.builder == BvhBuilder::kSah)
    std::printf("bvh        binned SAH, %u bins, max leaf %u: ", bvh.options.bins,
                bvh.options.max_leaf_size);
  else
    std::printf(
        "bvh        %s: MICRO 2021's, Embree's spatial-split SAH, max leaf %u, %u triangle "
        "references:\n           ",
        std::string(bvh_builder_name(bvh.options.builder)).c_str(), bvh.options.max_leaf_size,
        st.references);
  std::printf(
      "%u nodes (%u interior, %u leaves), depth max %u mean-leaf %.1f, SAH cost %.2f, %.1f MB, "
      "built in %.3f s\n",
      st.nodes, st.interior, st.leaves, st.max_depth, st.mean_leaf_depth, st.sah_cost,
      bvh.memory_bytes() / 1e6, st.build_seconds);
  std::printf("           leaf sizes:");
  size_t largest = st.leaf_size_histogram.size() - 1;  // up to the largest leaf
  while (largest > 1 && st.leaf_size_histogram[largest] == 0) --largest;
  for (size_t k = 1; k <= largest; ++k) std::printf(" %zu:%u", k, st.leaf_size_histogram[k]);
  std::printf("\n");
  if (!json_path.empty()) {
    // Everything the text shows.
    auto vec = [](const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
    nlohmann::json lights = nlohmann::json::array();
    for (const Light& l : s.lights) {
      nlohmann::json lj = {{"name", l.name},
                           {"type", light_type_name(l.type)},
                           {"intensity", l.intensity},
                           {"color", vec(l.color)},
                           {"range", l.range > 0 ? nlohmann::json(l.range) : nlohmann::json()}};
      if (l.type != Light::Type::kDirectional) lj["position"] = vec(l.position);
      if (l.type != Light::Type::kPoint) lj["direction"] = vec(l.direction);
      lights.push_back(lj);
    }
    nlohmann::json materials = nlohmann::json::array();
    for (size_t i = 0; i < s.materials.size(); ++i) {
      const Material& m = s.materials[i];
      materials.push_back(
          {{"name", m.name},
           {"base_color", {m.base_color.r, m.base_color.g, m.base_color.b, m.base_color.a}},
           {"metallic", m.metallic},
           {"roughness", m.roughness},
           {"emission", m.is_emissive() ? vec(m.emission()) : nlohmann::json()},
           {"transmission", m.transmission},
           {"ior", m.ior},
           {"double_sided", m.double_sided},
           {"triangles", tri_count[i]}});
    }
    nlohmann::json meshes = nlohmann::json::array();
    for (const MeshRange& m : s.meshes)
      meshes.push_back({{"name", m.name},
                        {"first_triangle", m.first},
                        {"triangles", m.count},
                        {"material", m.material}});
    nlohmann::json j = {{"scene", s.path},
                        {"triangles", s.triangles.size()},
                        {"degenerate_triangles", s.degenerate_triangles},
                        {"meshes", meshes},
                        {"bounds",
                         {{"min", {s.bounds.lo.x, s.bounds.lo.y, s.bounds.lo.z}},
                          {"max", {s.bounds.hi.x, s.bounds.hi.y, s.bounds.hi.z}}}},
                        {"camera",
                         {{"source", c.source},
                          {"eye", vec(c.eye)},
                          {"target", vec(c.target)},
                          {"up", vec(c.up)},
                          {"fov_y_deg", c.fov_y_deg},
                          {"aspect", c.aspect},
                          {"image", {c.width, c.height}}}},
                        {"lights", lights},
                        {"emissive_triangles", s.emissive_triangles().size()},
                        {"materials", materials},
                        {"bvh", bvh_json(bvh)}};
    j["bvh"]["build_seconds"] = st.build_seconds;
    j["tool"] = tool_json();
    if (!write_json_file(json_path, j)) return 2;
  }
  return 0;
}

}  // namespace

Subcommand add_info(CLI::App& app) {
  auto a = std::make_shared<InfoArgs>();
  auto* info = app.add_subcommand("info",
                                  "Print a scene's triangles, bounds, camera, lights, "
                                  "materials and BVH statistics");
  info->add_option("scene", a->scene, "glTF scene (.glb or .gltf)")->required();
  a->leaf_size_opt =
      info->add_option("--leaf-size", a->leaf_size, "maximum triangles per BVH leaf (--bvh sah)")
          ->check(CLI::Range(1, 64));
  add_bvh_option(info, a->bvh);
  info->add_option("--json", a->json_path,
                   "also write the summary as JSON to this file ('-': to standard output, the text "
                   "summary then to standard error)");
  return {info, [a] { return cmd_info(*a); }};
}

}  // namespace hrpp::cli
