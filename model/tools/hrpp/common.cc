// hrpp CLI: the shared options and helpers (common.h).
#include "common.h"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>

#include "hrpp/predictor/presets.h"
#include "hrpp/util/atomic_file.h"
#include "hrpp/util/cli.h"
#include "hrpp/util/version.h"

namespace hrpp::cli {
namespace {

int json_stdout_fd = -1;  // --json -: the process's standard output, kept for the JSON

}  // namespace

bool write_json_file(const std::string& path, const nlohmann::json& j) {
  const std::string text = j.dump(2) + "\n";
  if (path == "-") {
    std::fflush(stdout);
    const int fd = json_stdout_fd >= 0 ? json_stdout_fd : STDOUT_FILENO;
    for (size_t done = 0; done < text.size();) {
      const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        std::fprintf(stderr, "hrpp: --json -: cannot write to standard output: %s\n",
                     std::strerror(errno));
        return false;
      }
      done += size_t(n);
    }
    return true;
  }
  try {
    write_file_atomic(path, text);
  } catch (const AtomicFileError& e) {
    std::fprintf(stderr, "hrpp: %s\n", e.what());
    return false;
  }
  return true;
}

namespace {

/// Why PATH cannot be made a folder (created with its missing parents), or "" when it can.
std::string output_folder_problem(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) return "the folder name is empty";
  std::error_code ec;
  if (fs::exists(path, ec)) {
    if (!fs::is_directory(path, ec)) return "'" + path + "' is a file, not a folder";
    if (::access(path.c_str(), W_OK | X_OK) != 0)
      return "the folder '" + path + "' is not writable: " + std::strerror(errno);
    return "";
  }
  // The nearest existing folder above it must take the missing ones.
  fs::path p = fs::path(path).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();
  for (fs::path up = p.parent_path();; up = up.parent_path()) {
    const fs::path dir = up.empty() ? fs::path(".") : up;
    if (fs::exists(dir, ec)) {
      if (!fs::is_directory(dir, ec)) return "'" + dir.string() + "' is not a folder";
      if (::access(dir.c_str(), W_OK | X_OK) != 0)
        return "the folder '" + dir.string() + "' is not writable: " + std::strerror(errno);
      return "";
    }
    if (up.empty() || up == up.parent_path()) return "no existing folder above it";
  }
}

}  // namespace

bool check_output_path(const char* cmd, const char* option, const std::string& path,
                       OutputKind kind) {
  std::string why;
  if (path == "-")
    why = kind == OutputKind::kJson ? "" : "standard output is not supported for this option";
  else
    why = kind == OutputKind::kFolder ? output_folder_problem(path) : output_file_problem(path);
  if (!why.empty()) {
    std::fprintf(stderr, "hrpp %s: %s %s: %s\n", cmd, option, path.c_str(), why.c_str());
    return false;
  }
  if (path == "-" && json_stdout_fd < 0) {
    // The JSON alone on standard output; the text report goes to standard error.
    std::fflush(stdout);
    json_stdout_fd = ::dup(STDOUT_FILENO);
    if (json_stdout_fd < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
      std::fprintf(stderr, "hrpp %s: %s -: cannot redirect standard output: %s\n", cmd, option,
                   std::strerror(errno));
      return false;
    }
  }
  return true;
}

