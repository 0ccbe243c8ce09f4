// hrpp predict: run the HRPP predictor over a scene's rays (generated, or read from a ray-stream
// file) and report skipped work, precision and recall per ray kind, and the cost of accuracy.
// cmd_predict coordinates: the configuration (configure_predict), the run (run_predict), the
// report as JSON (predict_json) and as text (print_configuration, print_report).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "common.h"
#include "gpu_time.h"
#include "hrpp/hardware/rtl_config.h"
#include "hrpp/hardware/rtl_update_delay.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/predictor/tiled_predictor.h"
#include "hrpp/report/spec_image.h"
#include "hrpp/scene/scene.h"
#include "hrpp/timing/cost_model.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/util/progress.h"
#include "hrpp/workload/ray_stream.h"
#include "hrpp/workload/workload.h"
#include "subcommands.h"

namespace hrpp::cli {
namespace {

struct PredictArgs {
  std::string scene, json_path, stream, bvh = "sah";
  WorkloadArgs w;
  PredictorArgs p;
  // Cost of accuracy (docs/cost_model.md).
  uint32_t update_delay = 0;
  int pipeline_latency = -1;  // >= 0: update_delay from the RTL's cycle model
  bool measure_time = false;
  std::string spec_images;
  uint32_t cores = 1, threads = 1, tile = 8;  // TiledPredictor (docs/predictor.md)
  TimingArgs t;  // the time figure: simulated (--gpu) or the cost model's
};

/// What a run needs, resolved from the options, the scene and the rays' source.
struct PredictSetup {
  PredictorConfig cfg;
  std::unique_ptr<RayStreamReader> stream;  // --stream; otherwise the rays are generated
  Scene scene;
  Bvh bvh;
  WorkloadOptions wo;       // the generated workload (without --stream)
  nlohmann::json workload;  // the report's description of the workload
  TiledOptions to;
  sim::GpuConfig gpu;  // --timing simulate
};

/// Resolves the configuration; prints the error and returns the exit code (0: go on).
int configure_predict(const PredictArgs& a, PredictSetup* s) {
  PredictorConfig& cfg = s->cfg;
  if (!parse_predictor_args("predict", a.p, &cfg) || !check_workload_args("predict", a.w) ||
      !check_timing_args("predict", a.t, &s->gpu))
    return 2;
  if ((!a.json_path.empty() &&
       !check_output_path("predict", "--json", a.json_path, OutputKind::kJson)) ||
      (!a.spec_images.empty() &&
       !check_output_path("predict", "--spec-images", a.spec_images, OutputKind::kFolder)))
    return 2;
  std::unique_ptr<RayStreamReader>& stream = s->stream;
  if (!a.stream.empty()) stream = std::make_unique<RayStreamReader>(a.stream);

  s->scene = load_scene(a.scene);
  s->bvh = build_bvh(s->scene.triangles, bvh_build_options(a.bvh));
  const Scene& scene = s->scene;
  if (!finish_predictor_config("predict", a.p, scene, s->bvh, &cfg)) return 2;
  cfg.update_delay =
      a.pipeline_latency >= 0 ? rtl_update_delay(uint32_t(a.pipeline_latency)) : a.update_delay;
  cfg.measure_time = a.measure_time;
  WorkloadOptions& wo = s->wo;
  nlohmann::json& workload = s->workload;
  if (stream) {
    const uint64_t fp = scene_fingerprint(scene);
    if (stream->header().scene_fingerprint != fp) {
      std::fprintf(stderr,
                   "hrpp predict: %s was generated from another scene (fingerprint %016llx; %s "
                   "has %016llx)\n",
                   a.stream.c_str(), (unsigned long long)stream->header().scene_fingerprint,
                   scene.path.c_str(), (unsigned long long)fp);
      return 2;
    }
    workload = nlohmann::json::parse(stream->header().options, nullptr, false);
    if (workload.is_discarded()) workload = stream->header().options;
    workload["stream"] = a.stream;
    workload["rays"] = stream->header().ray_count;
  } else {
    if (!make_workload("predict", a.w, scene, &wo)) return 2;
    workload = workload_json(scene, wo);
  }

  TiledOptions& to = s->to;
  to.cores = a.cores;
  to.threads = a.threads;
  to.tile = a.tile;
  if (stream && workload.contains("resolution") && workload["resolution"].is_array())
    to.width = workload["resolution"][0].get<uint32_t>();
  else if (!stream)
    to.width = static_cast<uint32_t>(wo.width);
  if (const std::string e = to.validate(); !e.empty()) {
    std::fprintf(stderr, "hrpp predict: --cores/--threads: %s%s\n", e.c_str(),
                 stream ? " (the stream's header records no resolution)" : "");
    return 2;
  }
  return 0;
}

/// The run's outcome beside the predictor's statistics.
struct PredictRun {
  double secs = 0;                        // wall-clock time of the run
  std::unique_ptr<SpecImage> spec_image;  // generated workloads with one thread
  std::vector<RayRecord> rays;            // --timing simulate: the rays, in issue order
  std::unique_ptr<GpuTime> time;          // --timing simulate
};

/// Feeds every ray to the predictor, with progress on stderr, and finishes it.
PredictRun run_predict(PredictSetup& s, const PredictArgs& a, TiledPredictor& pred) {
  PredictRun run;
  const std::unique_ptr<RayStreamReader>& stream = s.stream;
  const WorkloadOptions& wo = s.wo;
  // The speculative image needs each ray's result: generated workloads, one thread.
  std::unique_ptr<SpecImage>& spec_image = run.spec_image;
  if (!stream && a.threads == 1)
    spec_image = std::make_unique<SpecImage>(  // its picture names the configuration
        s.scene, wo.width, wo.height, wo.spp,
        (a.p.preset.empty() ? "" : "preset " + a.p.preset + ": ") +
            predictor_line(a.p, s.cfg,
                           s.cfg.table.unbounded ? 0 : (s.cfg.table.total_bits() + 7) / 8,
                           kUnknownEntries));
  const uint64_t expected =
      stream ? stream->header().ray_count : uint64_t(wo.width) * wo.height * wo.spp;
  const char* unit = stream ? "stream rays" : "camera samples";
  uint64_t done = 0;
  auto t0 = std::chrono::steady_clock::now();
  Progress progress(stderr, "predict", unit, expected, t0);  // hrpp/util/progress.h
  const bool keep = a.t.timing == "simulate";
  auto process = [&](const RayRecord& r) {
    if (keep) run.rays.push_back(r);
    const std::optional<RayResult> res = pred.push(r);
    if (spec_image && res) spec_image->add(r, *res);
    if ((!stream && r.kind != RayKind::kPrimary) || (++done & 0xFFF)) return;
    progress.update(done);
  };
  if (stream) {
    RayRecord r;
    while (stream->next(&r)) process(r);
  } else {
    generate_rays(s.scene, s.bvh, wo, [&](const RayRecord& r, const Hit*) { process(r); });
  }
  pred.finish();
  progress.finish();
  run.secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

/// The JSON report; finishes the speculative image (writing --spec-images DIR's picture).
nlohmann::json predict_json(const PredictSetup& s, const PredictArgs& a, const TiledPredictor& pred,
                            const PredictRun& run, const CostModel& cost) {
  const nlohmann::json& workload = s.workload;
  nlohmann::json j = {{"tool", tool_json()}};
  j.update(pred.to_json());
  if (!s.cfg.measure_time) null_unmeasured_times(&j);  // not measured: null, not 0
  j["scene"] = s.scene.path;
  j["bvh"] = bvh_json(s.bvh);
  j["workload"] = workload;
  if (workload.contains("resolution")) j["resolution"] = workload["resolution"];
  if (workload.contains("spp")) j["spp"] = workload["spp"];
  if (workload.contains("seed")) j["seed"] = workload["seed"];
  j["seconds"] = run.secs;
  j["threads"] = a.threads;
  // Cost of accuracy (docs/cost_model.md): cost-model cycles, CPU time, speculative image error.
  j["config"]["update_delay"] = s.cfg.update_delay;
  j["config"]["pipeline_latency"] =  // null: none given (the update delay is --update-delay's)
      a.pipeline_latency >= 0 ? nlohmann::json(a.pipeline_latency) : nlohmann::json(nullptr);
  j["cost_model"] = cost.to_json();
  j["cost"] = cycle_cost_json(pred.total(), cost);
  {
    const CycleCost cc = cycle_cost(pred.total(), cost);
    j["time"] = time_json(run.time.get(), cc.baseline, cc.hrpp);
  }
  j["preset"] = preset_json(a.p);
  for (int k = 0; k < kNumRayKinds; ++k)
    if (pred.by_kind(RayKind(k)).rays)
      j["by_kind"][std::string(ray_kind_name(RayKind(k)))]["cost"] =
          cycle_cost_json(pred.by_kind(RayKind(k)), cost);
  if (run.spec_image) {
    if (!a.spec_images.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(a.spec_images, ec);
    }
    j["image_error"] = run.spec_image->finish(a.spec_images);
  }
  return j;
}

/// The text report's head, printed before the run: the workload, its effects, the predictor and
/// its cores, the time figure's source.
void print_configuration(const PredictSetup& s, const PredictArgs& a, const TiledPredictor& pred) {
  const Scene& scene = s.scene;
  const std::unique_ptr<RayStreamReader>& stream = s.stream;
  if (stream) {
    std::printf("predict %s: rays from %s (%llu records), generated with %s\n", scene.path.c_str(),
                a.stream.c_str(), (unsigned long long)stream->header().ray_count,
                stream->header().options.c_str());
  } else {
    std::printf("predict %s: %s\n", scene.path.c_str(), workload_line(s.wo).c_str());
    print_effects(scene, s.wo, a.w.effects);
  }
  std::printf("%s", bvh_line(s.bvh).c_str());
  std::printf("  predictor %s: %s\n", a.p.label.c_str(),
              predictor_line(a.p, s.cfg, pred.table_bytes(), kUnknownEntries).c_str());
  if (a.cores > 1)
    std::printf(
        "  %u cores, each with its own table (%ux%u-pixel tiles, tile i on core i mod %u), "
        "%u threads\n",
        a.cores, a.tile, a.tile, a.cores, a.threads);
  if (a.t.timing == "simulate")
    std::printf(
        "  time: the rays on %s RT units with no predictor and with this one (hrpp "
        "simulate), then the cost model's\n",
        a.t.gpu.c_str());
  else
    std::printf("  time: the cost model's (--timing cost-model: no caches, no competing rays)\n");
  std::fflush(stdout);
}

/// The text report's body: the time first (simulated, then the cost model's), one row per ray
/// kind, the table's use, the run's speed.
void print_report(const PredictorConfig& cfg, const TiledPredictor& pred, const nlohmann::json& j,
                  const CostModel& cost, const PredictRun& run) {
  const CycleCost cc = cycle_cost(pred.total(), cost);
  std::printf("%s", time_lines(run.time.get(), cc.baseline, cc.hrpp, pred.total().rays).c_str());
  if (cfg.update_delay)
    std::printf(
        "  (the work below and the cost model's time with an update delay of %u rays; the "
        "simulated table's staleness is the simulation's own)\n",
        cfg.update_delay);
  if (cfg.measure_time)
    std::printf("  CPU time of the golden model: %.0f -> %.0f ns per ray\n",
                double(pred.total().baseline_ns) / std::max<uint64_t>(1, pred.total().rays),
                double(pred.total().hrpp_ns) / std::max<uint64_t>(1, pred.total().rays));
  if (j.contains("image_error"))
    std::printf("  image: MAE %.5f, %.3f%% pixels differ from the exact render\n",
                j["image_error"]["mean_abs_error"].get<double>(),
                100 * j["image_error"]["differing_pixel_fraction"].get<double>());
  std::printf(
      "  work, by ray kind (skipped: interior-node tests saved, wasted predicted tests "
      "counted against it; work is not time):\n");
  std::printf("  %-10s %10s %8s %9s %9s %10s %10s %10s %10s %8s\n", "kind", "rays", "skipped",
              "precision", "recall", "TP", "FP", "FN", "TN", "wrong");
  auto row = [](const char* name, const PredictStats& s) {
    std::printf("  %-10s %10llu %7.2f%% %9.4f %9.4f %10llu %10llu %10llu %10llu %8llu\n", name,
                (unsigned long long)s.rays, 100 * s.skipped_interior_fraction(), s.precision(),
                s.recall(), (unsigned long long)s.true_positive,
                (unsigned long long)s.false_positive, (unsigned long long)s.false_negative,
                (unsigned long long)s.true_negative, (unsigned long long)s.wrong_results);
  };
  for (int k = 0; k < kNumRayKinds; ++k)
    if (pred.by_kind(RayKind(k)).rays)
      row(std::string(ray_kind_name(RayKind(k))).c_str(), pred.by_kind(RayKind(k)));
  row("all", pred.total());
  if (cfg.mode == PredictMode::kAnyHit && pred.total().wrong_results)
    std::printf(
        "  wrong: closest-hit rays answered as any-hit queries with a hit that is not "
        "their closest (%llu of them the any-hit walk from the root gives wrong too)\n",
        (unsigned long long)pred.total().baseline_wrong_results);
  if (pred.table_entries() != kUnknownEntries)
    std::printf("  table: %llu entries used, %llu bytes%s\n",
                (unsigned long long)pred.table_entries(), (unsigned long long)pred.table_bytes(),
                cfg.table.unbounded ? " (unbounded: the bytes of the entries used)" : "");
  std::printf("  %.1f s, %.2f M rays/s\n", run.secs, pred.total().rays / run.secs / 1e6);
}

int cmd_predict(const PredictArgs& a) {
  PredictSetup s;
  if (const int rc = configure_predict(a, &s)) return rc;
  TiledPredictor pred(s.bvh, s.cfg, s.to);
  if (!a.spec_images.empty() && a.threads != 1) {
    std::fprintf(stderr, "hrpp predict: --spec-images needs --threads 1\n");
    return 2;
  }
  print_configuration(s, a, pred);
  PredictRun run = run_predict(s, a, pred);
  if (a.t.timing == "simulate") {
    run.time = std::make_unique<GpuTime>();
    if (!simulate_time("predict", a.t, s.gpu, a.p, s.cfg, s.scene, s.bvh, run.rays, run.time.get()))
      return 2;
  }
  const CostModel cost;
  const nlohmann::json j = predict_json(s, a, pred, run, cost);
  print_report(s.cfg, pred, j, cost, run);
  // The report is written either way (it counts exact_mismatches); the exit code says which.
  if (!a.json_path.empty() && !write_json_file(a.json_path, j)) return 2;
  if (pred.total().exact_mismatches) {
    std::fprintf(
        stderr,
        "hrpp predict: BUG: %llu rays answered differently from the baseline in an exact mode\n",
        (unsigned long long)pred.total().exact_mismatches);
    return 1;
  }
  return 0;
}

}  // namespace

Subcommand add_predict(CLI::App& app) {
  auto pa = std::make_shared<PredictArgs>();
  auto* pr = app.add_subcommand("predict",
                                "Run the HRPP predictor over a scene's rays and report "
                                "skipped work, precision and recall per ray kind");
  pr->add_option("scene", pa->scene, "glTF scene (.glb or .gltf)")->required();
  add_predictor_options(pr, pa->p);
  add_timing_options(pr, pa->t);
  std::vector<CLI::Option*> wopts = add_workload_options(pr, pa->w, "shadow,ao");
  wopts.push_back(pr->add_flag("!--no-shadow", pa->w.shadow, "do not trace shadow rays"));
  wopts.push_back(pr->add_flag("!--no-ao", pa->w.ao, "do not trace ambient-occlusion rays"));
  auto* stream_opt = pr->add_option("--stream", pa->stream,
                                    "read the rays from this ray-stream file (hrpp trace) instead "
                                    "of generating them");
  for (CLI::Option* o : wopts) stream_opt->excludes(o);
  pr->add_option("--json", pa->json_path,
                 "write the report as JSON to this file ('-': to standard output, the text report "
                 "then to standard error)");
  add_bvh_option(pr, pa->bvh);
  auto* delay_opt = pr->add_option("--update-delay", pa->update_delay,
                                   "rays looked up between a ray's lookup and its table write "
                                   "(0: the untimed model; docs/cost_model.md)")
                        ->capture_default_str();
  pr->add_option("--pipeline-latency", pa->pipeline_latency,
                 "traversal-engine walk latency in cycles: the update delay is the RTL's, from "
                 "the cycle model (docs/cost_model.md); default: none, the update delay's")
      ->check(CLI::Range(0, 1 << 20))
      ->excludes(delay_opt);
  pr->add_flag("--measure-time", pa->measure_time,
               "measure the CPU time per ray of the baseline walk and of HRPP's work");
  pr->add_option("--spec-images", pa->spec_images,
                 "write DIR/spec_compare.png: exact | predictor's answers | difference "
                 "(primary rays)")
      ->excludes(stream_opt);

  pr->add_option("--cores", pa->cores,
                 "predictor cores, each with its own table; image tile i goes to core i mod "
                 "cores (the statistics depend on it, not on --threads)")
      ->check(CLI::Range(1u, 4096u))
      ->capture_default_str();
  pr->add_option("--threads", pa->threads, "worker threads that run the cores")
      ->check(CLI::Range(1u, 1024u))
      ->capture_default_str();
  pr->add_option("--core-tile", pa->tile, "edge in pixels of the image tiles assigned to cores")
      ->check(CLI::Range(1u, 65536u))
      ->capture_default_str();
  return {pr, [pa] {
            if (!resolve_preset("predict", pa->p)) return 2;
            return cmd_predict(*pa);
          }};
}

}  // namespace hrpp::cli
