#include "hrpp/predictor/pred_table.h"

#include <algorithm>
#include <bit>

namespace hrpp {

static int clog2(uint64_t n) { return n <= 1 ? 0 : std::bit_width(n - 1); }

int node_bits_for(size_t num_nodes) { return std::max(1, clog2(num_nodes)); }

std::string TableConfig::validate() const {
  if (nodes_per_entry < 1 || nodes_per_entry > kMaxNodesPerEntry)
    return "nodes per entry must be 1.." + std::to_string(kMaxNodesPerEntry) + ", got " +
           std::to_string(nodes_per_entry);
  if (node_bits < 1 || node_bits > 32) return "node id width must be 1..32 bits";
  if (conf_bits < 0 || conf_bits > 3)
    return "confidence bits must be 0..3, got " + std::to_string(conf_bits);
  if (conf_bits > 0 && (conf_threshold < 1 || uint32_t(conf_threshold) > conf_max()))
    return "the confidence threshold must be 1.." + std::to_string(conf_max()) + " with " +
           std::to_string(conf_bits) + " confidence bits, got " + std::to_string(conf_threshold);
  if (unbounded) return {};
  if (sets == 0 || !std::has_single_bit(sets))
    return "the number of sets must be a power of two (>= 1), got " + std::to_string(sets);
  if (ways < 1 || ways > 16) return "ways must be 1..16, got " + std::to_string(ways);
  if (tag_bits < 0 || tag_bits > 64) return "tag width must be 0..64 bits";
  return {};
}

int TableConfig::count_bits() const { return clog2(uint64_t{nodes_per_entry} + 1); }
int TableConfig::age_bits() const { return clog2(ways); }
int TableConfig::entry_bits() const {
  const int id = unbounded ? key_bits : 1 + tag_bits;
  return id + count_bits() + static_cast<int>(nodes_per_entry) * node_bits + conf_bits;
}
uint64_t TableConfig::set_bits() const { return uint64_t{ways} * (entry_bits() + age_bits()); }
uint64_t TableConfig::total_bits(uint64_t unbounded_entries) const {
  return unbounded ? unbounded_entries * entry_bits() : uint64_t{sets} * set_bits();
}

void promote_node(Way& w, uint32_t node, uint32_t k) {
  uint32_t pos = w.count;
  for (uint32_t i = 0; i < w.count; ++i)
    if (w.nodes[i] == node) {
      pos = i;
      break;
    }
  if (pos == w.count) {  // not present: insert, dropping the LRU node when full
    pos = std::min(w.count, k - 1);
    if (w.count < k) w.count++;
  }
  for (uint32_t i = pos; i > 0; --i) w.nodes[i] = w.nodes[i - 1];
  w.nodes[0] = node;
}

PredTable::PredTable(const TableConfig& cfg) : cfg_(cfg) { clear(); }

void PredTable::clear() {
  map_.clear();
  if (cfg_.unbounded) return;
  ways_.assign(size_t{cfg_.sets} * cfg_.ways, Way{});
  ages_.resize(ways_.size());
  for (size_t i = 0; i < ages_.size(); ++i) ages_[i] = static_cast<uint8_t>(i % cfg_.ways);
}

uint64_t PredTable::stored_tag(uint64_t tag) const {
  return cfg_.tag_bits >= 64 ? tag : tag & ((uint64_t{1} << cfg_.tag_bits) - 1);
}

Prediction PredTable::lookup(uint32_t index, uint64_t tag, uint64_t key) const {
  Prediction p;
  tag = stored_tag(tag);
  const Way* w = nullptr;
  if (cfg_.unbounded) {
    auto it = map_.find(key);
    if (it != map_.end()) w = &it->second;
  } else {
    for (uint32_t i = 0; i < cfg_.ways; ++i) {
      const Way& c = ways_[size_t{index} * cfg_.ways + i];
      if (c.valid && c.tag == tag) {
        w = &c;
        p.way = static_cast<int>(i);
        break;
      }
    }
  }
  if (w) {
    p.conf = w->conf;
    if (cfg_.conf_bits > 0 && w->conf < uint32_t(cfg_.conf_threshold)) {
      p.suppressed = true;  // not confident: no prediction
    } else {
      p.count = w->count;
      p.nodes = w->nodes;
    }
  }
  return p;
}

// The confidence rule of an update: `node` already in the list confirms the entry (count up,
// saturating), else it resets the counter (node inserted, or the entry new). Before promote_node.
static void update_conf(Way& w, uint32_t node, uint32_t conf_max) {
  bool present = false;
  for (uint32_t i = 0; i < w.count; ++i) present |= w.nodes[i] == node;
  w.conf = present ? std::min(w.conf + 1, conf_max) : 0;
}

void PredTable::update(uint32_t index, uint64_t tag, uint64_t key, uint32_t node) {
  if (cfg_.unbounded) {
    Way& w = map_[key];
    update_conf(w, node, cfg_.conf_max());
    promote_node(w, node, cfg_.nodes_per_entry);
    return;
  }
  tag = stored_tag(tag);
  Way* set = &ways_[size_t{index} * cfg_.ways];
  uint8_t* age = &ages_[size_t{index} * cfg_.ways];
  int hit = -1, victim = -1;
  for (uint32_t i = 0; i < cfg_.ways; ++i)
    if (set[i].valid && set[i].tag == tag) hit = static_cast<int>(i);
  if (hit < 0) {
    for (uint32_t i = 0; i < cfg_.ways && victim < 0; ++i)
      if (!set[i].valid) victim = static_cast<int>(i);
    if (victim < 0)
      for (uint32_t i = 0; i < cfg_.ways; ++i)
        if (age[i] == cfg_.ways - 1) victim = static_cast<int>(i);
    set[victim] = Way{};
    set[victim].valid = true;
    set[victim].tag = tag;
    hit = victim;
  }
  update_conf(set[hit], node, cfg_.conf_max());
  promote_node(set[hit], node, cfg_.nodes_per_entry);
  const uint8_t a = age[hit];
  for (uint32_t i = 0; i < cfg_.ways; ++i)
    if (age[i] < a) age[i]++;
  age[hit] = 0;
}

bool PredTable::demote(uint32_t index, uint64_t tag, uint64_t key) {
  if (cfg_.conf_bits == 0) return false;
  Way* w = nullptr;
  if (cfg_.unbounded) {
    auto it = map_.find(key);
    if (it != map_.end()) w = &it->second;
  } else {
    tag = stored_tag(tag);
    Way* set = &ways_[size_t{index} * cfg_.ways];
    for (uint32_t i = 0; i < cfg_.ways && !w; ++i)
      if (set[i].valid && set[i].tag == tag) w = &set[i];
  }
  if (!w) return false;
  if (w->conf > 0) w->conf--;
  return true;
}

uint64_t PredTable::entries_used() const {
  if (cfg_.unbounded) return map_.size();
  uint64_t n = 0;
  for (const Way& w : ways_) n += w.valid;
  return n;
}

}  // namespace hrpp
