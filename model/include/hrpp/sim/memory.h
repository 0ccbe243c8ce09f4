// The RT units' memory system (docs/timing_model.md, "Memory"): one L1 per unit, a shared L2 and
// DRAM. Set-associative LRU caches with MSHRs; bandwidth-limited L2-to-L1 and DRAM transfers.
//
// A request is timed when it is made, in the order the simulator makes them (nondecreasing
// cycles, up to MSHR waits): a miss installs its line at once with the cycle its data arrives,
// so later requests to the line merge with the miss (they wait for the same data) and the LRU
// order is the order of requests. A miss holds one of its cache's MSHRs until its data arrives;
// with every MSHR busy it waits for the earliest to free. A transfer over a bandwidth-limited
// link starts when the link is free and holds it for bytes / bytes_per_cycle cycles.
#pragma once

#include <cstdint>
#include <queue>
#include <vector>

#include "hrpp/sim/gpu_config.h"

namespace hrpp::sim {

struct CacheStats {
  uint64_t accesses = 0;     // block (line or sector) requests
  uint64_t hits = 0;         // the line was there, its data arrived
  uint64_t merged = 0;       // the line's miss was in flight: waited for its data (no new miss)
  uint64_t misses = 0;       // new misses (sent to the next level)
  uint64_t mshr_waits = 0;   // misses that waited for a free MSHR
  uint64_t mshr_cycles = 0;  // cycles they waited
  double hit_rate() const { return accesses ? double(hits) / double(accesses) : 0.0; }
  CacheStats& operator+=(const CacheStats& o);
};

/// An issue-limited resource (a test pipeline, a cache port): per_cycle issues per cycle (0:
/// unbounded), each result `latency` cycles after its issue. Reservations are kept in a ring over
/// the cycles ahead of the simulator's current cycle.
class IssueSlots {
 public:
  explicit IssueSlots(const PipeConfig& c) : c_(c), ring_(c.per_cycle ? kRing : 0) {}
  /// n issues that may start at cycle t (t >= now), each in the first cycle with room: the cycle
  /// the last one's result is there.
  uint64_t issue(uint64_t now, uint64_t t, uint32_t n);

 private:
  static constexpr uint64_t kRing = 1 << 16;
  struct Slot {
    uint64_t cycle = ~0ull;
    uint32_t count = 0;
  };
  PipeConfig c_;
  std::vector<Slot> ring_;
};

/// Tags, LRU order and MSHRs of one cache. A request names a byte address; the cache's block is
/// its sector (CacheConfig::sector_bytes) or its line.
class Cache {
 public:
  enum class Probe : uint8_t {
    kAbsent,         // the line is not there
    kSectorMissing,  // sectored: the line is there, the request's sector is not
    kPresent,        // the block is there (its data arrived or in flight)
  };
  explicit Cache(const CacheConfig& cfg);
  /// kPresent with the block's arrival cycle in *ready; a line that is there has its recency
  /// refreshed.
  Probe lookup(uint64_t addr, uint64_t* ready);
  /// Installs the missing block of addr, whose data arrives at `ready` (allocating its line when
  /// absent, replacing the set's least recently used line).
  void insert(uint64_t addr, uint64_t ready);
  /// The first cycle >= t at which an MSHR is free for a miss made at t; the caller then calls
  /// hold_mshr with the cycle the miss's data arrives.
  uint64_t mshr_free_at(uint64_t t);
  void hold_mshr(uint64_t until) { mshr_.push(until); }
  const CacheConfig& config() const { return cfg_; }
  CacheStats stats;

 private:
  static constexpr uint64_t kNoData = ~0ull;
  size_t way_of(uint64_t line) const;  // the way holding the line, or npos
  CacheConfig cfg_;
  uint32_t set_mask_, line_shift_, sectors_;
  std::vector<uint64_t> tag_;    // line + 1 (0: invalid), sets x ways
  std::vector<uint64_t> ready_;  // by way and sector: the block's arrival cycle (kNoData: absent)
  std::vector<uint64_t> used_;   // LRU stamp
  uint64_t stamp_ = 0;
  std::priority_queue<uint64_t, std::vector<uint64_t>, std::greater<>> mshr_;  // busy until
};

/// A link that moves bytes_per_cycle bytes per cycle (0: unbounded), one transfer at a time.
class Link {
 public:
  explicit Link(double bytes_per_cycle) : bpc_(bytes_per_cycle) {}
  /// A transfer of `bytes` that may start at cycle t: the cycle it ends.
  uint64_t transfer(uint64_t t, uint32_t bytes);
  uint64_t busy_cycles() const { return uint64_t(busy_); }

 private:
  double bpc_;
  double free_ = 0, busy_ = 0;
};

struct MemoryStats {
  CacheStats l1, l2;  // l1: all units together
  uint64_t dram_bytes = 0;
  uint64_t loads = 0;             // load() calls
  uint64_t port_wait_cycles = 0;  // sum over line requests of cycles waiting for an L1 port
};

class MemorySystem {
 public:
  explicit MemorySystem(const GpuConfig& g);
  /// Unit `unit` reads [addr, addr + bytes) at cycle `now`, one request per L1 block (sector or
  /// line): the cycle every block of it is there. *l1_hit (if set): every block was an L1 hit.
  uint64_t load(uint32_t unit, uint64_t addr, uint32_t bytes, uint64_t now, bool* l1_hit = nullptr);
  MemoryStats stats() const;

 private:
  uint64_t l1_block(uint32_t unit, uint64_t addr, uint64_t now, bool* hit);
  uint64_t l2_block(uint64_t addr, uint64_t t);
  GpuConfig g_;
  std::vector<Cache> l1_;
  std::vector<IssueSlots> l1_port_;  // requests_per_cycle
  Cache l2_;
  Link l2_link_, dram_link_;
  uint64_t dram_bytes_ = 0, loads_ = 0, port_wait_ = 0;
  uint32_t l1_block_shift_;
};

}  // namespace hrpp::sim
