// The predictor table (docs/hash.md, "Predictor table"). Finite: S sets x W ways, each way a
// valid bit, a tag, a node count, up to K node ids in most-recently-used-first order and a C-bit
// confidence counter (C = 0: none); each set has W age counters for true LRU replacement of ways.
// Unbounded: one entry per key (the limit study). This class is shared by the untimed model and
// the cycle model.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace hrpp {

constexpr int kMaxNodesPerEntry = 8;

struct TableConfig {
  bool unbounded = false;
  uint32_t sets = 256;  // power of two
  uint32_t ways = 4;
  uint32_t nodes_per_entry = 2;  // K
  int node_bits = 20;            // width of a node id (BVH node index)
  int tag_bits = 22;             // stored tag bits: the hash's full tag width, or fewer (then
                                 // different keys of one set may alias: documented, counted as
                                 // false positives when the prediction fails)
  int key_bits = 30;             // unbounded table: the whole key is stored
  // Confidence (docs/hash.md, "Confidence"): a C-bit saturating counter per way (0..3 bits; 0:
  // none, every entry predicts); an entry predicts only when its counter is >= the threshold T
  // (1..2^C - 1; unused when C = 0).
  int conf_bits = 0;       // C
  int conf_threshold = 1;  // T

  std::string validate() const;
  /// Bits of storage, counted as the RTL stores them.
  int count_bits() const;  // node count field: ceil(log2(K + 1))
  int age_bits() const;    // per way: ceil(log2(W))
  int entry_bits() const;  // valid + tag + count + K node ids + C (the key for unbounded)
  uint32_t conf_max() const { return (1u << conf_bits) - 1; }  // the counter's saturation
  uint64_t set_bits() const;                                   // W entries + W ages
  uint64_t total_bits(uint64_t unbounded_entries = 0) const;
};

/// Node bits needed to name every node of a BVH with n nodes.
int node_bits_for(size_t num_nodes);

struct Prediction {
  uint32_t count = 0;                               // 0 also when suppressed
  std::array<uint32_t, kMaxNodesPerEntry> nodes{};  // MRU first
  int way = -1;                                     // finite table: the way that matched
  uint32_t conf = 0;        // the matching entry's confidence counter (0 when none matched)
  bool suppressed = false;  // an entry matched, its counter below the threshold: no prediction
};

struct Way {
  bool valid = false;
  uint64_t tag = 0;
  uint32_t count = 0;
  std::array<uint32_t, kMaxNodesPerEntry> nodes{};
  uint32_t conf = 0;  // the confidence counter (always 0 when conf_bits = 0)
};

class PredTable {
 public:
  explicit PredTable(const TableConfig& cfg);

  /// Read-only lookup. A matching entry whose confidence counter is below the threshold returns
  /// no nodes (count 0, `suppressed`; `way` and `conf` are still set).
  Prediction lookup(uint32_t index, uint64_t tag, uint64_t key) const;
  /// The part of a tag the table stores (its low tag_bits bits).
  uint64_t stored_tag(uint64_t tag) const;
  /// Update after a ray's walk: `node` becomes the most recently used node of the key's entry
  /// (moved to the front if present, else inserted at the front, the LRU node dropped when the
  /// entry is full). A missing entry is allocated (the first invalid way of the set, else the
  /// least recently used way). The way becomes the set's most recently used. Confidence: when
  /// `node` was already in the entry's list, the counter counts up (saturating); when it is
  /// inserted (or the entry allocated), the counter becomes 0.
  void update(uint32_t index, uint64_t tag, uint64_t key, uint32_t node);
  /// A prediction the ray was given failed and the ray wrote nothing: the matching entry's
  /// confidence counter counts down (saturating at 0). Nothing else changes: no recency change,
  /// no allocation; no entry, or conf_bits = 0: nothing at all. Returns whether an entry matched.
  bool demote(uint32_t index, uint64_t tag, uint64_t key);

  void clear();
  uint64_t entries_used() const;
  uint64_t bytes() const { return (cfg_.total_bits(entries_used()) + 7) / 8; }
  const TableConfig& config() const { return cfg_; }

  // Finite-table state, for the cycle model and tests.
  const Way& way(uint32_t set, uint32_t w) const { return ways_[set * cfg_.ways + w]; }
  uint32_t age(uint32_t set, uint32_t w) const { return ages_[set * cfg_.ways + w]; }

 private:
  TableConfig cfg_;
  std::vector<Way> ways_;
  std::vector<uint8_t> ages_;  // 0 = most recently used
  std::unordered_map<uint64_t, Way> map_;
};

/// Moves `node` to the front of an MRU-ordered list of at most k nodes.
void promote_node(Way& w, uint32_t node, uint32_t k);

}  // namespace hrpp
