// The predictor beside one RT unit, as the unit's traversal engine sees it (docs/timing_model.md,
// "The predictor"): rays enter it, predictions come back, predicted-walk results go in, skip
// decisions come back, final outcomes go in. Two implementations:
//   PortPredictor   the RTL's ports, cycle by cycle: the C++ cycle model of hrpp_top
//                   (CyclePortModel), or the Verilated RTL in lockstep with it (`--rtl`).
//   TimedPredictor  the golden model's predictor (any hash, table and mode, or the oracle) behind
//                   a stated timing wrapper: lookup, decision and update latencies, lookups and
//                   updates per cycle, and credits (rays held at once).
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/hardware/cycle_model_lanes.h"
#include "hrpp/predictor/engine_side.h"
#include "hrpp/predictor/pred_table.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/workload/workload.h"

namespace hrpp::sim {

/// A message from the engine: a predicted-walk result or a final outcome (ray = stream index).
struct EngineMsg {
  uint32_t ray = 0;
  bool hit = false;
  uint32_t node = 0;
};

/// One cycle's traffic between a unit's engine and its predictor. The engine fills the queues
/// (messages in the order they became ready); the predictor removes what it takes this cycle and
/// appends what it delivers.
struct UnitIo {
  std::deque<uint32_t> entering;   // rays waiting to enter the predictor, in issue order
  std::deque<EngineMsg> pw;        // predicted-walk results
  std::deque<EngineMsg> outcomes;  // final outcomes
  std::vector<std::pair<uint32_t, Prediction>> predictions;  // delivered this cycle
  std::vector<std::pair<uint32_t, Action>> decisions;        // delivered this cycle
};

struct UnitPredictorStats {
  uint64_t lookups = 0;       // rays taken
  uint64_t stall_cycles = 0;  // cycles in which a ray waited to enter and none was taken
  uint64_t entry_wait = 0;    // sum over the rays of the cycles they waited to enter
  uint64_t updates = 0;       // table writes
  // Confidence counters (TableConfig::conf_bits > 0): demote requests (a predicted ray whose
  // predicted walks found no hit and whose outcome is a miss), and lookups whose matching entry
  // was below the threshold (TimedPredictor only: the RTL's ports do not show them).
  uint64_t demotes = 0;
  uint64_t suppressed_lookups = 0;
  uint64_t mismatches = 0;  // --rtl: cycles in which the RTL's outputs differed from the model's
  uint64_t bypassed = 0;    // rays that gave up waiting to enter (SimOptions::entry_timeout)
  uint64_t gate_closed_cycles = 0;  // SimOptions::gate: cycles the unit's gate was closed
  uint64_t gate_openings = 0;       // SimOptions::gate: predicted hits that opened a closed gate
};

/// What a ray's lookup found (the loss breakdown against the oracle: docs/timing_model.md,
/// "Losses against the oracle"). Known to the golden predictor (TimedPredictor); the RTL's ports
/// do not show it (kUnknown).
enum class LookupClass : uint8_t {
  kUnknown = 0,
  kPredicted = 1,   // an entry gave nodes (its predicted walk tells right from wrong)
  kCompulsory = 2,  // the key never written before the lookup
  kEvicted = 3,     // written before, gone from the table (capacity or conflict)
  kStale = 4,       // not in the table, a write to it sent and not yet landed
  kSuppressed = 5,  // an entry matched, its confidence below the threshold
};

class UnitPredictor {
 public:
  virtual ~UnitPredictor() = default;
  /// What ray's lookup found, once (the record is dropped); kUnknown when not recorded.
  virtual LookupClass take_class(uint32_t /*ray*/) { return LookupClass::kUnknown; }
  /// One clock cycle.
  virtual void cycle(uint64_t now, UnitIo* io) = 0;
  /// Holds rays or messages (the engine keeps clocking it).
  virtual bool busy() const = 0;
  virtual const UnitPredictorStats& stats() const = 0;
  /// A protocol error seen, or "".
  virtual std::string error() const { return {}; }
};

/// The RTL's ports, one cycle at a time (hrpp/hardware/cycle_model.h's DutIn / DutOut): one lane
/// (hrpp_top), or lanes() lanes (hrpp_lanes), each with hrpp_top's ports.
class PortModel {
 public:
  virtual ~PortModel() = default;
  virtual int lanes() const { return 1; }
  /// Lane `lane`'s outputs in this cycle.
  virtual DutOut outputs(int lane) = 0;
  /// One clock edge with every lane's inputs (in.size() == lanes()).
  virtual void tick(const std::vector<DutIn>& in) = 0;
  virtual std::string error() const { return {}; }
  virtual uint64_t mismatches() const { return 0; }
};

/// The cycle model of hrpp_top behind its ports.
class CyclePortModel : public PortModel {
 public:
  explicit CyclePortModel(const CycleConfig& cc) : m_(cc) {}
  DutOut outputs(int /*lane*/) override { return m_.outputs(); }
  void tick(const std::vector<DutIn>& in) override { m_.tick(in.at(0)); }
  std::string error() const override { return m_.error(); }
  const CycleModel& model() const { return m_; }

