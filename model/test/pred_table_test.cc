// Predictor table behaviour on small hand-built cases whose expected outcome is written here.
#include "hrpp/predictor/pred_table.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace hrpp
