// The RTL's named configurations and pipeline latencies, from their one definition
// (rtl/config/hrpp_configs.json; the build generates hrpp/rtl_config_data.h from it). The golden
// model's own defaults (HashConfig, TableConfig) are not an RTL configuration: `hrpp predict`
// without options runs the study's faithful hash on an unbounded table; `--preset rtl-NAME`
// selects one of these.
#pragma once

#include <bit>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/predictor/hash.h"
#include "hrpp/predictor/pred_table.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/rtl_config_data.h"

namespace hrpp {

/// One RTL configuration: every hrpp_top parameter, as the golden model's pieces.
struct RtlConfig {
  std::string name;
  /// The hash; origin_cell_exp is the scene's (cfg_cell_exp_i), left 0 here.
  HashConfig hash;
  /// The finite table; node_bits = the RTL's node-id width, key_bits = the hash's key width.
  TableConfig table;
  int node_id_width = 0;  // NodeIdWidth
  int id_width = 0;       // IdWidth: ray ids
  int pred_fifo_depth = 0, skip_fifo_depth = 0, update_queue_depth = 0;
  bool key_store_bram = false;  // KeyStoreBram: one cycle more of decision and update latency
  bool inject_fault = false;    // test only (the "mutant" configuration)
  int lanes = 1;                // lookups and updates per cycle: 1 (hrpp_top), 2 or 4 (hrpp_lanes)
  bool any_hit_only = false;    // predict_kinds "any-hit": the unit offers any-hit rays only
  bool issue_reg = false;       // IssueReg: the table's issue register, one cycle more of update
  bool key_store_reg = false;   // KeyStoreReg: the key store's read register, one cycle more of
                                // decision and update latency (with key_store_bram)

  /// The latencies of this configuration (docs/microarchitecture.md, "Declared latencies"): the
  /// declared ones, one cycle more with the key store in block RAM (its registered read) and one
  /// more with its read register, and one cycle more of update latency with the table's issue
  /// register. The rule is written once, in pyhrpp.rtl_config.latencies(); the generator writes
  /// each configuration's figures into rtl::ConfigData, and tb_hrpp --latency (ctest
  /// tb.latency.<config>) measures them at the RTL's and the cycle model's ports.
  int prediction_latency() const { return latencies.prediction; }
  int decision_latency() const { return latencies.decision; }
  int update_write_latency() const { return latencies.update_write; }
  int update_landing() const { return latencies.update_landing; }
  struct {
    int prediction = 0, decision = 0, update_write = 0, update_landing = 0;
  } latencies;

  /// "improved hash 5/3 concat, 128x8 table, K=2, 8-bit tags" (faithful: "P=6 E=3"; the
  /// octahedral direction code: "improved hash 3/3 oct concat").
  std::string describe() const {
    const std::string h = hash.variant == HashVariant::kImproved
                              ? "improved hash " + std::to_string(hash.origin_bits) + "/" +
                                    std::to_string(hash.dir_bits) +
                                    (hash.dir_code == DirCode::kOct ? " oct" : "")
                              : "faithful hash P=" + std::to_string(hash.precision) +
                                    " E=" + std::to_string(hash.exp_bits);
    return h + (hash.combine == CombineMode::kConcat ? " concat, " : " xor, ") +
           std::to_string(table.sets) + "x" + std::to_string(table.ways) +
           " table, K=" + std::to_string(table.nodes_per_entry) + ", " +
           std::to_string(table.tag_bits) + "-bit tags" +
           (lanes > 1 ? ", " + std::to_string(lanes) + " lanes" : "") +
           (table.conf_bits > 0 ? ", confidence bit" : "");
  }
  /// The predictor of this configuration (go-up 0, closest-exact mode).
  PredictorConfig predictor() const {
    PredictorConfig p;
    p.hash = hash;
    p.table = table;
    return p;
  }
  /// The cycle model of this configuration in `mode`.
  CycleConfig cycle(PredictMode mode) const {
    CycleConfig c;
    c.hash = hash;
    c.table = table;
    c.mode = mode;
    c.id_bits = id_width;
    c.pred_fifo_depth = pred_fifo_depth;
    c.skip_fifo_depth = skip_fifo_depth;
    c.update_queue_depth = update_queue_depth;
    c.key_store_bram = key_store_bram;
    c.key_store_reg = key_store_reg;
    c.issue_reg = issue_reg;
    c.lanes = lanes;
    return c;
  }
  /// The cycle model of this configuration in `mode` for a scene: the scene's cell exponent, and
  /// the RTL's node-id and tag widths checked against the BVH. Returns "" or what does not fit.
  std::string cycle_for_scene(PredictMode mode, const Scene& scene, const Bvh& bvh,
                              CycleConfig* cc) const {
    *cc = cycle(mode);
    const std::string err =
        resolve_for_scene(scene, bvh, &cc->hash, &cc->table,
                          {.node_bits = node_id_width, .tag_bits = table.tag_bits});
    return err.empty() ? cc->validate() : err;
  }
};

inline RtlConfig make_rtl_config(const rtl::ConfigData& d) {
  RtlConfig c;
  c.name = d.name;
  c.hash.variant = d.variant;
  c.hash.precision = d.precision;
  c.hash.exp_bits = d.exp_bits;
  c.hash.origin_bits = d.origin_bits;
  c.hash.dir_bits = d.dir_bits;
  c.hash.combine = d.combine;
  c.hash.dir_code = d.dir_code;
  c.hash.index_bits = std::countr_zero(d.sets);
  c.table.sets = d.sets;
  c.table.ways = d.ways;
  c.table.nodes_per_entry = d.nodes_per_entry;
  c.table.tag_bits = d.tag_bits;
  c.table.conf_bits = d.confidence_bits;  // 0 or 1 (the generator refuses more), threshold 1
  c.any_hit_only = d.any_hit_only;
  c.table.conf_threshold = 1;
  c.table.node_bits = d.node_id_width;
  c.table.key_bits = c.hash.key_bits();
  c.node_id_width = d.node_id_width;
  c.id_width = d.id_width;
  c.pred_fifo_depth = d.pred_fifo_depth;
  c.skip_fifo_depth = d.skip_fifo_depth;
  c.update_queue_depth = d.update_queue_depth;
  c.key_store_bram = d.key_store_bram;
  c.inject_fault = d.inject_fault;
  c.lanes = int(d.lanes);
  c.issue_reg = d.issue_reg;
  c.key_store_reg = d.key_store_reg;
  c.latencies = {d.prediction_latency, d.decision_latency, d.update_write_latency,
                 d.update_landing};
  return c;
}

/// The names of the RTL configurations, in the file's order.
inline std::vector<std::string> rtl_config_names() {
  std::vector<std::string> names;
  for (const rtl::ConfigData& d : rtl::kConfigs) names.emplace_back(d.name);
  return names;
}

/// The named RTL configuration ("small", "default", "large", "mobile", "mutant", ...); throws
/// std::invalid_argument naming the known ones.
inline RtlConfig rtl_config(std::string_view name) {
  for (const rtl::ConfigData& d : rtl::kConfigs)
    if (name == d.name) return make_rtl_config(d);
  std::string known;
  for (const std::string& n : rtl_config_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown RTL configuration '" + std::string(name) +
                              "' (known: " + known + ")");
}

}  // namespace hrpp
