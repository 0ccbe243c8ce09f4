// hrpp: the project's command-line tool. `hrpp --help` and `hrpp SUBCOMMAND --help` list options.
//
// Exit codes: 0 success; 1 a check failed (e.g. check-embree found mismatches); 2 bad input
// (bad option, unreadable or malformed scene or ray stream, unwritable output).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "hrpp/util/atomic_file.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/timing/cost_model.h"
#include "hrpp/reference/crosscheck.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/workload/ray_stream.h"
#include "hrpp/report/render.h"
#include "hrpp/hardware/rtl_config.h"
#include "hrpp/scene/scene.h"
#include "hrpp/predictor/tiled_predictor.h"
#include "hrpp/workload/workload.h"

#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace {

using namespace hrpp;

void print_vec(const char* label, const Vec3& v) {
  std::printf("%s(%g, %g, %g)\n", label, v.x, v.y, v.z);
}

bool write_json_file(const std::string& path, const nlohmann::json& j) {
  try {
    write_file_atomic(path, j.dump(2) + "\n");
  } catch (const AtomicFileError& e) {
    std::fprintf(stderr, "hrpp: %s\n", e.what());
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
  std::printf("  %-8s %9s %8s %8s %9s %13s %8s %7s %6s %6s %6s\n", "kind", "rays", "invalid",
              "no-embr", "hits", "hit-agreement", "hit-mis", "grazes", "t-mis", "p-mis", "ties");
  auto row = [](const char* name, const CrossCheckCounts& c) {
    std::printf("  %-8s %9llu %8llu %8llu %9llu %13.7f %8llu %7llu %6llu %6llu %6llu\n", name,
                (unsigned long long)c.rays, (unsigned long long)c.invalid_rays,
                (unsigned long long)c.outside_embree, (unsigned long long)c.hits,
                c.hit_agreement(),
                (unsigned long long)c.hit_mismatches, (unsigned long long)c.grazes,
                (unsigned long long)c.t_mismatches, (unsigned long long)c.prim_mismatches,
                (unsigned long long)c.ties);
  };
  for (int k = 0; k < kNumRayKinds; ++k)
    if (r.by_kind[k].rays) row(std::string(ray_kind_name(RayKind(k))).c_str(), r.by_kind[k]);
  row("all", r.total);
  for (const auto& e : r.examples) std::printf("  %s\n", e.c_str());
  std::printf("  (no-embr: valid rays outside Embree's range, never sent to it; a check must "
              "compare at least %g%% of the rays and at least one)\n",
              100 * kMinComparedFraction);
  if (r.passed()) {
    std::printf("  PASS: our traversal agrees with Embree\n");
  } else {
    std::printf("  FAIL: %s\n", r.failure().c_str());
    std::fprintf(stderr, "hrpp check-embree: FAIL: %s\n", r.failure().c_str());
  }
  if (!json_path.empty() && !write_json_file(json_path, r.to_json())) return 2;
  return r.passed() ? 0 : 1;
}


/// Parses "WxH" into two positive integers.
bool parse_wxh(const std::string& s, uint32_t* a, uint32_t* b) {
  size_t x = s.find('x');
  if (x == std::string::npos || x == 0 || x + 1 >= s.size()) return false;
  try {
    size_t p1, p2;
    unsigned long va = std::stoul(s.substr(0, x), &p1), vb = std::stoul(s.substr(x + 1), &p2);
    if (p1 != x || p2 != s.size() - x - 1 || va == 0 || vb == 0 || va > (1u << 24) ||
        vb > (1u << 24))
      return false;
    *a = static_cast<uint32_t>(va);
    *b = static_cast<uint32_t>(vb);
    return true;
  } catch (...) {
    return false;
  }
}

// ---- workload options (trace, predict, render) -----------------------------------------------

struct WorkloadArgs {
  std::string effects, order = "scanline", res;
  int spp = 1, depth = 2, tile = 8;
  uint64_t seed = 1;
  float ao_distance = 0.f;
  bool shadow = true, ao = true;  // predict's --no-shadow / --no-ao
};

/// Adds the workload options; returns them (so that --stream can exclude them).
std::vector<CLI::Option*> add_workload_options(CLI::App* app, WorkloadArgs& a,
                                               const std::string& default_effects) {
  a.effects = default_effects;
  std::vector<CLI::Option*> o;
  o.push_back(app->add_option("--effects", a.effects,
                              "'auto' (what the scene's lights and materials call for), 'none', or "
                              "a comma-separated list of shadow, ao, reflection, refraction, "
                              "diffuse, auto (docs/workloads.md)")
                  ->capture_default_str());
  o.push_back(app->add_option("--res", a.res, "image resolution WxH (default: the camera's)"));
  o.push_back(app->add_option("--spp", a.spp, "samples per pixel")->check(CLI::Range(1, 4096)));
  o.push_back(app->add_option("--order", a.order, "ray issue order")
                  ->check(CLI::IsMember({"scanline", "tiled", "morton"}))
                  ->capture_default_str());
  o.push_back(app->add_option("--tile", a.tile, "tile edge in pixels (tiled and morton orders)")
                  ->check(CLI::Range(1, 4096))
                  ->capture_default_str());
  o.push_back(app->add_option("--depth", a.depth,
                              "generations of reflection / refraction / diffuse rays")
                  ->check(CLI::Range(0, 16))
                  ->capture_default_str());
  o.push_back(app->add_option("--seed", a.seed, "random seed of the ray generator"));
  o.push_back(app->add_option("--ao-distance", a.ao_distance,
                              "AO ray length (default or 0: 5% of the scene diagonal)")
                  ->check(CLI::NonNegativeNumber));
  return o;
}

/// Checks what can be checked before the scene is loaded.
bool check_workload_args(const char* cmd, const WorkloadArgs& a) {
  uint32_t w, h;
  if (!a.res.empty() && !parse_wxh(a.res, &w, &h)) {
    std::fprintf(stderr, "hrpp %s: --res must be WIDTHxHEIGHT (e.g. 256x256), got '%s'\n", cmd,
                 a.res.c_str());
    return false;
  }
  if (!std::isfinite(a.ao_distance)) {  // CLI11's NonNegativeNumber lets NaN through
    std::fprintf(stderr, "hrpp %s: --ao-distance must be a finite number >= 0, got %g\n", cmd,
                 a.ao_distance);
    return false;
  }
  return true;
}

/// The generation options for a scene; prints the error and returns false on a bad --effects.
bool make_workload(const char* cmd, const WorkloadArgs& a, const Scene& scene,
                   WorkloadOptions* wo) {
  uint32_t w = 0, h = 0;
  if (!a.res.empty()) parse_wxh(a.res, &w, &h);  // checked by check_workload_args
  wo->width = static_cast<int>(w);
  wo->height = static_cast<int>(h);
  workload_resolution(scene, *wo, &wo->width, &wo->height);
  wo->spp = a.spp;
  wo->seed = a.seed;
  wo->ao_distance = a.ao_distance;
  wo->max_depth = a.depth;
  wo->tile = a.tile;
  parse_ray_order(a.order, &wo->order);  // checked by CLI11
  const std::string err = apply_effects(a.effects, scene, wo);
  if (!err.empty()) {
    std::fprintf(stderr, "hrpp %s: --effects: %s\n", cmd, err.c_str());
    return false;
  }
  wo->shadow = wo->shadow && a.shadow;
  wo->ao = wo->ao && a.ao;
  return true;
}

/// "512x512, 1 spp, seed 1, scanline order, depth 2"
std::string workload_line(const WorkloadOptions& wo) {
  std::string order(ray_order_name(wo.order));
  if (wo.order != RayOrder::kScanline)
    order += " (" + std::to_string(wo.tile) + "x" + std::to_string(wo.tile) + " tiles)";
  return std::to_string(wo.width) + "x" + std::to_string(wo.height) + ", " +
         std::to_string(wo.spp) + " spp, seed " + std::to_string(wo.seed) + ", " + order +
         " order, depth " + std::to_string(wo.max_depth);
}

void print_effects(const Scene& scene, const WorkloadOptions& wo, const std::string& spec) {
  std::printf("effects (--effects %s):\n", spec.c_str());
  for (const std::string& l : describe_effects(scene, wo, spec)) std::printf("  %s\n", l.c_str());
}

// ---- predictor options (predict, render) -----------------------------------------------------

struct PredictorArgs {
  std::string hash = "faithful", table = "unbounded", mode = "closest-exact", combine = "xor";
  int precision = 6, exp_bits = 3, origin_bits = 5, dir_bits = 3;
  uint32_t go_up = 0, nodes_per_entry = 1;
  int tag_bits = -1;
  std::string preset;  // rtl-NAME: an RTL configuration's hash and table
  std::map<std::string, CLI::Option*> given;  // the options a preset sets, by name
};

void add_predictor_options(CLI::App* app, PredictorArgs& a) {
  std::vector<std::string> presets;
  for (const std::string& n : rtl_config_names()) presets.push_back("rtl-" + n);
  app->add_option("--preset", a.preset,
                  "an RTL configuration's hash and table (rtl/config/hrpp_configs.json); the "
                  "options below override it")
      ->check(CLI::IsMember(presets));
  app->add_option("--hash", a.hash, "hash variant")->check(CLI::IsMember({"faithful", "improved"}));
  app->add_option("--precision", a.precision, "faithful hash: mantissa bits per component (P)")
      ->check(CLI::Range(1, 23));
  app->add_option("--exp-bits", a.exp_bits, "faithful hash: top exponent bits per component (E)")
      ->check(CLI::Range(0, 8));
  app->add_option("--origin-bits", a.origin_bits, "improved hash: bits per origin axis")
      ->check(CLI::Range(1, 16));
  app->add_option("--dir-bits", a.dir_bits, "improved hash: bits per direction component")
      ->check(CLI::Range(1, 16));
  app->add_option("--combine", a.combine, "how origin and direction fields combine")
      ->check(CLI::IsMember({"xor", "concat"}));
  app->add_option("--go-up", a.go_up, "store the hit leaf's ancestor this many levels up")
      ->check(CLI::Range(0u, 64u));
  app->add_option("--table", a.table, "'unbounded' or SETSxWAYS, e.g. 256x4");
  app->add_option("--tag-bits", a.tag_bits,
                  "stored tag bits (default: the full tag, so keys never alias; fewer bits save "
                  "storage and let keys of one set alias)")
      ->check(CLI::Range(0, 64));
  app->add_option("--nodes-per-entry", a.nodes_per_entry, "node ids per table entry (K)")
      ->check(CLI::Range(1, kMaxNodesPerEntry));
  app->add_option("--mode", a.mode, "how closest-hit rays use predictions")
      ->check(CLI::IsMember({"anyhit", "closest-exact", "closest-spec"}));
  for (const char* o : {"--hash", "--precision", "--exp-bits", "--origin-bits", "--dir-bits",
                        "--combine", "--table", "--tag-bits", "--nodes-per-entry"})
    a.given[o] = app->get_option(o);
}

/// --preset rtl-NAME: the RTL configuration's hash and table options, each unless given.
void apply_preset(PredictorArgs& a) {
  if (a.preset.empty()) return;
  const RtlConfig rc = rtl_config(a.preset.substr(4));  // "rtl-"
  const HashConfig& h = rc.hash;
  const TableConfig& t = rc.table;
  auto set = [&](const char* opt, auto* field, auto value) {
    if (a.given.at(opt)->count() == 0) *field = value;
  };
  set("--hash", &a.hash,
      std::string(h.variant == HashVariant::kFaithful ? "faithful" : "improved"));
  set("--precision", &a.precision, h.precision);
  set("--exp-bits", &a.exp_bits, h.exp_bits);
  set("--origin-bits", &a.origin_bits, h.origin_bits);
  set("--dir-bits", &a.dir_bits, h.dir_bits);
  set("--combine", &a.combine, std::string(h.combine == CombineMode::kXor ? "xor" : "concat"));
  set("--table", &a.table, std::to_string(t.sets) + "x" + std::to_string(t.ways));
  set("--nodes-per-entry", &a.nodes_per_entry, t.nodes_per_entry);
  set("--tag-bits", &a.tag_bits, t.tag_bits);
}

/// The parts of the predictor configuration that need no scene; prints the error.
bool parse_predictor_args(const char* cmd, const PredictorArgs& a, PredictorConfig* cfg) {
  HashConfig& h = cfg->hash;
  h.variant = a.hash == "faithful" ? HashVariant::kFaithful : HashVariant::kImproved;
  h.precision = a.precision;
  h.exp_bits = a.exp_bits;
  h.origin_bits = a.origin_bits;
  h.dir_bits = a.dir_bits;
  h.combine = a.combine == "xor" ? CombineMode::kXor : CombineMode::kConcat;
  parse_predict_mode(a.mode, &cfg->mode);
  cfg->go_up = a.go_up;
  TableConfig& t = cfg->table;
  t.nodes_per_entry = a.nodes_per_entry;
  if (a.table == "unbounded") {
    t.unbounded = true;
  } else if (!parse_wxh(a.table, &t.sets, &t.ways)) {
    std::fprintf(stderr, "hrpp %s: --table must be 'unbounded' or SETSxWAYS (e.g. 256x4), got '%s'\n",
                 cmd, a.table.c_str());
    return false;
  } else {
    if (!std::has_single_bit(t.sets)) {
      std::fprintf(stderr, "hrpp %s: --table %s: the number of sets must be a power of two\n",
                   cmd, a.table.c_str());
      return false;
    }
  }
  return true;
}

/// Completes the configuration for a scene and its BVH and validates it; prints the error.
bool finish_predictor_config(const char* cmd, const PredictorArgs& a, const Scene& scene,
                             const Bvh& bvh, PredictorConfig* cfg) {
  const std::string err =
      resolve_for_scene(scene, bvh, cfg, {.tag_bits = a.tag_bits, .tag_bits_name = "--tag-bits"});
  if (!err.empty()) {
    std::fprintf(stderr, "hrpp %s: %s\n", cmd, err.c_str());
    return false;
  }
  return true;
}

std::string predictor_line(const PredictorArgs& a, const PredictorConfig& cfg, uint64_t table_bytes,
                           uint64_t table_entries) {
  const HashConfig& h = cfg.hash;
  const TableConfig& t = cfg.table;
  char b[512];
  const std::string hash =
      h.variant == HashVariant::kFaithful
          ? "P=" + std::to_string(h.precision) + " E=" + std::to_string(h.exp_bits) + " " + a.combine
          : "origin " + std::to_string(h.origin_bits) + " bits, cell 2^" +
                std::to_string(h.origin_cell_exp) + ", dir " + std::to_string(h.dir_bits) +
                " bits " + a.combine;
  std::snprintf(b, sizeof b,
                "hash %s (%s), key %d bits, table %s (K=%u, %u-bit node ids, %llu bytes, %llu "
                "entries used), go-up %u, mode %s",
                a.hash.c_str(), hash.c_str(), h.key_bits(),
                t.unbounded ? "unbounded" : (std::to_string(t.sets) + "x" + std::to_string(t.ways)).c_str(),
                t.nodes_per_entry, t.node_bits, (unsigned long long)table_bytes,
                (unsigned long long)table_entries, cfg.go_up, a.mode.c_str());
  return b;
}

// ---- predict -----------------------------------------------------------------------------------

struct PredictArgs {
  std::string scene, json_path, stream;
  WorkloadArgs w;
  PredictorArgs p;
  // Cost of accuracy (docs/cost_model.md).
  uint32_t update_delay = 0;
  int pipeline_latency = -1;  // >= 0: update_delay from the RTL's cycle model
  bool measure_time = false;
  std::string spec_images;
  uint32_t cores = 1, threads = 1, tile = 8;  // TiledPredictor (docs/predictor.md)
};

int cmd_predict(const PredictArgs& a) {
  PredictorConfig cfg;
  if (!parse_predictor_args("predict", a.p, &cfg) || !check_workload_args("predict", a.w)) return 2;
  std::unique_ptr<RayStreamReader> stream;
  if (!a.stream.empty()) stream = std::make_unique<RayStreamReader>(a.stream);

  Scene scene = load_scene(a.scene);
  Bvh bvh = build_bvh(scene.triangles);
  if (!finish_predictor_config("predict", a.p, scene, bvh, &cfg)) return 2;
  cfg.update_delay = a.pipeline_latency >= 0 ? rtl_update_delay(uint32_t(a.pipeline_latency))
                                             : a.update_delay;
  cfg.measure_time = a.measure_time;
  WorkloadOptions wo;
  nlohmann::json workload;
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

  TiledOptions to;
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
  TiledPredictor pred(bvh, cfg, to);
  if (!a.spec_images.empty() && a.threads != 1) {
    std::fprintf(stderr, "hrpp predict: --spec-images needs --threads 1\n");
    return 2;
  }
  // The speculative image needs each ray's result: generated workloads, one thread.
  std::unique_ptr<SpecImage> spec_image;
  if (!stream && a.threads == 1)
    spec_image = std::make_unique<SpecImage>(scene, wo.width, wo.height, wo.spp);
  const uint64_t expected = stream ? stream->header().ray_count
                                   : uint64_t(wo.width) * wo.height * wo.spp;
  const char* unit = stream ? "stream rays" : "camera samples";
  uint64_t done = 0;
  auto t0 = std::chrono::steady_clock::now();
  auto last = t0;
  auto process = [&](const RayRecord& r) {
    const std::optional<RayResult> res = pred.push(r);
    if (spec_image && res) spec_image->add(r, *res);
    if ((!stream && r.kind != RayKind::kPrimary) || (++done & 0xFFFF)) return;
    auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::seconds(2)) return;
    last = now;
    double secs = std::chrono::duration<double>(now - t0).count();
    std::fprintf(stderr, "predict: %5.1f%% of %llu %s, %.2f M %s/s\n", 100.0 * done / expected,
                 (unsigned long long)expected, unit, done / secs / 1e6, unit);
  };
  if (stream) {
    RayRecord r;
    while (stream->next(&r)) process(r);
  } else {
    generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit*) { process(r); });
  }
  pred.finish();
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  nlohmann::json j = pred.to_json();
  j["scene"] = scene.path;
  j["workload"] = workload;
  if (workload.contains("resolution")) j["resolution"] = workload["resolution"];
  if (workload.contains("spp")) j["spp"] = workload["spp"];
  if (workload.contains("seed")) j["seed"] = workload["seed"];
  j["seconds"] = secs;
  j["threads"] = a.threads;
  // Cost of accuracy (docs/cost_model.md): cost-model cycles, CPU time, speculative image error.
  const CostModel cost;
  j["config"]["update_delay"] = cfg.update_delay;
  j["config"]["pipeline_latency"] = a.pipeline_latency;
  j["cost_model"] = cost.to_json();
  j["cost"] = cycle_cost_json(pred.total(), cost);
  for (int k = 0; k < kNumRayKinds; ++k)
    if (pred.by_kind(RayKind(k)).rays)
      j["by_kind"][std::string(ray_kind_name(RayKind(k)))]["cost"] =
          cycle_cost_json(pred.by_kind(RayKind(k)), cost);
  if (spec_image) {
    if (!a.spec_images.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(a.spec_images, ec);
    }
    j["image_error"] = spec_image->finish(a.spec_images);
  }
  if (stream) {
    std::printf("predict %s: rays from %s (%llu records), generated with %s\n", scene.path.c_str(),
                a.stream.c_str(), (unsigned long long)stream->header().ray_count,
                stream->header().options.c_str());
  } else {
    std::printf("predict %s: %s\n", scene.path.c_str(), workload_line(wo).c_str());
    print_effects(scene, wo, a.w.effects);
  }
  std::printf("  %s\n",
              predictor_line(a.p, cfg, pred.table_bytes(), pred.table_entries()).c_str());
  if (a.cores > 1)
    std::printf("  %u cores, each with its own table (%ux%u-pixel tiles, tile i on core i mod %u), "
                "%u threads\n", a.cores, a.tile, a.tile, a.cores, a.threads);
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
  {
    const CycleCost cc = cycle_cost(pred.total(), cost);
    std::printf("  cost model: %.1f -> %.1f cycles per ray (%.2f%% saved), update delay %u rays",
                cc.baseline / std::max<uint64_t>(1, pred.total().rays),
                cc.hrpp / std::max<uint64_t>(1, pred.total().rays), 100 * cc.saved_fraction(),
                cfg.update_delay);
    if (cfg.measure_time)
      std::printf(", CPU %.0f -> %.0f ns per ray",
                  double(pred.total().baseline_ns) / std::max<uint64_t>(1, pred.total().rays),
                  double(pred.total().hrpp_ns) / std::max<uint64_t>(1, pred.total().rays));
    if (j.contains("image_error"))
      std::printf(", image MAE %.5f, %.3f%% pixels differ",
                  j["image_error"]["mean_abs_error"].get<double>(),
                  100 * j["image_error"]["differing_pixel_fraction"].get<double>());
    std::printf("\n");
  }
  std::printf("  skipped = 1 - HRPP interior-node tests (wasted predicted tests included) / baseline; %.1f s, %.2f M rays/s\n",
              secs, pred.total().rays / secs / 1e6);
  if (pred.total().exact_mismatches) {
    std::fprintf(stderr, "hrpp predict: BUG: %llu rays answered differently from the baseline in an exact mode\n",
                 (unsigned long long)pred.total().exact_mismatches);
    return 1;
  }
  if (!a.json_path.empty() && !write_json_file(a.json_path, j)) return 2;
  return 0;
}

