// Predictor table behaviour on small hand-built cases whose expected outcome is written here.
#include "hrpp/predictor/pred_table.h"

#include <gtest/gtest.h>

#include <random>

#include "hrpp/trace/bvh.h"
#include "test_util.h"

namespace hrpp {
namespace {

TableConfig small(uint32_t sets, uint32_t ways, uint32_t k) {
  TableConfig c;
  c.sets = sets;
  c.ways = ways;
  c.nodes_per_entry = k;
  c.node_bits = 10;
  c.tag_bits = 12;
  return c;
}

std::vector<uint32_t> nodes(const Prediction& p) {
  return std::vector<uint32_t>(p.nodes.begin(), p.nodes.begin() + p.count);
}

TEST(PredTable, EmptyTableHasNoPrediction) {
  PredTable t(small(4, 2, 2));
  EXPECT_EQ(t.lookup(1, 7, 0).count, 0u);
  EXPECT_EQ(t.entries_used(), 0u);
}

TEST(PredTable, KNodeEntryKeepsMostRecentlyUsedFirst) {
  PredTable t(small(4, 2, 3));
  t.update(1, 7, 0, 100);
  EXPECT_EQ(nodes(t.lookup(1, 7, 0)), (std::vector<uint32_t>{100}));
  t.update(1, 7, 0, 200);
  t.update(1, 7, 0, 300);
  EXPECT_EQ(nodes(t.lookup(1, 7, 0)), (std::vector<uint32_t>{300, 200, 100}));
  t.update(1, 7, 0, 400);  // full: the LRU node (100) is dropped
  EXPECT_EQ(nodes(t.lookup(1, 7, 0)), (std::vector<uint32_t>{400, 300, 200}));
  t.update(1, 7, 0, 200);  // a verified node moves to the front, nothing dropped
  EXPECT_EQ(nodes(t.lookup(1, 7, 0)), (std::vector<uint32_t>{200, 400, 300}));
  t.update(1, 7, 0, 200);
  EXPECT_EQ(nodes(t.lookup(1, 7, 0)), (std::vector<uint32_t>{200, 400, 300}));
  EXPECT_EQ(t.entries_used(), 1u);
}

TEST(PredTable, WaysAreReplacedInLruOrder) {
  PredTable t(small(2, 3, 1));
  // Fill set 0 with tags 1, 2, 3 (invalid ways are used first, in order).
  t.update(0, 1, 0, 11);
  t.update(0, 2, 0, 12);
  t.update(0, 3, 0, 13);
  EXPECT_EQ(t.lookup(0, 1, 0).way, 0);
  EXPECT_EQ(t.lookup(0, 2, 0).way, 1);
  EXPECT_EQ(t.lookup(0, 3, 0).way, 2);
  // Ages: way 2 most recent (0), way 1 (1), way 0 least (2).
  EXPECT_EQ(t.age(0, 2), 0u);
  EXPECT_EQ(t.age(0, 1), 1u);
  EXPECT_EQ(t.age(0, 0), 2u);
  t.update(0, 1, 0, 21);  // touch tag 1: now tag 2 is the least recently used
  t.update(0, 4, 0, 14);  // evicts tag 2 (way 1)
  EXPECT_EQ(t.lookup(0, 2, 0).count, 0u);
  EXPECT_EQ(t.lookup(0, 4, 0).way, 1);
  EXPECT_EQ(nodes(t.lookup(0, 4, 0)), (std::vector<uint32_t>{14}));
  EXPECT_EQ(nodes(t.lookup(0, 1, 0)), (std::vector<uint32_t>{21}));
  t.update(0, 5, 0, 15);  // evicts tag 3 (way 2), the oldest now
  EXPECT_EQ(t.lookup(0, 3, 0).count, 0u);
  EXPECT_EQ(t.lookup(0, 5, 0).way, 2);
  // The other set is untouched; lookup never changes recency.
  EXPECT_EQ(t.lookup(1, 1, 0).count, 0u);
  for (int i = 0; i < 5; ++i) t.lookup(0, 1, 0);
  t.update(0, 6, 0, 16);  // LRU is tag 1 (way 0) despite the lookups
  EXPECT_EQ(t.lookup(0, 1, 0).count, 0u);
  EXPECT_EQ(t.entries_used(), 3u);
}

TEST(PredTable, AgesStayAPermutation) {
  PredTable t(small(1, 4, 2));
  uint64_t z = 1;
  for (int i = 0; i < 1000; ++i) {
    z = z * 6364136223846793005ull + 1;
    t.update(0, (z >> 40) % 7, 0, i);
    std::vector<int> seen(4, 0);
    for (uint32_t w = 0; w < 4; ++w) seen[t.age(0, w)]++;
    for (int s : seen) ASSERT_EQ(s, 1);
  }
}

TEST(PredTable, ByteAccountingFromFieldWidths) {
  // 256 sets x 4 ways, K = 2, 17-bit node ids, 22-bit tags:
  // entry = 1 valid + 22 tag + 2 count (K+1 = 3 values) + 2 * 17 = 59 bits; age 2 bits per way.
  TableConfig c = small(256, 4, 2);
  c.node_bits = 17;
  c.tag_bits = 22;
  EXPECT_EQ(c.count_bits(), 2);
  EXPECT_EQ(c.age_bits(), 2);
  EXPECT_EQ(c.entry_bits(), 59);
  EXPECT_EQ(c.set_bits(), 4u * (59 + 2));
  EXPECT_EQ(c.total_bits(), 256u * 244);
  EXPECT_EQ(PredTable(c).bytes(), 7808u);
  // Direct mapped, K = 1: no age bits, 1-bit count.
  TableConfig d = small(1024, 1, 1);
  EXPECT_EQ(d.age_bits(), 0);
  EXPECT_EQ(d.entry_bits(), 1 + 12 + 1 + 10);
  EXPECT_EQ(PredTable(d).bytes(), 1024u * 24 / 8);
  // Unbounded: the whole key per entry, counted per used entry.
  TableConfig u = small(1, 1, 4);
  u.unbounded = true;
  u.key_bits = 30;
  PredTable ut(u);
  EXPECT_EQ(ut.bytes(), 0u);
  ut.update(0, 0, 5, 1);
  ut.update(0, 0, 6, 1);
  EXPECT_EQ(u.entry_bits(), 30 + 3 + 4 * 10);
  EXPECT_EQ(ut.bytes(), (2u * 73 + 7) / 8);
  EXPECT_EQ(node_bits_for(110293), 17);
  EXPECT_EQ(node_bits_for(2), 1);
  EXPECT_EQ(node_bits_for(1024), 10);
  EXPECT_EQ(node_bits_for(1025), 11);
}

TEST(PredTable, UnboundedKeepsOneEntryPerKey) {
  TableConfig u = small(1, 1, 2);
  u.unbounded = true;
  PredTable t(u);
  for (uint64_t k = 0; k < 1000; ++k) t.update(0, 0, k, static_cast<uint32_t>(k));
  EXPECT_EQ(t.entries_used(), 1000u);
  EXPECT_EQ(nodes(t.lookup(0, 0, 777)), (std::vector<uint32_t>{777}));
}

TEST(PredTable, Validation) {
  EXPECT_EQ(small(256, 4, 2).validate(), "");
  EXPECT_NE(small(0, 4, 2).validate().find("power of two"), std::string::npos);
  EXPECT_NE(small(100, 4, 2).validate().find("power of two"), std::string::npos);
  EXPECT_NE(small(256, 0, 2).validate().find("ways"), std::string::npos);
  EXPECT_NE(small(256, 4, 0).validate().find("nodes per entry"), std::string::npos);
  EXPECT_NE(small(256, 4, 9).validate().find("nodes per entry"), std::string::npos);
}

TEST(GoUpLevel, AncestorSelection) {
  // A hand-checkable tree: 4 triangles spread along x, one per leaf with max leaf size 1.
  std::vector<Triangle> tris;
  for (int i = 0; i < 4; ++i) {
    float x = 10.f * i;
    tris.push_back({{x, 0, 0}, {x + 1, 0, 0}, {x, 1, 0}});
  }
  Bvh bvh = build_bvh(tris, {.max_leaf_size = 1});
  ASSERT_EQ(bvh.nodes.size(), 7u);  // a balanced tree: root, 2 interior, 4 leaves
  for (uint32_t i = 0; i < 7; ++i) {
    if (!bvh.nodes[i].is_leaf()) continue;
    EXPECT_EQ(bvh.depth[i], 2u);
    EXPECT_EQ(bvh.ancestor(i, 0), i);
    EXPECT_EQ(bvh.ancestor(i, 1), bvh.parent[i]);
    EXPECT_EQ(bvh.depth[bvh.ancestor(i, 1)], 1u);
    EXPECT_EQ(bvh.ancestor(i, 2), 0u);
    EXPECT_EQ(bvh.ancestor(i, 3), 0u);  // stops at the root
  }
}

// ---- confidence counters (docs/hash.md, "Confidence") -----------------------------------------

TableConfig confident(uint32_t ways, uint32_t k, int bits, int threshold) {
  TableConfig c = small(4, ways, k);
  c.conf_bits = bits;
  c.conf_threshold = threshold;
  return c;
}

TEST(PredTableConfidence, ANewEntryPredictsOnlyOnceConfirmed) {
  PredTable t(confident(2, 2, 2, 2));
  t.update(1, 7, 0, 100);  // allocated: counter 0, below the threshold
  Prediction p = t.lookup(1, 7, 0);
  EXPECT_EQ(p.count, 0u);
  EXPECT_TRUE(p.suppressed);
  EXPECT_EQ(p.way, 0);
  EXPECT_EQ(p.conf, 0u);
  EXPECT_EQ(t.entries_used(), 1u);
  t.update(1, 7, 0, 100);  // confirmed (the node is in the list): 1, still below T = 2
  EXPECT_EQ(t.lookup(1, 7, 0).count, 0u);
  EXPECT_EQ(t.lookup(1, 7, 0).conf, 1u);
  t.update(1, 7, 0, 100);  // 2: predicts
  p = t.lookup(1, 7, 0);
  EXPECT_FALSE(p.suppressed);
  EXPECT_EQ(p.conf, 2u);
  EXPECT_EQ(nodes(p), (std::vector<uint32_t>{100}));
  // No entry: not suppressed, nothing matched.
  EXPECT_FALSE(t.lookup(1, 8, 0).suppressed);
  EXPECT_EQ(t.lookup(1, 8, 0).way, -1);
}

TEST(PredTableConfidence, ConfirmationSaturatesAndAnyListedNodeConfirms) {
  PredTable t(confident(2, 2, 2, 1));
  t.update(0, 3, 0, 10);
  for (int i = 0; i < 5; ++i) t.update(0, 3, 0, 10);
  EXPECT_EQ(t.way(0, 0).conf, 3u);  // 2 bits: saturates at 3
  t.update(0, 3, 0, 20);            // inserted: reset
  EXPECT_EQ(t.way(0, 0).conf, 0u);
  EXPECT_EQ(nodes(t.lookup(0, 3, 0)), (std::vector<uint32_t>{}));
  t.update(0, 3, 0, 10);  // the older node of the list confirms too (and moves to the front)
  EXPECT_EQ(t.way(0, 0).conf, 1u);
  EXPECT_EQ(nodes(t.lookup(0, 3, 0)), (std::vector<uint32_t>{10, 20}));
  t.update(0, 3, 0, 30);  // inserted, the LRU node (20) dropped: reset
  EXPECT_EQ(t.way(0, 0).conf, 0u);
  EXPECT_EQ(t.lookup(0, 3, 0).count, 0u);
}

TEST(PredTableConfidence, AnEvictedWayStartsAtZero) {
  PredTable t(confident(2, 1, 1, 1));
  t.update(0, 1, 0, 11);
  t.update(0, 1, 0, 11);  // way 0: 1
  t.update(0, 2, 0, 12);
  t.update(0, 2, 0, 12);  // way 1: 1
  EXPECT_EQ(t.way(0, 0).conf, 1u);
  EXPECT_EQ(t.way(0, 1).conf, 1u);
  t.update(0, 3, 0, 13);  // evicts tag 1 (way 0, the LRU): the new entry starts at 0
  EXPECT_EQ(t.way(0, 0).tag, 3u);
  EXPECT_EQ(t.way(0, 0).conf, 0u);
  EXPECT_TRUE(t.lookup(0, 3, 0).suppressed);
  EXPECT_EQ(nodes(t.lookup(0, 2, 0)), (std::vector<uint32_t>{12}));
}

TEST(PredTableConfidence, DemoteCountsDownAndNeverAllocatesOrTouchesRecency) {
  PredTable t(confident(2, 2, 2, 2));
  EXPECT_FALSE(t.demote(0, 5, 0));  // no entry: nothing allocated
  EXPECT_EQ(t.entries_used(), 0u);
  t.update(0, 5, 0, 50);
  t.update(0, 5, 0, 50);
  t.update(0, 5, 0, 50);  // 2
  t.update(0, 6, 0, 60);  // way 1, most recently used; way 0 (tag 5) now the LRU
  const uint32_t age0 = t.age(0, 0), age1 = t.age(0, 1);
  EXPECT_EQ(t.lookup(0, 5, 0).count, 1u);
  EXPECT_TRUE(t.demote(0, 5, 0));  // 1: below the threshold
  EXPECT_EQ(t.way(0, 0).conf, 1u);
  EXPECT_TRUE(t.lookup(0, 5, 0).suppressed);
  EXPECT_EQ(t.age(0, 0), age0);  // recency unchanged
  EXPECT_EQ(t.age(0, 1), age1);
  EXPECT_EQ(t.way(0, 0).count, 1u);  // the node list unchanged
  EXPECT_EQ(t.way(0, 0).nodes[0], 50u);
  EXPECT_TRUE(t.demote(0, 5, 0));
  EXPECT_TRUE(t.demote(0, 5, 0));  // saturates at 0
  EXPECT_EQ(t.way(0, 0).conf, 0u);
  EXPECT_FALSE(t.demote(0, 7, 0));  // another tag of the set: nothing
  EXPECT_EQ(t.entries_used(), 2u);
  t.update(0, 5, 0, 50);  // a confirmation after demotes counts up again
  EXPECT_EQ(t.way(0, 0).conf, 1u);
}

TEST(PredTableConfidence, OneBitDemotesAreIdempotentUpdatesNot) {
  // C = 1, T = 1: an update leaves 1 when the node was listed, 0 when inserted; a demote leaves 0.
  // A demote applied twice is applied once, and so is an update of a listed node; an update that
  // inserts is not: the same update again sets the bit (so the RTL's merge of a repeated update
  // into the one before it sets the bit: MergedPairIsOnePass).
  PredTable t(confident(2, 1, 1, 1));
  t.update(2, 9, 0, 90);
  EXPECT_EQ(t.way(2, 0).conf, 0u);
  t.update(2, 9, 0, 90);  // the identical update again: a confirmation
  EXPECT_EQ(t.way(2, 0).conf, 1u);
  t.update(2, 9, 0, 90);
  EXPECT_EQ(t.way(2, 0).conf, 1u);
  EXPECT_EQ(nodes(t.lookup(2, 9, 0)), (std::vector<uint32_t>{90}));
  t.demote(2, 9, 0);
  t.demote(2, 9, 0);
  EXPECT_EQ(t.way(2, 0).conf, 0u);
  EXPECT_EQ(t.lookup(2, 9, 0).count, 0u);
}

TEST(PredTableConfidence, MergedPairIsOnePass) {
  // The RTL's merge of a request into the one before it of its set and tag
  // (docs/microarchitecture.md, "Hazards"): from any table state, the pair applied one after the
  // other leaves what the table's one pass writes: a demote behind a demote: the demote; a
  // demote behind an update: the update with the tag's bit 0; an update behind a demote: the
  // update alone; an update behind the same update: the update with the tag's bit 1. Random
  // states of a 4-way set with K = 2 (small tags and nodes, so updates hit, insert, evict and
  // demote often).
  std::mt19937 rng(7);
  for (int trial = 0; trial < 4000; ++trial) {
    PredTable t(confident(4, 2, 1, 1));
    const int steps = int(rng() % 24);
    for (int i = 0; i < steps; ++i) {
      if (rng() % 4 == 0)
        t.demote(1, rng() % 6, 0);
      else
        t.update(1, rng() % 6, 0, rng() % 4);
    }
    const uint64_t tag = rng() % 6;
    const uint32_t node = rng() % 4;
    const bool first_demote = rng() % 2, second_demote = rng() % 2;
    PredTable pair = t, pass = t;
    for (const bool demote : {first_demote, second_demote}) {
      if (demote)
        pair.demote(1, tag, 0);
      else
        pair.update(1, tag, 0, node);
    }
    // One pass: the last update, if any, else the demote; then the bit the merge fixes.
    if (first_demote && second_demote)
      pass.demote(1, tag, 0);
    else
      pass.update(1, tag, 0, node);
    const bool fixed = !first_demote;  // the first is an update: the second fixes the bit
    for (uint32_t w = 0; w < 4; ++w) {
      const Way& a = pass.way(1, w);
      const Way& b = pair.way(1, w);
      ASSERT_EQ(a.valid, b.valid) << "trial " << trial;
      ASSERT_EQ(pass.age(1, w), pair.age(1, w)) << "trial " << trial;
      if (!a.valid) continue;
      ASSERT_EQ(a.tag, b.tag);
      ASSERT_EQ(a.count, b.count);
      for (uint32_t k = 0; k < a.count; ++k) ASSERT_EQ(a.nodes[k], b.nodes[k]);
      const uint32_t want = fixed && a.tag == tag ? (second_demote ? 0u : 1u) : a.conf;
      ASSERT_EQ(b.conf, want) << "trial " << trial << " way " << w;
    }
  }
}

TEST(PredTableConfidence, UnboundedTableKeepsACounterPerKey) {
  TableConfig u = confident(1, 2, 1, 1);
  u.unbounded = true;
  PredTable t(u);
  t.update(0, 0, 42, 7);
  EXPECT_TRUE(t.lookup(0, 0, 42).suppressed);
  t.update(0, 0, 42, 7);
  EXPECT_EQ(nodes(t.lookup(0, 0, 42)), (std::vector<uint32_t>{7}));
  EXPECT_TRUE(t.demote(0, 0, 42));
  EXPECT_TRUE(t.lookup(0, 0, 42).suppressed);
  EXPECT_FALSE(t.demote(0, 0, 43));
  EXPECT_EQ(t.entries_used(), 1u);
}

TEST(PredTableConfidence, WithoutCountersNothingChanges) {
  // C = 0: every entry predicts at once, a demote is a no-op; the same state as before.
  PredTable t(small(4, 2, 2));
  t.update(1, 7, 0, 100);
  Prediction p = t.lookup(1, 7, 0);
  EXPECT_EQ(nodes(p), (std::vector<uint32_t>{100}));
  EXPECT_FALSE(p.suppressed);
  t.update(1, 7, 0, 100);
  EXPECT_EQ(t.way(1, 0).conf, 0u);
  EXPECT_FALSE(t.demote(1, 7, 0));
  EXPECT_EQ(nodes(t.lookup(1, 7, 0)), (std::vector<uint32_t>{100}));
}

TEST(PredTableConfidence, StorageAndValidation) {
  TableConfig c = confident(4, 1, 0, 1);
  const int base = c.entry_bits();
  for (int bits : {1, 2, 3}) {
    c.conf_bits = bits;
    EXPECT_EQ(c.entry_bits(), base + bits);
    EXPECT_EQ(c.total_bits(), uint64_t{4} * 4 * (base + bits + 2));
  }
  // The study's 256 x 4, K = 1 table with 1 confidence bit: 1,024 bits more.
  TableConfig m = small(256, 4, 1);
  m.node_bits = 21;
  m.tag_bits = 8;
  const uint64_t without = m.total_bits();
  m.conf_bits = 1;
  EXPECT_EQ(m.total_bits(), without + 1024);
  TableConfig u = confident(1, 4, 2, 1);
  u.unbounded = true;
  u.key_bits = 30;
  EXPECT_EQ(u.entry_bits(), 30 + 3 + 4 * 10 + 2);
  EXPECT_EQ(confident(4, 1, 1, 1).validate(), "");
  EXPECT_EQ(confident(4, 1, 3, 7).validate(), "");
  EXPECT_EQ(confident(4, 1, 0, 5).validate(), "");  // the threshold is unused without counters
  EXPECT_NE(confident(4, 1, 4, 1).validate().find("confidence bits must be 0..3"),
            std::string::npos);
  EXPECT_NE(confident(4, 1, -1, 1).validate().find("confidence bits"), std::string::npos);
  EXPECT_NE(confident(4, 1, 1, 2).validate().find("threshold must be 1..1"), std::string::npos);
  EXPECT_NE(confident(4, 1, 2, 0).validate().find("threshold must be 1..3"), std::string::npos);
}

}  // namespace
}  // namespace hrpp