 private:
  CycleModel m_;
};

/// The cycle model of hrpp_lanes (cfg.lanes 2 or 4) behind its lanes' ports.
class LanesCyclePortModel : public PortModel {
 public:
  explicit LanesCyclePortModel(const CycleConfig& cc) : m_(cc) {}
  int lanes() const override { return m_.lanes(); }
  DutOut outputs(int lane) override { return m_.outputs(lane); }
  void tick(const std::vector<DutIn>& in) override { m_.tick(in); }
  std::string error() const override { return m_.error(); }
  const LanesCycleModel& model() const { return m_; }

 private:
  LanesCycleModel m_;
};

/// The engine's side of the RTL's ports: per lane, ray ids (2^id_bits, the RTL's credits), one
/// ray, one predicted-walk result and one outcome offered per cycle and held until taken,
/// predictions and decisions always accepted. With more than one lane, each lane without a ray
/// on offer takes the next entering ray (lanes in order), and a ray's messages go back on its
/// lane: each lane is offered the oldest waiting message of its rays.
class PortPredictor : public UnitPredictor {
 public:
  /// `confidence`: the model's table has confidence counters (counts demotes in the stats).
  PortPredictor(const std::vector<RayRecord>& rays, std::unique_ptr<PortModel> model, int id_bits,
                bool confidence = false);
  void cycle(uint64_t now, UnitIo* io) override;
  bool busy() const override;
  const UnitPredictorStats& stats() const override { return stats_; }
  std::string error() const override;
  PortModel& model() { return *model_; }

 private:
  struct Lane {
    std::deque<uint32_t> free_ids;
    std::vector<uint32_t> ray_of;                          // by id
    std::vector<uint8_t> in_use;                           // by id
    std::optional<std::pair<uint32_t, uint32_t>> offered;  // id, ray
    std::vector<uint8_t> predicted;  // by id: given a prediction, its predicted walks found no hit
  };
  struct LaneId {
    uint32_t lane = 0, id = 0;
  };
  const std::vector<RayRecord>& rays_;
  std::unique_ptr<PortModel> model_;
  std::vector<Lane> lanes_;
  std::unordered_map<uint32_t, LaneId> id_of_;  // ray (stream index) -> its lane and id
  bool confidence_;
  UnitPredictorStats stats_;
  std::string error_;
};

/// Timing of the golden predictor (docs/timing_model.md, "Presets").
struct TimedConfig {
  uint32_t lookup_latency = 10;    // cycles from a ray's entry to its prediction
  uint32_t decision_latency = 2;   // from a predicted-walk result to the skip decision
  uint32_t update_latency = 7;     // from an outcome (or a skip) to the table write's visibility
  uint32_t lookups_per_cycle = 1;  // rays taken per cycle (predicted-walk results too)
  uint32_t updates_per_cycle = 1;  // outcomes taken per cycle
  uint32_t credits = 0;            // rays held at once (0: unlimited)
  bool oracle = false;  // predict the baseline walk's hit leaf's go_up-th ancestor, no table
  nlohmann::json to_json() const;
};

/// The timing of a golden-model preset (docs/timing_model.md, "The predictor"): micro21's from
/// its simulator's configuration; every other name the RTL's latencies and port rate (one lookup
/// and one outcome per cycle) without its credit limit.
TimedConfig preset_timing(const std::string& preset);

class TimedPredictor : public UnitPredictor {
 public:
  TimedPredictor(const Bvh& bvh, const std::vector<RayRecord>& rays, const PredictorConfig& pc,
                 const TimedConfig& tc);
  void cycle(uint64_t now, UnitIo* io) override;
  bool busy() const override;
  const UnitPredictorStats& stats() const override { return stats_; }
  LookupClass take_class(uint32_t ray) override;

 private:
  struct Pending {
    uint64_t due;
    uint32_t ray;
    Prediction p;
  };
  struct Decision {
    uint64_t due;
    uint32_t ray;
    Action action;
    uint32_t node;  // the predicted-walk result's node (written on a skip)
  };
  struct Write {
    uint64_t due;
    HashKey key;
    uint32_t node;
    bool demote = false;  // PredTable::demote (confidence), not an update
  };
  struct Held {  // a ray taken and not yet finished
    HashKey key;
    bool predicted = false;  // given a prediction (count > 0)
    bool pw_hit = false;     // its predicted walks found a hit
  };
  Prediction predict(uint32_t ray);
  const Bvh& bvh_;
  const std::vector<RayRecord>& rays_;
  PredictorConfig pc_;
  TimedConfig tc_;
  PredTable table_;
  std::deque<Pending> preds_;
  std::deque<Decision> decisions_;
  std::deque<Write> writes_;
  std::unordered_map<uint32_t, Held> held_of_;  // rays held: their keys, for the table write
  std::unordered_map<uint32_t, LookupClass> class_of_;  // rays looked up, until take_class
  std::unordered_set<uint64_t> written_;                // keys a write was sent for
  std::unordered_map<uint64_t, uint32_t> in_flight_;    // keys: their writes not yet landed
  uint64_t held_ = 0;                                   // rays taken, not yet finished (credits)
  UnitPredictorStats stats_;
};

}  // namespace hrpp::sim
