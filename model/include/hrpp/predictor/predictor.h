// The untimed HRPP predictor model: hash, table lookup, predicted subtree walks, verification and
// table update, with the baseline walk run beside it for the counters (docs/predictor.md).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <nlohmann/json.hpp>
#include <string>

#include "hrpp/predictor/hash.h"
#include "hrpp/predictor/pred_table.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/trace/ray.h"
#include "hrpp/trace/traverse.h"
#include "hrpp/workload/workload.h"

namespace hrpp {

/// How rays of closest-hit kinds are answered. Any-hit kinds (shadow, AO) always use the
/// any-hit scheme.
enum class PredictMode : uint8_t {
  kAnyHit = 0,        // every ray is an any-hit query (the study's "hit-any" column)
  kClosestExact = 1,  // a predicted hit shrinks tfar, then the full walk runs: exact
  kClosestSpec = 2,   // a predicted hit is accepted as the answer: speculative
};
const char* predict_mode_name(PredictMode m);
bool parse_predict_mode(const std::string& s, PredictMode* out);

struct PredictorConfig {
  HashConfig hash;
  TableConfig table;
  uint32_t go_up = 0;  // L: the stored node is the hit leaf's L-th ancestor
  PredictMode mode = PredictMode::kClosestExact;
  /// Only rays answered as any-hit queries use the predictor (MICRO 2021 predicts any-hit rays
  /// only). The others are answered by a plain walk from the root: no lookup, no predicted walk,
  /// no table update; they count as rays that were not predicted (a false negative when they hit,
  /// else a true negative) and in `unoffered_rays`.
  bool any_hit_only = false;
  /// Rays issued between a ray's lookup and the table write of its outcome (0: the untimed
  /// model, where the next ray sees the write). A pipelined unit has many rays in flight, so
  /// later rays look up a staler table (docs/cost_model.md, "Pipeline latency").
  uint32_t update_delay = 0;
  /// Measure the CPU time of the baseline walk and of HRPP's work per ray (baseline_ns, hrpp_ns).
  bool measure_time = false;
};

/// Choices resolve_for_scene leaves to its caller.
struct ResolveOptions {
  int node_bits = 0;  // node-id width: 0 for the narrowest that names every node of the BVH
                      // (node_bits_for), else this width (a fixed RTL width), checked to suffice
  int tag_bits = -1;  // stored tag width: < 0 for the hash's full tag, else this many bits
  const char* tag_bits_name = "the stored tag width";  // names tag_bits in the error message
};

/// Completes a hash and table configuration for a scene and its BVH, and validates it: the
/// improved hash's origin cell exponent from the scene's bounds (cell_exp_for), the hash's index
/// width from the table's sets (0 for the unbounded table), the table's key width, node-id width
/// and stored tag width (none for the unbounded table). Returns "" or what is wrong. Every tool
/// that runs a predictor on a scene (hrpp, hrpp_bench, tb_hrpp) resolves its configuration here.
std::string resolve_for_scene(const Scene& scene, const Bvh& bvh, HashConfig* hash,
                              TableConfig* table, const ResolveOptions& opt = {});
inline std::string resolve_for_scene(const Scene& scene, const Bvh& bvh, PredictorConfig* cfg,
                                     const ResolveOptions& opt = {}) {
  return resolve_for_scene(scene, bvh, &cfg->hash, &cfg->table, opt);
}

struct PredictStats {
  uint64_t rays = 0, invalid_rays = 0;
  Counters baseline;   // full walks from the root
  Counters hrpp;       // predicted subtree walks + full walks when needed
  Counters predicted;  // the predicted subtree walks alone
  Counters wasted;     // predicted subtree walks of rays whose prediction failed
  uint64_t true_positive = 0, false_positive = 0, false_negative = 0, true_negative = 0;
  uint64_t skipped_walks = 0;  // rays that needed no walk from the root
  // Answers that are not the closest hit a closest-hit ray asked for: closest-spec answers that
  // differ from the baseline, and closest-hit rays answered as any-hit queries (any-hit mode)
  // whose answer is not their closest hit.
  uint64_t wrong_results = 0;
  // Any-hit mode: closest-hit rays whose baseline any-hit walk itself did not return their
  // closest hit (the mode's own error, without prediction; part of wrong_results' reference).
  uint64_t baseline_wrong_results = 0;
  uint64_t exact_mismatches = 0;  // exact modes: answer differs from the baseline (must be 0)
  uint64_t baseline_hits = 0;
  uint64_t table_updates = 0;  // rays whose outcome wrote the table
  // Confidence (TableConfig::conf_bits > 0; always 0 without): rays whose failed prediction
  // demoted their entry (PredTable::demote, requested: the entry may be gone when it lands), and
  // lookups whose matching entry was below the threshold (no prediction given).
  uint64_t table_demotes = 0;
  uint64_t suppressed_lookups = 0;
  uint64_t unoffered_rays = 0;  // any_hit_only: closest-hit rays never offered to the predictor
  uint64_t baseline_ns = 0;     // measure_time: CPU time of the baseline walks
  uint64_t hrpp_ns = 0;         // measure_time: hash, lookup, predicted and full walks, update

