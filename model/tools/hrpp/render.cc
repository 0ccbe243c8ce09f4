// hrpp render: PNG pictures of the shaded scene and per-pixel heat maps of traversal work and
// predictor outcomes.
#include "hrpp/report/render.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "common.h"
#include "gpu_time.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/util/atomic_file.h"
#include "hrpp/util/progress.h"
#include "hrpp/workload/workload.h"
#include "subcommands.h"

namespace hrpp::cli {
namespace {

struct RenderArgs {
  std::string scene, out;
  WorkloadArgs w;
  PredictorArgs p;
  TimingArgs t;  // the time figure: simulated (--gpu) or the cost model's
};

int cmd_render(const RenderArgs& a) {
  PredictorConfig cfg;
  sim::GpuConfig gpu;
  if (!parse_predictor_args("render", a.p, &cfg) || !check_workload_args("render", a.w) ||
      !check_timing_args("render", a.t, &gpu))
    return 2;
  if (!check_output_path("render", "--out", a.out, OutputKind::kFolder)) return 2;
  // The pictures of one run, or none: they are written into a fresh folder beside --out, which
  // then takes --out's place. An existing --out is replaced only when it is empty or an earlier
  // render's (it holds render.json); any other folder is left alone.
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path given = fs::path(a.out).lexically_normal();
  const fs::path target = given.has_filename() ? given : given.parent_path();
  if (fs::exists(target, ec) && !fs::is_empty(target, ec) &&
      !fs::exists(target / "render.json", ec)) {
    std::fprintf(stderr,
                 "hrpp render: --out %s: the folder holds files that are not an earlier render's "
                 "(no render.json): choose a new or empty folder\n",
                 a.out.c_str());
    return 2;
  }
  // One name per --out: an interrupted run's staging folder is removed by the next run.
  const fs::path staging = target.parent_path() / (target.filename().string() + ".rendering");
  fs::remove_all(staging, ec);
  if (!fs::create_directories(staging, ec)) {
    std::fprintf(stderr, "hrpp render: --out %s: cannot create %s: %s\n", a.out.c_str(),
                 staging.c_str(), ec.message().c_str());
    return 2;
  }
  // Removes the staging folder unless it became --out.
  struct Staging {
    fs::path dir;
    bool kept = false;
    ~Staging() {
      std::error_code e;
      if (!kept) fs::remove_all(dir, e);
    }
  } stage{staging};
  Scene scene = load_scene(a.scene);
  Bvh bvh = build_bvh(scene.triangles);
  WorkloadOptions wo;
  if (!make_workload("render", a.w, scene, &wo) ||
      !finish_predictor_config("render", a.p, scene, bvh, &cfg))
    return 2;
  // The configuration before the run (standard output flushed: it may be a pipe).
  std::printf("render %s: %s\n", scene.path.c_str(), workload_line(wo).c_str());
  print_effects(scene, wo, a.w.effects);
  const uint64_t table_bytes = cfg.table.unbounded ? 0 : (cfg.table.total_bits() + 7) / 8;
  const std::string config =
      "preset " + a.p.label + ": " + predictor_line(a.p, cfg, table_bytes, kUnknownEntries);
  std::printf("  %s\n", config.c_str());
  std::fflush(stdout);
  auto t0 = std::chrono::steady_clock::now();
  // Progress on standard error, one phase after the other (hrpp/util/progress.h).
  std::unique_ptr<Progress> progress;
  std::string phase;
  RenderOptions ro{.tool = tool_json(), .config = config};
  ro.progress = [&](const char* name, const char* unit, uint64_t done, uint64_t total) {
    if (phase != name) {
      progress.reset();  // clears the previous phase's line on a terminal
      phase = name;
      progress =
          std::make_unique<Progress>(stderr, std::string("render: ") + name, unit, total, t0);
    }
    progress->update(done);
  };
  RenderOutput out = render_all(scene, bvh, wo, cfg, staging.string(), ro);
  progress.reset();
  // The time figure: the same rays on RT units (hrpp simulate), with no predictor and this one;
  // render.json gets it before the folder is put in place.
  std::unique_ptr<GpuTime> time;
  if (a.t.timing == "simulate") {
    std::vector<RayRecord> rays;
    generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit*) { rays.push_back(r); });
    time = std::make_unique<GpuTime>();
    if (!simulate_time("render", a.t, gpu, a.p, cfg, scene, bvh, rays, time.get())) return 2;
  }
  const auto& nc = out.summary["net_cycles"];
  const double cost_base = nc["baseline_cycles"].get<double>(),
               cost_hrpp = nc["hrpp_cycles"].get<double>();
  out.summary["time"] = time_json(time.get(), cost_base, cost_hrpp);
  out.summary["preset"] = preset_json(a.p);
  try {
    write_file_atomic((staging / "render.json").string(), out.summary.dump(2) + "\n");
  } catch (const AtomicFileError& e) {
    std::fprintf(stderr, "hrpp render: %s\n", e.what());
    return 2;
  }
  // The run is complete: its folder replaces --out (an earlier render's is removed).
  const fs::path old =
      target.parent_path() / (target.filename().string() + ".old-" + std::to_string(::getpid()));
  const bool had = fs::exists(target, ec);
  if (had) fs::rename(target, old, ec);
  if (!ec) fs::rename(staging, target, ec);
  if (ec) {
    std::fprintf(stderr, "hrpp render: --out %s: cannot put the pictures in place: %s\n",
                 a.out.c_str(), ec.message().c_str());
    if (had && !fs::exists(target)) fs::rename(old, target, ec);  // the earlier render back
    return 2;
  }
  stage.kept = true;
  if (had) fs::remove_all(old, ec);
  for (std::string& f : out.files)  // the files' names in --out, not in the staging folder
    f = (target / fs::path(f).filename()).string();
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& s = out.summary;
  uint64_t rays = 0;
  for (const auto& [kind, k] : s["by_kind"].items()) rays += k["rays"].get<uint64_t>();
  std::printf("%s", time_lines(time.get(), cost_base, cost_hrpp, rays).c_str());
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
  rd->add_option("--out", ra->out,
                 "output folder: created, or replaced when it holds an earlier render (all "
                 "pictures of one run or none)")
      ->required();
  add_workload_options(rd, ra->w, "shadow,ao");
  add_predictor_options(rd, ra->p);
  add_timing_options(rd, ra->t);
  return {rd, [ra] {
            if (!resolve_preset("render", ra->p)) return 2;
            return cmd_render(*ra);
          }};
}

}  // namespace hrpp::cli
