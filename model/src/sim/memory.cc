#include "hrpp/sim/memory.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hrpp::sim {

CacheStats& CacheStats::operator+=(const CacheStats& o) {
  accesses += o.accesses;
  hits += o.hits;
  merged += o.merged;
  misses += o.misses;
  mshr_waits += o.mshr_waits;
  mshr_cycles += o.mshr_cycles;
  return *this;
}

Cache::Cache(const CacheConfig& cfg)
    : cfg_(cfg),
      set_mask_(cfg.sets() - 1),
      line_shift_(std::countr_zero(cfg.line_bytes)),
      sectors_(cfg.line_bytes / cfg.block_bytes()),
      tag_(size_t(cfg.sets()) * cfg.ways, 0),
      ready_(tag_.size() * sectors_, kNoData),
      used_(tag_.size(), 0) {}

size_t Cache::way_of(uint64_t line) const {
  const size_t base = size_t(line & set_mask_) * cfg_.ways;
  for (uint32_t w = 0; w < cfg_.ways; ++w)
    if (tag_[base + w] == line + 1) return base + w;
  return std::string::npos;
}

Cache::Probe Cache::lookup(uint64_t addr, uint64_t* ready) {
  const uint64_t line = addr >> line_shift_;
  const size_t w = way_of(line);
  if (w == std::string::npos) return Probe::kAbsent;
  used_[w] = ++stamp_;
  const uint64_t r = ready_[w * sectors_ + (addr & (cfg_.line_bytes - 1)) / cfg_.block_bytes()];
  if (r == kNoData) return Probe::kSectorMissing;
  *ready = r;
  return Probe::kPresent;
}

void Cache::insert(uint64_t addr, uint64_t ready) {
  const uint64_t line = addr >> line_shift_;
  size_t victim = way_of(line);
  if (victim == std::string::npos) {
    const size_t base = size_t(line & set_mask_) * cfg_.ways;
    victim = base;
    for (uint32_t w = 0; w < cfg_.ways; ++w) {
      if (tag_[base + w] == 0) {
        victim = base + w;
        break;
      }
      if (used_[base + w] < used_[victim]) victim = base + w;
    }
    tag_[victim] = line + 1;
    std::fill_n(ready_.begin() + victim * sectors_, sectors_, kNoData);
  }
  ready_[victim * sectors_ + (addr & (cfg_.line_bytes - 1)) / cfg_.block_bytes()] = ready;
  used_[victim] = ++stamp_;
}

uint64_t Cache::mshr_free_at(uint64_t t) {
  while (!mshr_.empty() && mshr_.top() <= t) mshr_.pop();
  if (mshr_.size() < cfg_.mshrs) return t;
  const uint64_t start = mshr_.top();  // the earliest miss to complete frees its MSHR
  mshr_.pop();
  stats.mshr_waits++;
  stats.mshr_cycles += start - t;
  return start;
}

uint64_t IssueSlots::issue(uint64_t now, uint64_t t, uint32_t n) {
  if (c_.per_cycle == 0 || n == 0) return t + c_.latency;
  uint64_t c = t, last = t;
  while (n > 0) {
    if (c - now >= kRing) throw std::runtime_error("issue reservation too far ahead");
    Slot& s = ring_[c & (kRing - 1)];
    if (s.cycle != c) s = {c, 0};
    const uint32_t take = std::min(n, c_.per_cycle - s.count);
    if (take) {
      s.count += take;
      n -= take;
      last = c;
    }
    ++c;
  }
  return last + c_.latency;
}

uint64_t Link::transfer(uint64_t t, uint32_t bytes) {
  if (bpc_ <= 0) return t;
  const double start = std::max(double(t), free_);
  const double d = bytes / bpc_;
  free_ = start + d;
  busy_ += d;
  return uint64_t(std::ceil(free_));
}

MemorySystem::MemorySystem(const GpuConfig& g)
    : g_(g),
      l1_(g.units, Cache(g.l1)),
      l1_port_(g.units, IssueSlots({.latency = 0, .per_cycle = g.l1.requests_per_cycle})),
      l2_(g.l2),
      l2_link_(g.l2.bytes_per_cycle),
      dram_link_(g.dram.bytes_per_cycle),
      l1_block_shift_(std::countr_zero(g.l1.block_bytes())) {}

uint64_t MemorySystem::l2_block(uint64_t addr, uint64_t t) {
  Cache& c = l2_;
  c.stats.accesses++;
  uint64_t ready;
  if (c.lookup(addr, &ready) == Cache::Probe::kPresent) {
    (ready <= t ? c.stats.hits : c.stats.merged)++;
    return std::max(ready, t) + c.config().hit_latency;
  }
  c.stats.misses++;
  const uint64_t start = c.mshr_free_at(t);
  // The miss reaches DRAM after the L2's tag check; DRAM answers after its latency, then the
  // block crosses the DRAM link.
  const uint32_t bytes = c.config().block_bytes();
  const uint64_t arrive =
      dram_link_.transfer(start + c.config().hit_latency + g_.dram.latency, bytes);
  dram_bytes_ += bytes;
  c.hold_mshr(arrive);
  c.insert(addr, arrive);
  return arrive;
}

uint64_t MemorySystem::l1_block(uint32_t unit, uint64_t addr, uint64_t now, bool* hit) {
  Cache& c = l1_[unit];
  c.stats.accesses++;
  uint64_t ready;
  *hit = false;
  if (c.lookup(addr, &ready) == Cache::Probe::kPresent) {
    *hit = ready <= now;
    (ready <= now ? c.stats.hits : c.stats.merged)++;
    return std::max(ready, now + c.config().hit_latency);
  }
  c.stats.misses++;
  const uint64_t start = c.mshr_free_at(now);
  // The L1's tag check, then the L2 (its block holds this one), then the L2-to-L1 link.
  const uint64_t l2_ready = l2_block(addr, start + c.config().hit_latency);
  const uint64_t arrive = l2_link_.transfer(l2_ready, c.config().block_bytes());
  c.hold_mshr(arrive);
  c.insert(addr, arrive);
  return arrive;
}

uint64_t MemorySystem::load(uint32_t unit, uint64_t addr, uint32_t bytes, uint64_t now,
                            bool* l1_hit) {
  loads_++;
  bool all = true;
  uint64_t ready = now;
  const uint64_t first = addr >> l1_block_shift_,
                 last = (addr + std::max(bytes, 1u) - 1) >> l1_block_shift_;
  for (uint64_t block = first; block <= last; ++block) {
    const uint64_t t = l1_port_[unit].issue(now, now, 1);  // the L1's request port
    port_wait_ += t - now;
    bool hit;
    ready = std::max(ready, l1_block(unit, block << l1_block_shift_, t, &hit));
    all = all && hit;
  }
  if (l1_hit) *l1_hit = all;
  return ready;
}

MemoryStats MemorySystem::stats() const {
  MemoryStats s;
  for (const Cache& c : l1_) s.l1 += c.stats;
  s.l2 = l2_.stats;
  s.dram_bytes = dram_bytes_;
  s.loads = loads_;
  s.port_wait_cycles = port_wait_;
  return s;
}

}  // namespace hrpp::sim
