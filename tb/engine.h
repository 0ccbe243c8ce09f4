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
#include <string>
#include <vector>

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/predictor/engine_side.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/workload/workload.h"

namespace hrpp::tb {

struct EngineOptions {
  PredictMode mode = PredictMode::kClosestExact;
  uint32_t go_up = 0;
  int id_bits = 6;
  uint64_t seed = 1;
  double p_ray = 0.9;                     // probability of offering a ray in a cycle
  double p_pred_ready = 0.8;              // probability of accepting a prediction
  double p_skip_ready = 0.8;              // probability of accepting a skip decision
  int min_latency = 1, max_latency = 12;  // cycles from a prediction (decision) to its outcome
  uint64_t stall_every = 0;               // every so many cycles, stall all ready outputs ...
  uint64_t stall_length = 0;              // ... for this many cycles (0: never)
  // Random stalls on every interface (0: none): on each of the five interfaces independently,
  // a stall of 1..stall_max cycles starts with probability 1/stall_gap in a cycle without one.
  // Inputs (rays, predicted-walk results, final outcomes): no new message is offered (one
  // already offered stays valid until taken); outputs (predictions, decisions): ready is low.
  uint64_t stall_gap = 0;
  uint64_t stall_max = 0;
  // Test only: a deliberately wrong engine, to show the exactly-once check fails.
  //   1: a reset queues each dropped ray twice;  2: a ray stall withdraws the ray on offer and
  //   forgets it (the id is returned, the ray lost).
  int fault = 0;
};

/// The five interfaces, for the stall statistics.
enum StallPort { kStallRay, kStallPw, kStallUpd, kStallPred, kStallSkip, kNumStallPorts };
inline const char* stall_port_name(int p) {
  static const char* const names[] = {"ray_i", "pw_i", "outcome_i", "pred_o", "skip_o"};
  return names[p];
}
struct StallStats {
  uint64_t stalls = 0;   // stalls started
  uint64_t cycles = 0;   // cycles stalled
  uint64_t longest = 0;  // longest stall (cycles)
  uint64_t blocked = 0;  // stalled cycles in which a handshake was otherwise possible
};

class Engine {
 public:
  Engine(const Bvh& bvh, const std::vector<RayRecord>& rays, const EngineOptions& opt);

  /// The DUT's inputs for this cycle.
  void drive(uint64_t cycle, DutIn* in);
  /// The DUT's reset is asserted (from this cycle on, until released): the hardware forgets
  /// every ray in flight, so the engine drops their walks, pending messages and the ray on offer,
  /// and re-offers those rays (in stream order, ahead of new ones) once the DUT is ready again.
  /// Rays whose final result was already reported (final outcome accepted, or ActSkip decision
  /// taken) are not re-offered. Returns the number of rays dropped.
  uint64_t reset();
  /// The handshakes that happened in this cycle (inputs as driven, outputs as seen).
  void observe(uint64_t cycle, const DutIn& in, const DutOut& out);
  /// No ray left to offer and none in flight.
  bool done() const {
    return next_ray_ == rays_.size() && redo_.empty() && !offered_ray_ &&
           free_ids_.size() == by_id_.size();
  }
  /// "" if every ray of the stream got exactly one final result; else the first that did not.
  std::string check_exactly_once() const;
  uint64_t reoffered() const { return reoffered_; }
  const StallStats& stall_stats(int port) const { return stall_[port]; }
  const PredictStats& stats() const { return stats_; }
  uint64_t rays_finished() const { return finished_; }
  /// The most rays in flight at once (accepted by the DUT, final result not yet reported).
  uint64_t max_in_flight() const { return max_in_flight_; }
  uint64_t in_flight() const { return in_flight_; }
  /// A protocol violation seen (an output the engine cannot make sense of), or empty.
  const std::string& error() const { return error_; }

 private:
  struct InFlight {
    size_t ray = 0;
    EngineRay er;  // walks, outcome and statistics (hrpp/predictor/engine_side.h)
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
  /// The ray's final result is reported: its statistics, and its id is free again.
  void report(uint32_t id);
  /// Advances the random stall of each interface to this cycle.
  void step_stalls(uint64_t cycle);
  bool chance(double p) { return std::uniform_real_distribution<double>(0, 1)(rng_) < p; }
  uint64_t latency() {
    return std::uniform_int_distribution<int>(opt_.min_latency, opt_.max_latency)(rng_);
  }

  const Bvh& bvh_;
  const std::vector<RayRecord>& rays_;
  EngineOptions opt_;
  std::mt19937_64 rng_;
  size_t next_ray_ = 0;
  std::deque<size_t> redo_;  // rays dropped by a reset, to be offered again
  uint64_t finished_ = 0;
  uint64_t in_flight_ = 0, max_in_flight_ = 0;
  uint64_t reoffered_ = 0;
  std::vector<uint32_t> reports_;  // per ray of the stream: final results reported
  std::mt19937_64 stall_rng_;
  std::array<uint64_t, kNumStallPorts> stall_until_{};  // stalled while cycle < stall_until_
  std::array<bool, kNumStallPorts> stalled_{};          // in the cycle being driven
  std::array<StallStats, kNumStallPorts> stall_;
  std::deque<uint32_t> free_ids_;
  std::vector<std::optional<InFlight>> by_id_;
  std::optional<std::pair<uint32_t, size_t>> offered_ray_;  // id, ray
  Port pw_, upd_;  // predicted-walk results, final outcomes
  PredictStats stats_;
  std::string error_;
};

}  // namespace hrpp::tb