// ---- trace -------------------------------------------------------------------------------------

struct TraceArgs {
  std::string scene, out, json_path;
  WorkloadArgs w;
};

int cmd_trace(const TraceArgs& a) {
  if (!check_workload_args("trace", a.w)) return 2;
  Scene scene = load_scene(a.scene);
  Bvh bvh = build_bvh(scene.triangles);
  WorkloadOptions wo;
  if (!make_workload("trace", a.w, scene, &wo)) return 2;
  nlohmann::json options = workload_json(scene, wo);
  options["effects_spec"] = a.w.effects;
  options["generator"] = "hrpp trace";
  StreamHeader header;
  header.scene_fingerprint = scene_fingerprint(scene);
  header.options = options.dump();
  std::printf("trace %s: %s\n", scene.path.c_str(), workload_line(wo).c_str());
  print_effects(scene, wo, a.w.effects);

  auto t0 = std::chrono::steady_clock::now();
  RayStreamWriter writer(a.out, header);
  std::array<uint64_t, kNumRayKinds> by_kind{};
  generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit*) {
    writer.write(r);
    by_kind[static_cast<int>(r.kind)]++;
  });
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
              (unsigned long long)writer.count(), counts.c_str(),
              (64.0 * writer.count()) / 1e6, secs);
  if (!a.json_path.empty()) {
    nlohmann::json j = {{"stream", a.out},
                        {"scene", scene.path},
                        {"scene_fingerprint", header.scene_fingerprint},
                        {"options", options},
                        {"effects", describe_effects(scene, wo, a.w.effects)},
                        {"rays", writer.count()},
                        {"by_kind", jk},
                        {"seconds", secs}};
    if (!write_json_file(a.json_path, j)) return 2;
  }
  return 0;
}