  PredictStats& operator+=(const PredictStats& o);
  double skipped_interior_fraction() const;
  double precision() const;
  double recall() const;
  nlohmann::json to_json() const;
};

/// Result of one ray through the predictor.
struct RayResult {
  bool invalid = false;
  bool predicted = false;  // the table held nodes for the key
  bool verified = false;   // the prediction was confirmed (a hit in a predicted subtree)
  Hit baseline, answer;
  Counters base_counters, hrpp_counters;
  HashKey key;
  uint32_t update_node = kNoNode;  // what was written to the table (kNoNode: nothing)
  bool demoted = false;            // a demote was requested (failed prediction, nothing written)
  bool suppressed = false;         // the matching entry was below the confidence threshold
};

/// The confidence rule's demote (docs/predictor.md, "One ray"): with confidence counters, a ray
/// that was given a prediction (er.predicted) that failed (not verified) and that has no node to
/// write (update_node returned kNoNode) demotes its entry.
inline bool demotes(const TableConfig& t, bool predicted, bool verified, uint32_t update_node) {
  return t.conf_bits > 0 && predicted && !verified && update_node == kNoNode;
}

class Predictor {
 public:
  Predictor(const Bvh& bvh, const PredictorConfig& cfg);

  /// Runs one ray through lookup, walks and update, and accumulates statistics.
  RayResult process(const RayRecord& r);

  /// The sum over the ray kinds (computed when asked).
  const PredictStats& total() const;
  const PredictStats& by_kind(RayKind k) const { return by_kind_[static_cast<int>(k)]; }
  const PredTable& table() const { return table_; }
  const PredictorConfig& config() const { return cfg_; }

  /// Full JSON report: configuration, totals, by_kind, table_entries, table_bytes.
  nlohmann::json to_json() const;

 private:
  const Bvh& bvh_;
  PredictorConfig cfg_;
  PredTable table_;
  struct PendingUpdate {
    uint64_t due;  // the ray number before whose lookup the write lands
    uint32_t index;
    uint64_t tag, key;
    uint32_t node;
    bool demote = false;  // a demote (PredTable::demote), not an update
  };
  std::deque<PendingUpdate> pending_;  // update_delay > 0: writes not yet in the table
  uint64_t issued_ = 0;                // rays processed (valid or not)
  mutable PredictStats total_;         // total()'s result
  std::array<PredictStats, kNumRayKinds> by_kind_{};
};

/// True when `node` is `leaf` or one of its ancestors.
bool in_subtree(const Bvh& bvh, uint32_t node, uint32_t leaf);

/// Same answer: hit/miss equal, t bitwise equal, and the same primitive or an exact tie (the
/// other primitive is hit at exactly the same t).
bool same_answer(const Bvh& bvh, const Ray& r, const Hit& a, const Hit& b);

}  // namespace hrpp
