// The RT-unit model (docs/timing_model.md): warps of rays on N RT units, each ray walking the BVH
// one step at a time through the memory system (memory.h) and the units' box and triangle test
// pipelines, with a predictor beside every unit (unit_predictor.h) or none.
//
// Functional results come from the golden model: a ray's walks are the golden traversal's (their
// visited nodes, in order, replayed step by step), its decisions are the predictor's, and its
// statistics are classify()'s, so the simulator adds time and never changes an answer.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/sim/gpu_config.h"
#include "hrpp/sim/memory.h"
#include "hrpp/sim/unit_predictor.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/workload/workload.h"

namespace hrpp::sim {

/// Where the units' data sits (docs/timing_model.md, "Memory"): the traversal layout's node pairs
/// (BvhPair, 64 bytes: both child boxes of an interior node) from address 0, then the triangles
/// (36 bytes each, leaf order) from the next 4 KB boundary.
constexpr uint32_t kPairBytes = sizeof(BvhPair);
constexpr uint32_t kTriangleBytes = sizeof(Triangle);
uint64_t triangle_base(const Bvh& bvh);

enum class PredictorKind : uint8_t {
  kNone = 0,   // no predictor: every ray walks from the root
  kPort = 1,   // the RTL's ports: cycle model (or the Verilated RTL) per unit
  kTimed = 2,  // the golden predictor behind a timing wrapper (TimedConfig), or the oracle
};

struct SimProgress {
  uint64_t finished = 0, rays = 0, cycle = 0;
};

struct SimOptions {
  GpuConfig gpu;
  PredictorKind kind = PredictorKind::kNone;
  PredictorConfig pred;       // mode and go_up for every kind; hash and table for kTimed
  CycleConfig cycle;          // kPort
  TimedConfig timed;          // kTimed
  bool any_hit_only = false;  // only rays answered as any-hit queries use the predictor
  /// Warp repacking (docs/timing_model.md, "Repacking"): after its prediction a ray waits in its
  /// unit's buffer of its category; warp_size rays of one category walk on as a new warp at once,
  /// and when the unit's timer (started by the first ray buffered, restarted by every warp
  /// formed) reaches repack_timer cycles, one warp is formed from the categories in order.
  enum class Repack : uint8_t {
    kNone = 0,
    kPredicted = 1,  // MICRO 2021: two categories, predicted and not predicted
    kNode = 2,       // one category per first predicted node, and not predicted
    /// MICRO 2021's simulator (docs/timing_model.md, "MICRO 2021's timing"): a warp waits in
    /// the predictor; its rays given a prediction leave it for one pool, the others stay. The
    /// pool forms a warp of warp_size rays at once when it holds more than warp_size; when the
    /// timer (started by a warp entering an empty predictor, restarted by every release)
    /// expires, one release: a pool warp when the pool holds warp_size rays, else the oldest
    /// waiting warp goes on with the rays it kept (the pool's last rays when no warp waits). A
    /// unit holds warps_per_unit admitted warps (waiting ones included) and as many walking.
    kMicro21 = 3,
  } repack = Repack::kNone;
  uint32_t repack_timer = 20;  // MICRO 2021's -gpgpu_rt_predictor_repacking_timer
  /// A ray that has waited this many cycles to enter its unit's predictor (no credit, port busy)
  /// gives up: it walks from the root with no lookup and no table write, as a ray that does not
  /// use the predictor (`bypassed`). 0: rays wait until they enter.
  uint32_t entry_timeout = 0;
  /// The unit's gate (docs/timing_model.md, "The gate"): 0, none. N > 0: a unit whose last N
  /// answered lookups brought no predicted hit (no skip or shrink decision) closes its gate:
  /// while it is closed, a ray that cannot enter in its first cycle walks without the predictor
  /// (entry_timeout 1); the next predicted hit opens it.
  uint32_t gate = 0;
  /// With a gate: the lookups it allows before the unit's first predicted hit (unset: gate; 0:
  /// the gate starts closed).
  std::optional<uint32_t> gate_first;
  /// The RT unit starts a ray's walk from the root as soon as its predicted walks found no hit
  /// (the skip decision can then only be a full walk: skip_action) instead of waiting for the
  /// decision; the decision still comes and is taken, and the ray's outcome is sent after it.
  bool early_root = false;
  /// kTimed only. The ray's fetch list is settled at its prediction, as MICRO 2021's simulator
  /// replays functional walks (docs/timing_model.md, "MICRO 2021's timing"): the predicted walk
  /// starts at the predicted node's own pair (not its parent's, for the node's box), and the
  /// walk that follows (none when the predicted walk answers the ray, else from the root) starts
  /// as the predicted walk ends, without waiting for the predictor's decision; the decision must
  /// then agree.
  bool replay = false;
  /// How a run's cycles are counted. false: up to the last ray's answer. true: up to the last
  /// admitted (original) warp's retirement, as MICRO 2021's simulator ends a kernel when the
  /// warps of its thread blocks have retired, without waiting for the rays its predictor moved
  /// into warps of its own (with Repack::kMicro21, a warp whose rays all left retires when it
  /// is released).
  bool count_original_warps = false;
  /// A warm-up kernel, as MICRO 2021's benchmark's -w: the first warmup_rays rays of the stream
  /// run first; the other rays' warps enter once every warm-up ray is answered, and the run's
  /// cycles are counted from then (caches and tables stay as the warm-up left them).
  uint64_t warmup_rays = 0;
  /// kPort: the port model of unit u; default: the cycle model of `cycle`.
  std::function<std::unique_ptr<PortModel>(uint32_t unit)> port_model;
  /// When set: (*answers)[i] receives stream ray i's answer (resized to the stream; tests).
  std::vector<Hit>* answers = nullptr;
  /// Called every 2^14 finished rays.
  std::function<void(const SimProgress&)> progress;
};

struct KindTime {
  uint64_t rays = 0;
  uint64_t latency = 0;  // sum over the rays of their cycles in a unit (admission to answer)
};

/// The loss breakdown's tally (docs/timing_model.md, "Losses against the oracle"): the rays whose
/// baseline walk hits, which the oracle answers from their hit leaf, by what became of their
/// prediction, with their baseline walks' node tests; and the node tests of the predicted walks,
/// wrong and right.
struct LossTally {
  enum Class : uint8_t {
    kCaptured = 0,    // a prediction whose walk found the hit
    kAliased = 1,     // a prediction whose walk did not: the key's node holds another hit
    kCompulsory = 2,  // no prediction: the key never written before the lookup
    kEvicted = 3,     // no prediction: written before, gone (capacity or conflict)
    kStale = 4,       // no prediction: a write to the key sent, not yet landed
    kSuppressed = 5,  // no prediction: below the confidence threshold
    kGated = 6,       // walked without the predictor (the gate, or the entry timeout)
    kNotOffered = 7,  // a ray kind the design does not predict
    kUnknown = 8,     // the predictor does not tell (the RTL's ports)
    kNumClasses = 9,
  };
  static const char* name(Class c);
  std::array<uint64_t, kNumClasses> rays{}, tests{};
  uint64_t wrong_rays = 0, wrong_tests = 0;  // predictions whose walks found no hit, all rays
  uint64_t right_tests = 0;                  // the walks of predictions that found it
};

struct SimStats {
  double seconds = 0;             // wall-clock time of the simulation (simulate())
  uint64_t rays = 0;              // simulated (valid) rays
  uint64_t invalid_rays = 0;      // never traced (validate_ray), as in hrpp predict
  uint64_t cycles = 0;            // from the first admission to the last answer
  uint64_t node_fetches = 0;      // node pairs fetched (start-box fetches included)
  uint64_t start_fetches = 0;     // of which: a predicted node's own box (its parent's pair)
  uint64_t triangle_fetches = 0;  // triangles fetched (= triangle tests)
  MemoryStats memory;
  // Node fetches that were L1 hits, for the top kTopLevels levels of the BVH and below them.
  static constexpr uint32_t kTopLevels = 8;
  uint64_t top_fetches = 0, top_hits = 0, deep_fetches = 0, deep_hits = 0;
  uint64_t warps = 0;
  uint64_t latency = 0;         // sum over rays of their latencies (admission to answer)
  uint64_t lane_cycles = 0;     // sum over rays and the warps they were in of their cycles there
  uint64_t repacked_warps = 0;  // warps formed by repacking (counted in `warps` too)
  uint64_t pooled_rays = 0;     // rays that left their warps for repacking's buffers
  uint64_t warp_cycles = 0;     // sum over warps of warp_size x cycles in a unit
  uint64_t in_flight_area = 0;  // sum over cycles of the rays in the units
  std::array<KindTime, kNumRayKinds> by_kind{};
  UnitPredictorStats predictor;                      // summed over the units
  LossTally loss;                                    // a predictor's runs (not the oracle's)
  std::array<PredictStats, kNumRayKinds> predict{};  // classify(), per kind
  PredictStats predict_total() const;
  double simd_efficiency() const { return warp_cycles ? double(lane_cycles) / warp_cycles : 0; }
  double mean_latency() const { return rays ? double(latency) / rays : 0; }
  double mean_in_flight() const { return cycles ? double(in_flight_area) / cycles : 0; }
  nlohmann::json to_json(const GpuConfig& g) const;
};

/// Simulates the rays (a stream, in issue order) on the GPU; throws std::runtime_error on a
/// predictor protocol error or a deadlock.
SimStats simulate(const Bvh& bvh, const std::vector<RayRecord>& rays, const SimOptions& opt);

}  // namespace hrpp::sim
