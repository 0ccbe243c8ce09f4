// hrpp CLI: what several subcommands share: JSON output, WxH parsing, the workload options
// (trace, predict, render) and the predictor options (predict, render), each registered on a
// CLI11 subcommand, checked and turned into the library's options, with their error messages.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "hrpp/predictor/predictor.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/workload/workload.h"

namespace hrpp::cli {

/// Writes j (indented, newline-terminated) to path atomically, or to standard output when path is
/// "-" (after check_output_path); prints the error and returns false.
bool write_json_file(const std::string& path, const nlohmann::json& j);

/// What an output option names: a file; a JSON file or "-" (standard output: the JSON goes there
/// and the text report to standard error); a folder, created (with its missing parents) if needed.
enum class OutputKind { kFile, kJson, kFolder };

/// Checks an output option before the work starts (util/cli.h's output_file_problem for files:
/// the folder exists and is writable, the path is not a folder; for a folder, the path is not a
/// file and the nearest existing folder above it is writable). Prints "hrpp CMD: OPTION PATH:
/// REASON" and returns false. For kJson "-", sends what the command prints to standard output
/// to standard error from here on, keeping standard output for the JSON.
bool check_output_path(const char* cmd, const char* option, const std::string& path,
                       OutputKind kind);

/// Records the command line and the start time for tool_json (main() calls it first).
void set_command_line(int argc, char** argv);

/// Where a JSON report came from: {"name", "version", "git_commit", "command_line" (the arguments
/// joined with shell quoting), "timestamp" (the start, UTC ISO 8601)}.
nlohmann::json tool_json();

/// Replaces what was not measured by null: every "baseline_ns" and "hrpp_ns" in j (recursively).
void null_unmeasured_times(nlohmann::json* j);

/// Parses "WxH" into two positive integers.
bool parse_wxh(const std::string& s, uint32_t* a, uint32_t* b);

// ---- the BVH (simulate, predict, trace, check-embree, exactness, info) -----------------------

/// Adds --bvh NAME (sah, micro21-sbvh: the builder, docs/bvh.md "Builders"; default sah).
CLI::Option* add_bvh_option(CLI::App* app, std::string& name);

/// The build options of --bvh NAME (a name CLI11 checked).
BvhBuildOptions bvh_build_options(const std::string& name);

/// A report's "bvh": {"builder", "max_leaf_size", "bins", the statistics (BvhStats: node counts,
/// triangle references, depths, leaf sizes, SAH cost; not the build time, so that a report's
/// figures are the same every run) and "memory_bytes"}.
nlohmann::json bvh_json(const Bvh& bvh);

/// A text report's line for a BVH other than the default (--bvh sah): "  bvh micro21-sbvh (MICRO
/// 2021's: ...): N nodes, ..."; "" for our SAH build, whose reports print no line.
std::string bvh_line(const Bvh& bvh);

// ---- workload options (trace, predict, render) -----------------------------------------------

struct WorkloadArgs {
  std::string workload = "camera", effects, order = "scanline", res;
  int spp = 1, depth = 2, tile = 8;
  uint64_t seed = 1;
  float ao_distance = 0.f;
  bool shadow = true, ao = true;    // predict's --no-shadow / --no-ao
  std::string ao_normal = "wound";  // MICRO 2021's AO workloads: wound or flipped
};

/// Adds the workload options; returns them (so that --stream can exclude them).
std::vector<CLI::Option*> add_workload_options(CLI::App* app, WorkloadArgs& a,
                                               const std::string& default_effects);

/// Checks what can be checked before the scene is loaded.
bool check_workload_args(const char* cmd, const WorkloadArgs& a);

/// The generation options for a scene; prints the error and returns false on a bad --effects.
bool make_workload(const char* cmd, const WorkloadArgs& a, const Scene& scene, WorkloadOptions* wo);

/// "512x512, 1 spp, seed 1, scanline order, depth 2"
std::string workload_line(const WorkloadOptions& wo);

/// "effects (--effects SPEC):" and one line per effect.
void print_effects(const Scene& scene, const WorkloadOptions& wo, const std::string& spec);

// ---- predictor options (predict, render) -----------------------------------------------------

struct PredictorArgs {
  std::string hash = "faithful", table = "unbounded", mode = "closest-exact", combine = "xor";
  std::string dir_code = "grid";      // improved hash: grid | oct
  std::string predict_kinds = "all";  // all | any-hit
  int precision = 6, exp_bits = 3, origin_bits = 5, dir_bits = 3;
  uint32_t go_up = 0, nodes_per_entry = 1;
  int tag_bits = -1;
  int confidence_bits = 0, confidence_threshold = 1;  // TableConfig::conf_bits, conf_threshold
  // --preset: a named preset (preset_names(): rtl-NAME, micro21, study2019) or a JSON file; after
  // resolve_preset, `preset` is the named preset in effect (a file's base "preset", or empty),
  // `preset_file` the file and `label` what reports call the configuration.
  std::string preset, preset_file, label;
  std::map<std::string, CLI::Option*> given;  // the options a preset sets, by name
  std::set<std::string> from_file;            // the options the preset file set
};

/// Adds the predictor options; --preset takes rtl-NAME, the extra names and FILE.json.
void add_predictor_options(CLI::App* app, PredictorArgs& a,
                           const std::vector<std::string>& extra_presets = {});

/// Applies --preset, in this order of precedence: the options given on the command line, a
/// preset file's values (a JSON object: option names as keys, e.g. {"name": "mine", "preset":
/// "rtl-primary", "go_up": 1}; "preset" names the named preset it starts from), the named
/// preset's values (predictor_preset), the defaults. Without --preset and without a hash or table
/// option, `default_preset` applies (the tools' default: rtl-default). Prints "hrpp CMD: ..." and
/// returns false for a preset file that cannot be read or holds an unknown key or a bad value.
bool resolve_preset(const char* cmd, PredictorArgs& a,
                    const std::string& default_preset = "rtl-default");

/// A report's "preset": {"name" (what reports call it), "base" (the named preset, or null),
/// "file" (the preset file, or null)}.
nlohmann::json preset_json(const PredictorArgs& a);

/// Whether OPTION ("--hash") was set by the user: on the command line or in a preset file.
bool option_given(const PredictorArgs& a, const std::string& option);

/// Whether a hash or table option (is_table_option) was set, on the command line or in a file.
bool table_option_set(const PredictorArgs& a);

/// The options that choose the hash and the table (an RTL configuration fixes them; go-up, mode
/// and the ray kinds that use the predictor are the traversal engine's choices).
bool is_table_option(const std::string& option);

/// The parts of the predictor configuration that need no scene; prints the error.
bool parse_predictor_args(const char* cmd, const PredictorArgs& a, PredictorConfig* cfg);

/// Completes the configuration for a scene and its BVH and validates it; prints the error.
bool finish_predictor_config(const char* cmd, const PredictorArgs& a, const Scene& scene,
                             const Bvh& bvh, PredictorConfig* cfg);

constexpr uint64_t kUnknownEntries = ~0ull;
/// "hash faithful (P=6 E=3 xor), key ... bits, table ..., go-up 0, mode closest-exact"
std::string predictor_line(const PredictorArgs& a, const PredictorConfig& cfg, uint64_t table_bytes,
                           uint64_t table_entries);

}  // namespace hrpp::cli