// ---- render ------------------------------------------------------------------------------------

struct RenderArgs {
  std::string scene, out;
  WorkloadArgs w;
  PredictorArgs p;
};

int cmd_render(const RenderArgs& a) {
  PredictorConfig cfg;
  if (!parse_predictor_args("render", a.p, &cfg) || !check_workload_args("render", a.w)) return 2;
  std::error_code ec;
  std::filesystem::create_directories(a.out, ec);
  if (ec || !std::filesystem::is_directory(a.out)) {
    std::fprintf(stderr, "hrpp render: cannot create the output directory %s: %s\n", a.out.c_str(),
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
  const RenderOutput out = render_all(scene, bvh, wo, cfg, a.out);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& s = out.summary;
  std::printf("  shaded: exposure %.4g, %.1f%% of surface samples lit\n",
              s["shaded"]["exposure"].get<double>(), 100 * s["shaded"]["lit_fraction"].get<double>());
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

  PredictArgs pa;
  auto* pr = app.add_subcommand("predict", "Run the HRPP predictor over a scene's rays and report "
                                           "skipped work, precision and recall per ray kind");
  pr->add_option("scene", pa.scene, "glTF scene (.glb or .gltf)")->required();
  add_predictor_options(pr, pa.p);
  std::vector<CLI::Option*> wopts = add_workload_options(pr, pa.w, "shadow,ao");
  wopts.push_back(pr->add_flag("!--no-shadow", pa.w.shadow, "do not trace shadow rays"));
  wopts.push_back(pr->add_flag("!--no-ao", pa.w.ao, "do not trace ambient-occlusion rays"));
  auto* stream_opt = pr->add_option("--stream", pa.stream,
                                    "read the rays from this ray-stream file (hrpp trace) instead "
                                    "of generating them");
  for (CLI::Option* o : wopts) stream_opt->excludes(o);
  pr->add_option("--json", pa.json_path, "write the report as JSON to this file");
  auto* delay_opt = pr->add_option("--update-delay", pa.update_delay,
                                   "rays looked up between a ray's lookup and its table write "
                                   "(0: the untimed model; docs/cost_model.md)");
  pr->add_option("--pipeline-latency", pa.pipeline_latency,
                 "traversal-engine walk latency in cycles: the update delay is the RTL's, from "
                 "the cycle model (docs/cost_model.md)")
      ->check(CLI::Range(0, 1 << 20))
      ->excludes(delay_opt);
  pr->add_flag("--measure-time", pa.measure_time,
               "measure the CPU time per ray of the baseline walk and of HRPP's work");
  pr->add_option("--spec-images", pa.spec_images,
                 "write DIR/spec_compare.png: exact | predictor's answers | difference "
                 "(primary rays)")
      ->excludes(stream_opt);

  pr->add_option("--cores", pa.cores,
                 "predictor cores, each with its own table; image tile i goes to core i mod "
                 "cores (the statistics depend on it, not on --threads)")
      ->check(CLI::Range(1u, 4096u))
      ->capture_default_str();
  pr->add_option("--threads", pa.threads, "worker threads that run the cores")
      ->check(CLI::Range(1u, 1024u))
      ->capture_default_str();
  pr->add_option("--core-tile", pa.tile, "edge in pixels of the image tiles assigned to cores")
      ->check(CLI::Range(1u, 65536u))
      ->capture_default_str();

  // sweep: the Python driver (model/tools/sweep.py) in the project's venv.
  std::vector<std::string> sweep_args;
  auto* sw = app.add_subcommand("sweep", "Sweep predictor parameters over scenes: CSV, Pareto "
                                         "fronts, plots (model/tools/sweep.py --help)");
  sw->allow_extras();
  sw->prefix_command();
  sw->set_help_flag();

  TraceArgs ta;
  auto* tr = app.add_subcommand("trace", "Generate a scene's ray workload and write it as a "
                                         "ray-stream file (docs/ray_stream.md)");
  tr->add_option("scene", ta.scene, "glTF scene (.glb or .gltf)")->required();
  add_workload_options(tr, ta.w, "auto");
  tr->add_option("--out", ta.out, "ray-stream file to write")->required();
  tr->add_option("--json", ta.json_path, "also write a summary (effects, ray counts) as JSON");

  RenderArgs ra;
  auto* rd = app.add_subcommand("render", "Write PNG pictures: the shaded scene and per-pixel heat "
                                          "maps of traversal work and predictor outcomes");
  rd->add_option("scene", ra.scene, "glTF scene (.glb or .gltf)")->required();
  rd->add_option("--out", ra.out, "output directory (created if missing)")->required();
  add_workload_options(rd, ra.w, "shadow,ao");
  add_predictor_options(rd, ra.p);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (*info) return cmd_info(scene, leaf_size, json_path);
    if (*ce) return cmd_check_embree(scene, rays, kind, seed, config, json_path);
    if (*pr) {
      apply_preset(pa.p);
      return cmd_predict(pa);
    }
    if (*tr) return cmd_trace(ta);
    if (*rd) {
      apply_preset(ra.p);
      return cmd_render(ra);
    }
    if (*sw) {
      std::vector<std::string> args = {HRPP_PYTHON, HRPP_SOURCE_DIR "/model/tools/sweep.py",
                                       "--hrpp", "/proc/self/exe"};
      for (const std::string& e : sw->remaining()) args.push_back(e);
      char self[4096];
      const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
      if (n > 0) args[3] = std::string(self, size_t(n));
      std::vector<char*> argv2;
      for (std::string& s : args) argv2.push_back(s.data());
      argv2.push_back(nullptr);
      execv(argv2[0], argv2.data());
      std::fprintf(stderr, "hrpp sweep: cannot run %s: %s (run `make setup`)\n", HRPP_PYTHON,
                   std::strerror(errno));
      return 2;
    }
  } catch (const SceneError& e) {
    std::fprintf(stderr, "hrpp: %s\n", e.what());
    return 2;
  } catch (const StreamError& e) {
    std::fprintf(stderr, "hrpp: %s\n", e.what());
    return 2;
  } catch (const RenderError& e) {
    std::fprintf(stderr, "hrpp: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrpp: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
