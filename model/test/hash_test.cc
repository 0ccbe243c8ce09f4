// The hash test vectors H1-H8 of ../shared/HARD_CASES.md, key folding, and an exhaustive sweep of
// all 2^32 patterns of one component against deliberately simple reference implementations.
#include "hrpp/predictor/hash.h"

#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <thread>

#include "hash_ref.h"

namespace hrpp {
namespace {

uint32_t bits(float f) { return std::bit_cast<uint32_t>(f); }
float flt(uint32_t b) { return std::bit_cast<float>(b); }

HashConfig faithful(int p = 6, int e = 3) {
  HashConfig c;
  c.variant = HashVariant::kFaithful;
  c.precision = p;
  c.exp_bits = e;
  c.index_bits = 0;
  return c;
}
HashConfig improved(int ob = 5, int k = -3, int db = 3) {
  HashConfig c;
  c.variant = HashVariant::kImproved;
  c.origin_bits = ob;
  c.origin_cell_exp = k;
  c.dir_bits = db;
  c.combine = CombineMode::kConcat;
  c.index_bits = 0;
  return c;
}

// Key of a ray whose six components are all `b` (exercises every field at once).
uint64_t key_all(uint32_t b, const HashConfig& c) { return hash_key({b, b, b, b, b, b}, c); }
// Key of a ray with origin (x, 0.5, 0.25) and direction (d, 0.5, -0.5).
uint64_t key_x(uint32_t x, uint32_t d, const HashConfig& c) {
  return hash_key({x, bits(0.5f), bits(0.25f), d, bits(0.5f), bits(-0.5f)}, c);
}

const std::vector<HashConfig>& configs() {
  static const std::vector<HashConfig> all = [] {
    std::vector<HashConfig> v;
    for (int p : {1, 2, 6, 10, 23})
      for (int e : {0, 3, 8}) {
        HashConfig c = faithful(p, e);
        if (c.validate().empty()) v.push_back(c);
        c.combine = CombineMode::kConcat;
        if (c.validate().empty()) v.push_back(c);
      }
    for (int ob : {1, 5, 10, 16})
      for (int k : {-20, -3, 0, 7})
        for (int db : {1, 3, 8})
          if (improved(ob, k, db).validate().empty()) v.push_back(improved(ob, k, db));
    return v;
  }();
  return all;
}

TEST(Hash, H1_PlusAndMinusZeroSameKey) {
  for (const auto& c : configs()) {
    EXPECT_EQ(key_all(0x00000000, c), key_all(0x80000000, c));
    EXPECT_EQ(key_x(0x80000000, 0x80000000, c), key_x(0, 0, c));
  }
}

TEST(Hash, H2_DenormalsHashAsZeroFltMinDistinct) {
  for (const auto& c : configs())
    for (uint32_t d : {0x00000001u, 0x007FFFFFu, 0x80000001u, 0x80400000u}) {
      EXPECT_EQ(key_x(d, 0, c), key_x(0, 0, c));
      EXPECT_EQ(key_x(0, d, c), key_x(0, 0, c));
    }
  // FLT_MIN (0x00800000) differs from +0 in every faithful configuration with an exponent bit of
  // weight 1 (E = 8) or any mantissa... documented: it differs when E = 8.
  EXPECT_NE(key_x(0x00800000, 0, faithful(6, 8)), key_x(0, 0, faithful(6, 8)));
  // With E < 8 the top exponent bits of FLT_MIN are 0 and its mantissa is 0: same key as +0
  // (documented in docs/hash.md).
  EXPECT_EQ(key_x(0x00800000, 0, faithful(6, 3)), key_x(0, 0, faithful(6, 3)));
}

TEST(Hash, H3_OneAndOneUlpBelow) {
  const uint32_t one = 0x3F800000, below = 0x3F7FFFFF;
  // Faithful: 1.0 has mantissa 0 and 0x3F7FFFFF all ones: different keys for every P >= 1.
  for (int p : {1, 6, 23}) EXPECT_NE(key_x(one, 0, faithful(p)), key_x(below, 0, faithful(p)));
  // Improved direction: 1.0 saturates to the top code, which 1 - ulp also reaches: same key.
  for (int db : {1, 3, 8})
    EXPECT_EQ(key_x(0, one, improved(5, -3, db)), key_x(0, below, improved(5, -3, db)));
  // Improved origin: 1.0 is a cell boundary whenever the cell size 2^k <= 1.
  EXPECT_NE(key_x(one, 0, improved(5, -3)), key_x(below, 0, improved(5, -3)));
  EXPECT_EQ(key_x(one, 0, improved(5, 2)), key_x(below, 0, improved(5, 2)));
}

TEST(Hash, H4_InfinitiesAndFltMaxDistinct) {
  const uint32_t pinf = 0x7F800000, ninf = 0xFF800000, fmax = 0x7F7FFFFF;
  for (const auto& c : configs()) {
    if (c.variant == HashVariant::kImproved && c.origin_bits < 2) continue;  // documented
    EXPECT_NE(key_x(pinf, 0, c), key_x(ninf, 0, c));
    EXPECT_NE(key_x(pinf, 0, c), key_x(fmax, 0, c));
    EXPECT_NE(key_x(ninf, 0, c), key_x(fmax, 0, c));
  }
}

TEST(Hash, H5_OneCanonicalNaNKeyNeverThatOf1e30) {
  const uint32_t nans[] = {0x7FC00000, 0xFFC00000, 0x7F800001, 0x7FC12345, 0xFFFFFFFF};
  const uint32_t big = bits(1e30f);
  for (const auto& c : configs()) {
    for (uint32_t n : nans) {
      EXPECT_EQ(key_x(n, 0, c), key_x(nans[0], 0, c));
      EXPECT_EQ(key_x(0, n, c), key_x(0, nans[0], c));
      EXPECT_EQ(canonical_bits(n), 0x7F800000u);
    }
    // Origin component: never the key of 1e30.
    if (!(c.variant == HashVariant::kImproved && c.origin_bits < 2)) {
      EXPECT_NE(key_x(nans[0], 0, c), key_x(big, 0, c));
    }
  }
  // Rays with NaN fields are invalid and never hashed at all (predictor_test checks that).
  EXPECT_NE(validate_ray({{std::nanf(""), 0, 0}, {0, 0, 1}}), RayError::kNone);
}

TEST(Hash, H6_NegativeZeroDirection) {
  for (const auto& c : configs())
    EXPECT_EQ(hash_key({0, 0, 0, bits(-1.f), bits(0.f), 0}, c),
              hash_key({0, 0, 0, bits(-1.f), bits(-0.f), 0}, c));
}

TEST(Hash, H7_FlushToZeroOnAndOff) {
  // A product that underflows: with flush-to-zero it is 0, without it a denormal.
  volatile float a = 1e-20f, b = 1e-25f;
  const float exact = a * b;  // denormal (FTZ off, the default here)
  ASSERT_EQ(std::fpclassify(exact), FP_SUBNORMAL);
  for (const auto& c : configs()) {
    EXPECT_EQ(key_x(bits(exact), bits(-exact), c), key_x(bits(0.f), bits(-0.f), c));
  }
}

TEST(Hash, SplitKeyNeverAliasesDifferentKeysInOneSet) {
  HashConfig c = faithful(6, 3);
  c.index_bits = 8;
  std::map<std::pair<uint32_t, uint64_t>, uint64_t> seen;
  for (uint64_t i = 0; i < 200000; ++i) {
    const uint64_t key = (i * 0x9E3779B97F4A7C15ull) >> (64 - c.key_bits());
    const HashKey k = split_key(key, c);
    EXPECT_LT(k.index, 256u);
    EXPECT_EQ(k.tag, key >> 8);
    auto [it, fresh] = seen.emplace(std::make_pair(k.index, k.tag), key);
    if (!fresh) {
      EXPECT_EQ(it->second, key) << "two keys share set and tag";
    }
  }
  // The index is the XOR of all 8-bit chunks.
  HashKey k = split_key(0x3'1234'5678ull, c);
  EXPECT_EQ(k.index, (0x78u ^ 0x56u ^ 0x34u ^ 0x12u ^ 0x3u));
}

TEST(Hash, ConfigValidation) {
  EXPECT_EQ(faithful(6, 3).validate(), "");
  EXPECT_NE(faithful(24, 3).validate().find("precision must be 1..23"), std::string::npos);
  EXPECT_NE(faithful(0, 3).validate(), "");
  EXPECT_NE(faithful(6, 9).validate().find("exponent bits"), std::string::npos);
  HashConfig c = faithful(10, 8);
  c.combine = CombineMode::kConcat;  // 6 * 19 = 114 bits
  EXPECT_NE(c.validate().find("at most 64"), std::string::npos);
  HashConfig d = faithful(1, 0);  // 3 * 2 = 6 key bits
  d.index_bits = 8;
  EXPECT_NE(d.validate().find("only 6 bits"), std::string::npos);
  EXPECT_NE(improved(0).validate(), "");
  EXPECT_NE(improved(5, -3, 17).validate(), "");
}

TEST(Hash, CellExponentCoversTheScene) {
  Aabb b{{-3, 0, 0}, {5, 1, 2}};         // extent 8
  EXPECT_EQ(cell_exp_for(b, 5), 3 - 5);  // 32 cells of 0.25
  Aabb c{{0, 0, 0}, {1000, 9, 9}};
  EXPECT_EQ(cell_exp_for(c, 4), 10 - 4);
}

// ---- H8: exhaustive sweep against simple reference implementations ----

using test::ref_faithful;
using test::ref_grid_dir;
using test::ref_grid_origin;

struct Sweep {
  const char* name;
  uint32_t (*fast)(uint32_t);
  uint32_t (*ref)(uint32_t);
};

// HRPP_H8_STRIDE=N (make test-sanitize sets it) checks every N-th pattern (N odd, so the low
// mantissa bits still take every value) instead of all 2^32: the instrumented sweep would take
// tens of minutes. Unset (the default, `make test`): every pattern.
uint64_t h8_stride() {
  const char* e = std::getenv("HRPP_H8_STRIDE");
  if (!e || !*e) return 1;
  const unsigned long long v = std::strtoull(e, nullptr, 10);
  if (v == 0) ADD_FAILURE() << "HRPP_H8_STRIDE must be a positive integer, got '" << e << "'";
  return v ? v : 1;
}

void exhaustive(const Sweep& s) {
  const uint64_t stride = h8_stride();
  if (stride > 1)
    std::cerr << s.name << ": reduced sweep, every " << stride << "th of the 2^32 patterns "
              << "(HRPP_H8_STRIDE)\n";
  const unsigned nt = std::max(1u, std::thread::hardware_concurrency());
  std::atomic<uint64_t> mismatches{0};
  std::atomic<uint32_t> first_bad{0};
  std::vector<std::thread> threads;
  for (unsigned t = 0; t < nt; ++t)
    threads.emplace_back([&, t] {
      const uint64_t n = ((uint64_t{1} << 32) + stride - 1) / stride;
      const uint64_t lo = n * t / nt, hi = n * (t + 1) / nt;
      uint64_t bad = 0;
      for (uint64_t i = lo; i < hi; ++i) {
        const uint64_t b = i * stride;
        const uint32_t x = static_cast<uint32_t>(b);
        if (s.fast(x) != s.ref(x)) {
          if (!bad++) first_bad = x;
        }
      }
      mismatches += bad;
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(mismatches.load(), 0u)
      << s.name << ": first mismatch at 0x" << std::hex << first_bad.load();
}

TEST(Hash, H8_ExhaustiveFaithfulField) {
  exhaustive({"faithful P=6 E=3", [](uint32_t b) { return faithful_field(b, 3, 6); },
              [](uint32_t b) { return ref_faithful(flt(b), 3, 6); }});
}

TEST(Hash, H8_ExhaustiveGridOriginField) {
  exhaustive({"grid origin k=-3 G=5", [](uint32_t b) { return grid_origin_field(b, -3, 5); },
              [](uint32_t b) { return ref_grid_origin(flt(b), -3, 5); }});
}

TEST(Hash, H8_ExhaustiveGridDirField) {
  exhaustive({"grid direction G=3", [](uint32_t b) { return grid_dir_field(b, 3); },
              [](uint32_t b) { return ref_grid_dir(flt(b), 3); }});
}

TEST(Hash, H8_DenseRandomOverManyConfigurations) {
  // Every parameter set the RTL supports, on random patterns plus every special class.
  std::vector<uint32_t> pats = {0,          0x80000000, 1,           0x807FFFFF,
                                0x00800000, 0x3F800000, 0x3F7FFFFF,  0x7F7FFFFF,
                                0xFF7FFFFF, 0x7F800000, 0xFF800000,  0x7FC00000,
                                0xFFC00000, 0x7F800001, bits(1e30f), bits(-1e-30f)};
  uint64_t z = 12345;
  for (int i = 0; i < 20000; ++i) {
    z = z * 6364136223846793005ull + 1442695040888963407ull;
    pats.push_back(static_cast<uint32_t>(z >> 32));
  }
  for (int p = 1; p <= 23; ++p)
    for (int e = 0; e <= 8; ++e)
      for (uint32_t b : pats) ASSERT_EQ(faithful_field(b, e, p), ref_faithful(flt(b), e, p));
  for (int g = 1; g <= 16; ++g) {
    for (int k : {-149, -60, -20, -3, 0, 5, 40, 127})
      for (uint32_t b : pats) ASSERT_EQ(grid_origin_field(b, k, g), ref_grid_origin(flt(b), k, g));
    for (uint32_t b : pats) ASSERT_EQ(grid_dir_field(b, g), ref_grid_dir(flt(b), g));
  }
}

}  // namespace
}  // namespace hrpp
