#include "hrpp/predictor/tiled_predictor.h"

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace hrpp {

std::string TiledOptions::validate() const {
  if (cores == 0) return "the number of cores must be at least 1";
  if (threads == 0) return "the number of threads must be at least 1";
  if (tile == 0) return "the tile edge must be at least 1 pixel";
  if (batch == 0 || queue_batches == 0) return "batch sizes must be at least 1";
  if (cores > 1 && width == 0) return "several cores need the image width (to cut it into tiles)";
  return "";
}

// A worker thread and its bounded queue of (core, batch) jobs, processed in FIFO order.
struct TiledPredictor::Worker {
  struct Job {
    uint32_t core;
    std::vector<RayRecord> rays;
  };
  std::mutex m;
  std::condition_variable cv_not_empty, cv_not_full;
  std::deque<Job> jobs;
  bool stop = false;
  std::exception_ptr error;
  std::thread thread;

  void run(std::vector<std::unique_ptr<Predictor>>* preds) {
    while (true) {
      Job job;
      {
        std::unique_lock<std::mutex> lk(m);
        cv_not_empty.wait(lk, [&] { return stop || !jobs.empty(); });
        if (jobs.empty()) return;  // stop and drained
        job = std::move(jobs.front());
        jobs.pop_front();
      }
      cv_not_full.notify_one();
      if (error) continue;  // after a failure, drain without work
      try {
        Predictor& p = *(*preds)[job.core];
        for (const RayRecord& r : job.rays) p.process(r);
      } catch (...) {
        error = std::current_exception();
      }
    }
  }
};

TiledPredictor::TiledPredictor(const Bvh& bvh, const PredictorConfig& cfg, const TiledOptions& opt)
    : opt_(opt) {
  if (const std::string e = opt.validate(); !e.empty()) throw std::invalid_argument(e);
  for (uint32_t c = 0; c < opt.cores; ++c) preds_.push_back(std::make_unique<Predictor>(bvh, cfg));
  if (opt.threads > 1) {
    pending_.resize(opt.cores);
    const uint32_t n = std::min(opt.threads, opt.cores);
    for (uint32_t t = 0; t < n; ++t) {
      workers_.push_back(std::make_unique<Worker>());
      Worker* w = workers_.back().get();
      w->thread = std::thread([w, this] { w->run(&preds_); });
    }
  }
}

TiledPredictor::~TiledPredictor() {
  try {
    finish();
  } catch (...) {
  }
}

uint32_t TiledPredictor::core_of(const RayRecord& r) const {
  if (opt_.cores == 1) return 0;
  const uint32_t x = r.pixel % opt_.width, y = r.pixel / opt_.width;
  const uint32_t tiles_x = (opt_.width + opt_.tile - 1) / opt_.tile;
  const uint64_t tile = uint64_t(y / opt_.tile) * tiles_x + x / opt_.tile;
  return static_cast<uint32_t>(tile % opt_.cores);
}

std::optional<RayResult> TiledPredictor::push(const RayRecord& r) {
  if (finished_) throw std::logic_error("TiledPredictor::push after finish");
  const uint32_t c = core_of(r);
  if (workers_.empty()) {  // one thread: in the caller's thread, in issue order
    return preds_[c]->process(r);
  }
  pending_[c].push_back(r);
  if (pending_[c].size() >= opt_.batch) flush(c);
  return std::nullopt;
}

// Core c always goes to worker c mod workers, whose queue is FIFO: each core's rays are processed
// in issue order by one thread, whatever the number of threads.
void TiledPredictor::flush(uint32_t c) {
  if (pending_[c].empty()) return;
  Worker& w = *workers_[c % workers_.size()];
  {
    std::unique_lock<std::mutex> lk(w.m);
    w.cv_not_full.wait(lk, [&] { return w.jobs.size() < opt_.queue_batches; });
    w.jobs.push_back({c, std::move(pending_[c])});
  }
  w.cv_not_empty.notify_one();
  pending_[c] = {};
  pending_[c].reserve(opt_.batch);
}

void TiledPredictor::finish() {
  if (finished_) return;
  finished_ = true;
  for (uint32_t c = 0; c < pending_.size(); ++c) flush(c);
  for (auto& w : workers_) {
    {
      std::lock_guard<std::mutex> lk(w->m);
      w->stop = true;
    }
    w->cv_not_empty.notify_one();
  }
  std::exception_ptr first;
  for (auto& w : workers_) {
    w->thread.join();
    if (w->error && !first) first = w->error;
  }
  workers_.clear();
  if (first) std::rethrow_exception(first);
}

PredictStats TiledPredictor::total() const {
  PredictStats s;
  for (const auto& p : preds_) s += p->total();
  return s;
}

PredictStats TiledPredictor::by_kind(RayKind k) const {
  PredictStats s;
  for (const auto& p : preds_) s += p->by_kind(k);
  return s;
}

uint64_t TiledPredictor::table_entries() const {
  uint64_t n = 0;
  for (const auto& p : preds_) n += p->table().entries_used();
  return n;
}

uint64_t TiledPredictor::table_bytes() const {
  uint64_t n = 0;
  for (const auto& p : preds_) n += p->table().bytes();
  return n;
}

nlohmann::json TiledPredictor::to_json() const {
  if (opt_.cores == 1) return preds_[0]->to_json();
  nlohmann::json j = total().to_json();
  j["config"] = preds_[0]->to_json()["config"];
  j["table_entries"] = table_entries();
  j["table_bytes"] = table_bytes();
  j["table_unbounded"] = j["config"]["table"] == "unbounded";
  uint64_t per_core = 0;
  for (const auto& p : preds_) per_core = std::max(per_core, p->table().bytes());
  j["table_bytes_per_core"] = per_core;
  j["cores"] = opt_.cores;
  j["tile"] = opt_.tile;
  nlohmann::json bk = nlohmann::json::object();
  for (int k = 0; k < kNumRayKinds; ++k) {
    const PredictStats s = by_kind(static_cast<RayKind>(k));
    if (s.rays) bk[std::string(ray_kind_name(static_cast<RayKind>(k)))] = s.to_json();
  }
  j["by_kind"] = bk;
  return j;
}

}  // namespace hrpp
