// The traversal engine the testbench plays around the DUT: it offers rays, walks predicted
// subtrees and the BVH from the root with the golden model, and answers with outcomes, with
// seeded random latencies and back-pressure. Its random choices depend only on what the DUT (or
// the cycle model) showed it, so two runs that agree cycle by cycle make the same choices.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <vector>

#include "hrpp/bvh.h"
#include "hrpp/cycle_model.h"
#include "hrpp/predictor.h"
#include "hrpp/workload.h"

namespace hrpp::tb {

struct EngineOptions {
  PredictMode mode = PredictMode::kClosestExact;
  uint32_t go_up = 0;
  int id_bits = 6;
  uint64_t seed = 1;
  double p_ray = 0.9;          // probability of offering a ray in a cycle
  double p_pred_ready = 0.8;   // probability of accepting a prediction
  double p_skip_ready = 0.8;   // probability of accepting a skip decision
  int min_latency = 1, max_latency = 12;  // cycles from a prediction (decision) to its outcome
  uint64_t stall_every = 0;    // every so many cycles, stall all ready outputs ...
  uint64_t stall_length = 0;   // ... for this many cycles (0: never)
};

class Engine {
 public:
  Engine(const Bvh& bvh, const std::vector<RayRecord>& rays, const EngineOptions& opt);

  /// The DUT's inputs for this cycle.
  void drive(uint64_t cycle, DutIn* in);
  /// The handshakes that happened in this cycle (inputs as driven, outputs as seen).
  void observe(uint64_t cycle, const DutIn& in, const DutOut& out);
  bool done() const { return finished_ == rays_.size(); }
  const PredictStats& stats() const { return stats_; }
  uint64_t rays_finished() const { return finished_; }
  /// A protocol violation seen (an output the engine cannot make sense of), or empty.
  const std::string& error() const { return error_; }

 private:
  struct InFlight {
    size_t ray = 0;
    bool any = false;
    bool predicted = false;
    Hit baseline, best;
    uint32_t best_node = kNoNode;
    std::array<uint32_t, kMaxNodesPerEntry> nodes{};  // the predicted nodes walked
    uint32_t num_nodes = 0;
    Counters base, hrpp, pred;
  };
  struct Message {
    uint64_t ready_cycle;
    uint32_t id;
    bool hit;
    uint32_t node;
  };
  /// A port's messages in order of their ready cycle, and the one offered (held until taken).
  struct Port {
    std::deque<Message> pending;
    std::optional<Message> offered;
  };
  void finish(uint32_t id, const Hit& answer, bool verified, bool skipped);
  bool chance(double p) { return std::uniform_real_distribution<double>(0, 1)(rng_) < p; }
  uint64_t latency() {
    return std::uniform_int_distribution<int>(opt_.min_latency, opt_.max_latency)(rng_);
  }

  const Bvh& bvh_;
  const std::vector<RayRecord>& rays_;
  EngineOptions opt_;
  std::mt19937_64 rng_;
  size_t next_ray_ = 0;
  uint64_t finished_ = 0;
  std::deque<uint32_t> free_ids_;
  std::vector<std::optional<InFlight>> by_id_;
  std::optional<std::pair<uint32_t, size_t>> offered_ray_;  // id, ray
  Port pw_, upd_;  // predicted-walk results, final outcomes
  PredictStats stats_;
  std::string error_;
};

}  // namespace hrpp::tb
