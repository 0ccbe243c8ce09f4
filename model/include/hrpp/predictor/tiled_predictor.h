// The predictor on several cores (docs/predictor.md, "Cores and threads"): the image is cut into
// tiles of tile x tile pixels, tile i belongs to core i mod cores, and every core owns its own
// predictor table, as every GPU core would. Each core sees its own rays in issue order, so the
// statistics depend on the number of cores but never on the number of threads that run them.
// One core is the single predictor of Predictor, ray for ray.
//
// Rays are pushed by one producer (the workload generator or a stream reader) and handed to the
// worker threads in batches through bounded queues: memory does not grow with the number of rays.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "hrpp/predictor/predictor.h"

namespace hrpp {

struct TiledOptions {
  uint32_t cores = 1;          // predictor tables (fixed by the study, not by the machine)
  uint32_t threads = 1;        // worker threads (1: everything runs in the caller's thread)
  uint32_t width = 0;          // image width in pixels (needed when cores > 1)
  uint32_t tile = 8;           // tile edge in pixels
  uint32_t batch = 4096;       // rays handed to a worker at once
  uint32_t queue_batches = 4;  // batches waiting per worker before the producer blocks
  /// Returns an empty string or the problem (cores or threads 0, cores > 1 without a width).
  std::string validate() const;
};

class TiledPredictor {
 public:
  TiledPredictor(const Bvh& bvh, const PredictorConfig& cfg, const TiledOptions& opt);
  ~TiledPredictor();  // joins the workers (finish() if not done)
  TiledPredictor(const TiledPredictor&) = delete;
  TiledPredictor& operator=(const TiledPredictor&) = delete;

  /// The core that owns a ray (a function of its pixel alone).
  uint32_t core_of(const RayRecord& r) const;
  /// Hands one ray to its core, in issue order. Not thread-safe: one producer. With one thread
  /// the ray is processed at once and its result returned; with more, nothing is returned.
  std::optional<RayResult> push(const RayRecord& r);
  /// Processes everything pushed so far and stops the workers; statistics are final after it.
  /// Rethrows the first exception a worker met.
  void finish();

  /// Sums over the cores (in core order).
  PredictStats total() const;
  PredictStats by_kind(RayKind k) const;
  uint64_t table_entries() const;  // entries used, summed over the cores' tables
  uint64_t table_bytes() const;    // storage of all cores' tables
  const Predictor& core(uint32_t c) const { return *preds_[c]; }
  uint32_t cores() const { return opt_.cores; }
  /// Predictor::to_json with the totals, by_kind and table figures summed over the cores, plus
  /// "cores", "tile", "table_bytes_per_core" (the largest core's).
  nlohmann::json to_json() const;

 private:
  struct Worker;
  void flush(uint32_t core);
  TiledOptions opt_;
  std::vector<std::unique_ptr<Predictor>> preds_;
  std::vector<std::vector<RayRecord>> pending_;  // per core
  std::vector<std::unique_ptr<Worker>> workers_;
  bool finished_ = false;
};

}  // namespace hrpp
