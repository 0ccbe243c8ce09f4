// hrpp render: PNG pictures of the shaded scene and per-pixel heat maps of traversal work and
// predictor outcomes.
#include "hrpp/report/render.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "common.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/workload/workload.h"
#include "subcommands.h"

namespace hrpp::cli {
namespace {

struct RenderArgs {
  std::string scene, out;
  WorkloadArgs w;
  PredictorArgs p;
};

int cmd_render(const RenderArgs& a) {
  PredictorConfig cfg;
  if (!parse_predictor_args("render", a.p, &cfg) || !check_workload_args("render", a.w)) return 2;
  if (!check_output_path("render", "--out", a.out, OutputKind::kFolder)) return 2;
  std::error_code ec;
  std::filesystem::create_directories(a.out, ec);
  if (ec || !std::filesystem::is_directory(a.out)) {
    std::fprintf(stderr, "hrpp render: --out %s: cannot create the folder: %s\n", a.out.c_str(),
                 ec ? ec.message().c_str() : "a file of that name exists");
    return 2;
  }
  Scene scene = load_scene(a.scene);
  Bvh bvh = build_bvh(scene.triangles);
  WorkloadOptions wo;
  if (!make_workload("render", a.w, scene, &wo) ||
      !finish_predictor_config("render", a.p, scene, bvh, &cfg))
    return 2;
  std::printf("render %s: %s\n", scene.path.c_str(), workload_line(wo).c_str());
  print_effects(scene, wo, a.w.effects);
  auto t0 = std::chrono::steady_clock::now();
  const RenderOutput out = render_all(scene, bvh, wo, cfg, a.out, tool_json());
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& s = out.summary;
  std::printf("  shaded: exposure %.4g, %.1f%% of surface samples lit\n",
              s["shaded"]["exposure"].get<double>(),
              100 * s["shaded"]["lit_fraction"].get<double>());
  for (const auto& [name, m] : s["maps"].items())
    std::printf("  %-17s %s: min %.4g, mean %.4g, max %.4g\n", name.c_str(),
                m["title"].get<std::string>().c_str(), m["min"].get<double>(),
                m["mean"].get<double>(), m["max"].get<double>());
  std::printf("  predictor: %.2f%% of interior-node tests skipped over all rays\n",
              100 * s["skipped_interior_fraction"].get<double>());
  std::printf("  wrote");
  for (const std::string& f : out.files) std::printf(" %s", f.c_str());
  std::printf(" (%.1f s)\n", secs);
  return 0;
}

}  // namespace

Subcommand add_render(CLI::App& app) {
  auto ra = std::make_shared<RenderArgs>();
  auto* rd = app.add_subcommand("render",
                                "Write PNG pictures: the shaded scene and per-pixel heat "
                                "maps of traversal work and predictor outcomes");
  rd->add_option("scene", ra->scene, "glTF scene (.glb or .gltf)")->required();
  rd->add_option("--out", ra->out, "output directory (created if missing)")->required();
  add_workload_options(rd, ra->w, "shadow,ao");
  add_predictor_options(rd, ra->p);
  return {rd, [ra] {
            apply_preset(ra->p);
            return cmd_render(*ra);
          }};
}

}  // namespace hrpp::cli