namespace {

std::string command_line_text, start_timestamp;

/// ARG as a POSIX shell reads it back: as is when it holds only safe characters, else in single
/// quotes (a quote inside as '\'').
std::string shell_quote(const std::string& arg) {
  const bool safe = !arg.empty() && arg.find_first_not_of(
                                        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                        "0123456789_-+=.,/:@%") == std::string::npos;
  if (safe) return arg;
  std::string q = "'";
  for (char c : arg) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

void set_command_line(int argc, char** argv) {
  command_line_text.clear();
  for (int i = 0; i < argc; ++i) command_line_text += (i ? " " : "") + shell_quote(argv[i]);
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char b[32];
  std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", &utc);
  start_timestamp = b;
}

nlohmann::json tool_json() {
  return {{"name", "hrpp"},
          {"version", project_version()},
          {"git_commit", git_commit()},
          {"command_line", command_line_text},
          {"timestamp", start_timestamp}};
}

void null_unmeasured_times(nlohmann::json* j) {
  if (j->is_object()) {
    for (auto& [k, v] : j->items()) {
      if (k == "baseline_ns" || k == "hrpp_ns")
        v = nullptr;
      else
        null_unmeasured_times(&v);
    }
  } else if (j->is_array()) {
    for (nlohmann::json& v : *j) null_unmeasured_times(&v);
  }
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

// ---- the BVH (simulate, predict, trace, check-embree, exactness, info) -----------------------

CLI::Option* add_bvh_option(CLI::App* app, std::string& name) {
  return app
      ->add_option("--bvh", name,
                   "BVH builder: 'sah' (ours: binned SAH, up to 4 triangles per leaf) or "
                   "'micro21-sbvh' (MICRO 2021's simulator's: Embree's spatial-split SAH, up to "
                   "32; docs/bvh.md)")
      ->check(CLI::IsMember({std::string(bvh_builder_name(BvhBuilder::kSah)),
                             std::string(bvh_builder_name(BvhBuilder::kMicro21Sbvh))}))
      ->capture_default_str();
}

BvhBuildOptions bvh_build_options(const std::string& name) {
  BvhBuildOptions o;
  parse_bvh_builder(name, &o.builder);  // checked by CLI11
  return o;
}

nlohmann::json bvh_json(const Bvh& bvh) {
  const BvhStats& s = bvh.stats;
  return {{"builder", bvh_builder_name(bvh.options.builder)},
          {"nodes", s.nodes},
          {"interior", s.interior},
          {"leaves", s.leaves},
          {"references", s.references},
          {"max_depth", s.max_depth},
          {"mean_leaf_depth", s.mean_leaf_depth},
          {"leaf_size_histogram", s.leaf_size_histogram},
          {"sah_cost", s.sah_cost},
          {"max_leaf_size", bvh.options.max_leaf_size},
          {"bins", bvh.options.bins},
          {"memory_bytes", bvh.memory_bytes()}};
}

std::string bvh_line(const Bvh& bvh) {
  if (bvh.options.builder == BvhBuilder::kSah) return "";
  const BvhStats& s = bvh.stats;
  char b[256];
  std::snprintf(b, sizeof b,
                "  bvh %s (MICRO 2021's: Embree's spatial-split SAH): %u nodes, %u leaves, %u "
                "triangle references, depth max %u, SAH cost %.2f\n",
                std::string(bvh_builder_name(bvh.options.builder)).c_str(), s.nodes, s.leaves,
                s.references, s.max_depth, s.sah_cost);
  return b;
}

// ---- workload options (trace, predict, render) -----------------------------------------------

/// Adds the workload options; returns them (so that --stream can exclude them).
std::vector<CLI::Option*> add_workload_options(CLI::App* app, WorkloadArgs& a,
                                               const std::string& default_effects) {
  a.effects = default_effects;
  std::vector<CLI::Option*> o;
  o.push_back(app->add_option("--workload", a.workload,
                              "where the rays come from: 'camera' (camera rays and the secondary "
                              "rays of their hits), 'micro21-ao' (MICRO 2021's AO benchmark: no "
                              "camera, one AO ray per triangle; docs/workloads.md) or "
                              "'micro21-ao-sorted' (the same rays in its ray-sorting order)")
                  ->check(CLI::IsMember({"camera", "micro21-ao", "micro21-ao-sorted"}))
                  ->capture_default_str());
  o.push_back(app->add_option("--ao-normal", a.ao_normal,
                              "MICRO 2021's AO workloads: the hemisphere about the triangle's "
                              "normal as wound, or about its opposite (flipped; docs/workloads.md)")
                  ->check(CLI::IsMember({"wound", "flipped"}))
                  ->capture_default_str());
  o.push_back(app->add_option("--effects", a.effects,
                              "'auto' (what the scene's lights and materials call for), 'none', or "
                              "a comma-separated list of shadow, ao, reflection, refraction, "
                              "diffuse, auto (docs/workloads.md)")
                  ->capture_default_str());
  o.push_back(app->add_option("--res", a.res, "image resolution WxH (default: the camera's)"));
  o.push_back(app->add_option("--spp", a.spp, "samples per pixel")
                  ->check(CLI::Range(1, 4096))
                  ->capture_default_str());
  o.push_back(app->add_option("--order", a.order, "ray issue order")
                  ->check(CLI::IsMember({"scanline", "tiled", "morton"}))
                  ->capture_default_str());
  o.push_back(app->add_option("--tile", a.tile, "tile edge in pixels (tiled and morton orders)")
                  ->check(CLI::Range(1, 4096))
                  ->capture_default_str());
  o.push_back(
      app->add_option("--depth", a.depth, "generations of reflection / refraction / diffuse rays")
          ->check(CLI::Range(0, 16))
          ->capture_default_str());
  o.push_back(
      app->add_option("--seed", a.seed, "random seed of the ray generator")->capture_default_str());
  o.push_back(app->add_option("--ao-distance", a.ao_distance,
                              "AO ray length (default or 0: 5% of the scene diagonal; 'inf': "
                              "unbounded, as in the MICRO 2021 study)")
                  ->check(CLI::Validator(
                      [](std::string& v) -> std::string {
                        double d = 0;  // CLI11's NonNegativeNumber stops at DBL_MAX
                        if (CLI::detail::lexical_cast(v, d) && d >= 0) return {};
                        return "must be a number >= 0 or 'inf', got " + v;
                      },
                      "NONNEGATIVE or inf")));
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
  if (a.workload != "camera" &&
      (!a.res.empty() || a.spp != 1 || a.order != "scanline" || a.ao_distance != 0.f)) {
    std::fprintf(stderr,
                 "hrpp %s: --workload %s has no camera and its own AO rays (one per "
                 "triangle, unbounded): --res, --spp, --order and --ao-distance do not apply\n",
                 cmd, a.workload.c_str());
    return false;
  }
  if (a.workload == "camera" && a.ao_normal != "wound") {
    std::fprintf(stderr,
                 "hrpp %s: --ao-normal applies to MICRO 2021's AO workloads (--workload "
                 "micro21-ao or micro21-ao-sorted); the camera's AO rays sample about the hit's "
                 "normal facing the ray\n",
                 cmd);
    return false;
  }
  if (std::isnan(a.ao_distance)) {  // CLI11's NonNegativeNumber lets NaN through; +inf is fine
    std::fprintf(stderr, "hrpp %s: --ao-distance must be a number >= 0 or 'inf', got %g\n", cmd,
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
  parse_workload_source(a.workload, &wo->source);  // checked by CLI11
  wo->micro21_flip = a.ao_normal == "flipped";
  if (is_micro21_ao(wo->source)) {  // AO rays only
    wo->shadow = wo->reflection = wo->refraction = wo->diffuse = false;
    wo->ao = true;
  }
  return true;
}

/// "512x512, 1 spp, seed 1, scanline order, depth 2"
std::string workload_line(const WorkloadOptions& wo) {
  if (is_micro21_ao(wo.source))
    return std::string(workload_source_name(wo.source)) +
           ": one AO ray per triangle (MICRO 2021's benchmark" +
           (wo.source == WorkloadSource::kMicro21AoSorted ? ", sorted by its ray-sorting key"
                                                          : "") +
           (wo.micro21_flip ? ", about the flipped normal" : "") + "), seed " +
           std::to_string(wo.seed);
  std::string order(ray_order_name(wo.order));
  if (wo.order != RayOrder::kScanline)
    order += " (" + std::to_string(wo.tile) + "x" + std::to_string(wo.tile) + " tiles)";
  return std::to_string(wo.width) + "x" + std::to_string(wo.height) + ", " +
         std::to_string(wo.spp) + " spp, seed " + std::to_string(wo.seed) + ", " + order +
         " order, depth " + std::to_string(wo.max_depth);
}

void print_effects(const Scene& scene, const WorkloadOptions& wo, const std::string& spec) {
  if (is_micro21_ao(wo.source)) {
    std::printf("effects: AO rays only (--workload %s; --effects does not apply)\n",
                std::string(workload_source_name(wo.source)).c_str());
    return;
  }
  std::printf("effects (--effects %s):\n", spec.c_str());
  for (const std::string& l : describe_effects(scene, wo, spec)) std::printf("  %s\n", l.c_str());
}

// ---- predictor options (predict, render) -----------------------------------------------------

void add_predictor_options(CLI::App* app, PredictorArgs& a,
                           const std::vector<std::string>& extra_presets) {
  std::vector<std::string> presets = extra_presets;
  for (const std::string& n : preset_names()) presets.push_back(n);
  const std::string names = [&] {
    std::string n;
    for (const std::string& p : presets) n += (n.empty() ? "" : ", ") + p;
    return n;
  }();
  app->add_option("--preset", a.preset,
                  "a named predictor: rtl-NAME (an RTL configuration's hash and table, "
                  "rtl/config/hrpp_configs.json), micro21 (MICRO 2021's predictor: grid-spherical "
                  "hash, 256x4 table, K=1, go-up 3, any-hit rays only) or study2019 (faithful "
                  "P=6 E=3 xor, unbounded table, K=2, go-up 0); or FILE.json, one's own (a JSON "
                  "object of option names and values, e.g. {\"name\": \"mine\", \"preset\": "
                  "\"rtl-primary\", \"go_up\": 1}); the options below override it. Default: "
                  "rtl-default unless a hash or table option is given")
      ->check(CLI::Validator(
          [presets, names](std::string& v) -> std::string {
            if (v.ends_with(".json") ||
                std::find(presets.begin(), presets.end(), v) != presets.end())
              return "";
            const std::string c = closest(v, presets);
            return "'" + v + "' is neither a preset (" + names + ") nor a .json file" +
                   (c.empty() ? "" : "; did you mean " + c + "?");
          },
          [&] {  // as CLI::IsMember shows its names, so that scripts can read them
            std::string d;
            for (const std::string& p : presets) d += (d.empty() ? "{" : ",") + p;
            return d + "}|FILE.json";
          }()));
  app->add_option("--hash", a.hash, "hash variant (micro21: MICRO 2021's grid-spherical hash)")
      ->check(CLI::IsMember({"faithful", "improved", "micro21"}))
      ->capture_default_str();
  app->add_option("--precision", a.precision, "faithful hash: mantissa bits per component (P)")
      ->check(CLI::Range(1, 23))
      ->capture_default_str();
  app->add_option("--exp-bits", a.exp_bits, "faithful hash: top exponent bits per component (E)")
      ->check(CLI::Range(0, 8))
      ->capture_default_str();
  app->add_option("--origin-bits", a.origin_bits,
                  "improved and micro21 hashes: bits per origin axis")
      ->check(CLI::Range(1, 16))
      ->capture_default_str();
  app->add_option("--dir-bits", a.dir_bits,
                  "improved hash: bits per direction component; micro21: theta bits (1..8, phi "
                  "gets one more)")
      ->check(CLI::Range(1, 16))
      ->capture_default_str();
  app->add_option("--dir-code", a.dir_code,
                  "improved hash: direction code, 'grid' (each component on a uniform grid of "
                  "--dir-bits bits) or 'oct' (octahedral map onto a square, --dir-bits 1..8 per "
                  "coordinate; docs/hash.md)")
      ->check(CLI::IsMember({"grid", "oct"}))
      ->capture_default_str();
  app->add_option("--combine", a.combine, "how origin and direction fields combine")
      ->check(CLI::IsMember({"xor", "concat"}))
      ->capture_default_str();
  app->add_option("--go-up", a.go_up, "store the hit leaf's ancestor this many levels up")
      ->check(CLI::Range(0u, 64u))
      ->capture_default_str();
  app->add_option("--table", a.table, "'unbounded' or SETSxWAYS, e.g. 256x4")
      ->capture_default_str();
  app->add_option("--tag-bits", a.tag_bits,
                  "stored tag bits (default: the full tag, so keys never alias; fewer bits save "
                  "storage and let keys of one set alias)")
      ->check(CLI::Range(0, 64));
  app->add_option("--nodes-per-entry", a.nodes_per_entry, "node ids per table entry (K)")
      ->check(CLI::Range(1, kMaxNodesPerEntry))
      ->capture_default_str();
  app->add_option("--confidence-bits", a.confidence_bits,
                  "bits of the confidence counter per table way (0: none, every entry predicts; "
                  "else an entry predicts only when its counter reaches --confidence-threshold)")
      ->check(CLI::Range(0, 3))
      ->capture_default_str();
  app->add_option("--confidence-threshold", a.confidence_threshold,
                  "the counter value from which an entry predicts (1..2^bits - 1; with "
                  "--confidence-bits > 0)")
      ->check(CLI::Range(1, 7))
      ->capture_default_str();
  app->add_option("--mode", a.mode, "how closest-hit rays use predictions")
      ->check(CLI::IsMember({"anyhit", "closest-exact", "closest-spec"}))
      ->capture_default_str();
  app->add_option("--predict-kinds", a.predict_kinds,
                  "which rays use the predictor: 'all', or 'any-hit' (only rays answered as "
                  "any-hit queries; the others walk from the root with no lookup and no table "
                  "update, and count as not predicted)")
      ->check(CLI::IsMember({"all", "any-hit"}))
      ->capture_default_str();
  for (const char* o :
       {"--hash", "--precision", "--exp-bits", "--origin-bits", "--dir-bits", "--dir-code",
        "--combine", "--table", "--tag-bits", "--nodes-per-entry", "--confidence-bits",
        "--confidence-threshold", "--go-up", "--mode", "--predict-kinds"})
    a.given[o] = app->get_option(o);
}

bool option_given(const PredictorArgs& a, const std::string& option) {
  const auto it = a.given.find(option);
  return (it != a.given.end() && it->second && it->second->count() > 0) ||
         a.from_file.contains(option);
}

bool is_table_option(const std::string& option) {
  return option != "--go-up" && option != "--mode" && option != "--predict-kinds";
}

namespace {

/// The predictor option fields by option name (what a preset sets).
struct OptionField {
  std::string* text = nullptr;
  int* number = nullptr;
  uint32_t* unsigned_number = nullptr;
};
std::map<std::string, OptionField> option_fields(PredictorArgs& a) {
  return {{"--hash", {.text = &a.hash}},
          {"--precision", {.number = &a.precision}},
          {"--exp-bits", {.number = &a.exp_bits}},
          {"--origin-bits", {.number = &a.origin_bits}},
          {"--dir-bits", {.number = &a.dir_bits}},
          {"--dir-code", {.text = &a.dir_code}},
          {"--combine", {.text = &a.combine}},
          {"--table", {.text = &a.table}},
          {"--tag-bits", {.number = &a.tag_bits}},
          {"--nodes-per-entry", {.unsigned_number = &a.nodes_per_entry}},
          {"--confidence-bits", {.number = &a.confidence_bits}},
          {"--confidence-threshold", {.number = &a.confidence_threshold}},
          {"--go-up", {.unsigned_number = &a.go_up}},
          {"--mode", {.text = &a.mode}},
          {"--predict-kinds", {.text = &a.predict_kinds}}};
}

/// The named preset's values, each unless the user set the option.
void apply_named_preset(PredictorArgs& a, const std::string& name) {
  const PredictorPreset p = predictor_preset(name);
  const HashConfig& h = p.hash;
  const TableConfig& t = p.table;
  auto set = [&](const char* opt, auto* field, auto value) {
    if (!option_given(a, opt)) *field = value;
  };
  set("--hash", &a.hash, std::string(hash_variant_name(h.variant)));
  set("--precision", &a.precision, h.precision);
  set("--exp-bits", &a.exp_bits, h.exp_bits);
  set("--origin-bits", &a.origin_bits, h.origin_bits);
  set("--dir-bits", &a.dir_bits, h.dir_bits);
  set("--dir-code", &a.dir_code, std::string(dir_code_name(h.dir_code)));
  set("--combine", &a.combine, std::string(combine_mode_name(h.combine)));
  set("--table", &a.table,
      t.unbounded ? std::string("unbounded")
                  : std::to_string(t.sets) + "x" + std::to_string(t.ways));
  set("--nodes-per-entry", &a.nodes_per_entry, t.nodes_per_entry);
  set("--tag-bits", &a.tag_bits, p.tag_bits);
  set("--confidence-bits", &a.confidence_bits, t.conf_bits);
  set("--confidence-threshold", &a.confidence_threshold, t.conf_threshold);
  if (p.go_up) set("--go-up", &a.go_up, *p.go_up);
  if (p.mode) set("--mode", &a.mode, std::string(predict_mode_name(*p.mode)));
  if (p.any_hit_only)
    set("--predict-kinds", &a.predict_kinds, std::string(*p.any_hit_only ? "any-hit" : "all"));
}

/// A preset file's values (each unless given on the command line); its base preset's name in
/// *base. Prints the error and returns false.
bool read_preset_file(const char* cmd, PredictorArgs& a, std::string* base) {
  const std::string& path = a.preset_file;
  auto fail = [&](const std::string& why) {
    std::fprintf(stderr, "hrpp %s: --preset %s: %s\n", cmd, path.c_str(), why.c_str());
    return false;
  };
  std::ifstream in(path);
  if (!in) return fail(std::string("cannot read it: ") + std::strerror(errno));
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) return fail("not valid JSON");
  if (!j.is_object()) return fail("not a JSON object of option names and values");
  std::map<std::string, OptionField> fields = option_fields(a);
  std::vector<std::string> keys = {"name", "description", "preset"};
  for (const auto& [opt, f] : fields) {
    std::string k = opt.substr(2);
    std::replace(k.begin(), k.end(), '-', '_');
    keys.push_back(k);
  }
  a.label = std::filesystem::path(path).stem().string();
  for (const auto& [key, value] : j.items()) {
    if (key == "description") continue;
    if (key == "name" || key == "preset") {
      if (!value.is_string() || value.get<std::string>().empty())
        return fail("\"" + key + "\" must be a non-empty string");
      if (key == "name") a.label = value.get<std::string>();
      if (key == "preset") {
        *base = value.get<std::string>();
        const std::vector<std::string> names = preset_names();
        if (std::find(names.begin(), names.end(), *base) == names.end()) {
          const std::string c = closest(*base, names);
          return fail("\"preset\": '" + *base + "' is not a preset" +
                      (c.empty() ? "" : "; did you mean " + c + "?"));
        }
      }
      continue;
    }
    std::string opt = "--" + key;
    std::replace(opt.begin(), opt.end(), '_', '-');
    const auto f = fields.find(opt);
    if (f == fields.end()) {
      std::string k = key;
      std::replace(k.begin(), k.end(), '-', '_');
      const std::string c = closest(k, keys);
      return fail("unknown key \"" + key + "\"" + (c.empty() ? "" : "; did you mean " + c + "?"));
    }
    std::string text;
    if (value.is_string() && f->second.text) {
      text = value.get<std::string>();
    } else if (value.is_number_integer() && !f->second.text) {
      text = std::to_string(value.get<int64_t>());
    } else {
      return fail("\"" + key + "\" must be " + (f->second.text ? "a string" : "an integer"));
    }
    CLI::Option* o = a.given.at(opt);
    for (int i = 0;; ++i) {  // the command line's checks
      CLI::Validator* v = nullptr;
      try {
        v = o->get_validator(i);
      } catch (const CLI::OptionNotFound&) {
        break;
      }
      std::string t = text;
      if (const std::string e = (*v)(t); !e.empty()) return fail("\"" + key + "\": " + e);
    }
    if (option_given(a, opt)) continue;  // the command line overrides the file
    const OptionField& field = f->second;
    if (field.text) *field.text = text;
    if (field.number) *field.number = int(std::stoll(text));
    if (field.unsigned_number) *field.unsigned_number = uint32_t(std::stoll(text));
    a.from_file.insert(opt);
  }
  return true;
}

}  // namespace

nlohmann::json preset_json(const PredictorArgs& a) {
  auto or_null = [](const std::string& v) {
    return v.empty() ? nlohmann::json() : nlohmann::json(v);
  };
  return {{"name", a.label}, {"base", or_null(a.preset)}, {"file", or_null(a.preset_file)}};
}

bool table_option_set(const PredictorArgs& a) {
  for (const auto& [name, opt] : a.given)
    if (is_table_option(name) && option_given(a, name)) return true;
  return false;
}

bool resolve_preset(const char* cmd, PredictorArgs& a, const std::string& default_preset) {
  if (a.preset.ends_with(".json")) {  // its "preset", if any, becomes a.preset
    a.preset_file = a.preset;
    a.preset.clear();
    if (!read_preset_file(cmd, a, &a.preset)) return false;
  }
  // No named preset and no hash or table option (command line or file): the default preset.
  if (a.preset.empty() && !table_option_set(a)) a.preset = default_preset;
  if (!a.preset.empty() && a.preset != "none" && a.preset != "oracle")
    apply_named_preset(a, a.preset);
  if (a.label.empty()) a.label = a.preset.empty() ? "custom" : a.preset;
  return true;
}

namespace {

/// Where a value came from: "--hash improved", "--preset micro21 (hash micro21)" or "the default
/// hash faithful".
std::string origin_of(const PredictorArgs& a, const char* opt, const char* what,
                      const std::string& value) {
  if (a.from_file.contains(opt))
    return std::string(opt) + " " + value + " (--preset " + a.preset_file + ")";
  if (option_given(a, opt)) return std::string(opt) + " " + value;
  if (!a.preset.empty()) return "--preset " + a.preset + " (" + what + " " + value + ")";
  return std::string("the default ") + what + " " + value;
}

/// An option the user gave that the configuration does not use: prints which option goes with
/// which and returns false (issue 20). A preset's values never count: only what was given.
bool check_applicable(const char* cmd, const PredictorArgs& a) {
  struct Rule {
    const char* opt;
    bool applies;
    const char* needs;  // what the option goes with
    const char* what;   // the setting that rules it out
    const char* setting_opt;
    std::string value;
  };
  const bool faithful = a.hash == "faithful";
  const Rule rules[] = {
      {"--precision", faithful, "the faithful hash (--hash faithful)", "hash", "--hash", a.hash},
      {"--exp-bits", faithful, "the faithful hash (--hash faithful)", "hash", "--hash", a.hash},
      {"--origin-bits", !faithful, "the improved and micro21 hashes (--hash improved|micro21)",
       "hash", "--hash", a.hash},
      {"--dir-bits", !faithful, "the improved and micro21 hashes (--hash improved|micro21)", "hash",
       "--hash", a.hash},
      {"--dir-code", a.hash == "improved", "the improved hash (--hash improved)", "hash", "--hash",
       a.hash},
      {"--tag-bits", a.table != "unbounded", "a set-associative table (--table SETSxWAYS)", "table",
       "--table", a.table},
      {"--confidence-threshold", a.confidence_bits > 0,
       "confidence counters (--confidence-bits 1..3)", "confidence bits", "--confidence-bits",
       std::to_string(a.confidence_bits)},
  };
  for (const Rule& r : rules)
    if (!r.applies && option_given(a, r.opt)) {
      const std::string opt = a.from_file.contains(r.opt)
                                  ? std::string(r.opt) + " (--preset " + a.preset_file + ")"
                                  : std::string(r.opt);
      std::fprintf(stderr, "hrpp %s: %s applies only to %s; this run uses %s\n", cmd, opt.c_str(),
                   r.needs, origin_of(a, r.setting_opt, r.what, r.value).c_str());
      return false;
    }
  return true;
}

}  // namespace

/// The parts of the predictor configuration that need no scene; prints the error.
bool parse_predictor_args(const char* cmd, const PredictorArgs& a, PredictorConfig* cfg) {
  if (!check_applicable(cmd, a)) return false;
  HashConfig& h = cfg->hash;
  h.variant = a.hash == "faithful"  ? HashVariant::kFaithful
              : a.hash == "micro21" ? HashVariant::kMicro21
                                    : HashVariant::kImproved;
  h.precision = a.precision;
  h.exp_bits = a.exp_bits;
  h.origin_bits = a.origin_bits;
  h.dir_bits = a.dir_bits;
  h.dir_code = a.dir_code == "oct" ? DirCode::kOct : DirCode::kGrid;
  h.combine = a.combine == "xor" ? CombineMode::kXor : CombineMode::kConcat;
  parse_predict_mode(a.mode, &cfg->mode);
  cfg->go_up = a.go_up;
  cfg->any_hit_only = a.predict_kinds == "any-hit";
  TableConfig& t = cfg->table;
  t.nodes_per_entry = a.nodes_per_entry;
  t.conf_bits = a.confidence_bits;
  t.conf_threshold = a.confidence_threshold;
  if (t.conf_bits > 0 && uint32_t(t.conf_threshold) > t.conf_max()) {
    std::fprintf(stderr,
                 "hrpp %s: --confidence-threshold %d: with %d confidence bits the threshold must "
                 "be 1..%u\n",
                 cmd, t.conf_threshold, t.conf_bits, t.conf_max());
    return false;
  }
  if (a.table == "unbounded") {
    t.unbounded = true;
  } else if (!parse_wxh(a.table, &t.sets, &t.ways)) {
    std::fprintf(stderr,
                 "hrpp %s: --table must be 'unbounded' or SETSxWAYS (e.g. 256x4), got '%s'\n", cmd,
                 a.table.c_str());
    return false;
  } else {
    if (!std::has_single_bit(t.sets)) {
      std::fprintf(stderr, "hrpp %s: --table %s: the number of sets must be a power of two\n", cmd,
                   a.table.c_str());
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
  std::string hash;
  if (h.variant == HashVariant::kFaithful)
    hash =
        "P=" + std::to_string(h.precision) + " E=" + std::to_string(h.exp_bits) + " " + a.combine;
  else if (h.variant == HashVariant::kMicro21)
    hash = "origin grid " + std::to_string(h.origin_bits) + " bits over the BVH's bounds, theta " +
           std::to_string(h.dir_bits) + " / phi " + std::to_string(h.dir_bits + 1) + " bits " +
           a.combine;
  else
    hash = "origin " + std::to_string(h.origin_bits) + " bits, cell 2^" +
           std::to_string(h.origin_cell_exp) + ", dir " + std::to_string(h.dir_bits) + " bits " +
           (h.dir_code == DirCode::kOct ? "oct " : "") + a.combine;
  // kUnknownEntries: the table's size only (e.g. one table per simulated unit).
  const std::string used = table_entries == kUnknownEntries
                               ? (t.unbounded ? "" : ", " + std::to_string(table_bytes) + " bytes")
                               : ", " + std::to_string(table_bytes) + " bytes, " +
                                     std::to_string(table_entries) + " entries used";
  std::snprintf(
      b, sizeof b,
      "hash %s (%s), key %d bits, table %s (K=%u, %u-bit node ids%s), go-up %u, mode %s",
      a.hash.c_str(), hash.c_str(), h.key_bits(),
      t.unbounded ? "unbounded" : (std::to_string(t.sets) + "x" + std::to_string(t.ways)).c_str(),
      t.nodes_per_entry, t.node_bits, used.c_str(), cfg.go_up, a.mode.c_str());
  std::string line = b;
  // Only when set, so that the line of every other configuration stays as it was.
  if (t.conf_bits > 0)
    line += ", confidence " + std::to_string(t.conf_bits) + (t.conf_bits == 1 ? " bit" : " bits") +
            " (threshold " + std::to_string(t.conf_threshold) + ")";
  if (cfg.any_hit_only) line += ", any-hit rays only";
  return line;
}

}  // namespace hrpp::cli
