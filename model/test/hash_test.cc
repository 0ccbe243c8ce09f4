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
#include "hrpp/util/rng.h"

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

// ---- Octahedral direction code (docs/hash.md, "Octahedral direction code") ----

using test::ref_oct_dir;

uint32_t oct(float x, float y, float z, int b) {
  return oct_dir_field({bits(x), bits(y), bits(z)}, b);
}
uint32_t oct_ref(float x, float y, float z, int b) { return ref_oct_dir({x, y, z}, b); }
// u << b | v from sign and magnitude bins.
uint32_t oct_code(uint32_t su, uint32_t mu, uint32_t sv, uint32_t mv, int b) {
  return (((su << (b - 1)) | mu) << b) | (sv << (b - 1)) | mv;
}

// A unit direction uniformly distributed on the sphere (z = 1 - 2u, phi = 2 pi u'), in float.
std::array<float, 3> unit_dir(uint64_t seed, uint64_t i) {
  const double z = 1.0 - 2.0 * uniform01(seed, i, 0), phi = 2 * M_PI * uniform01(seed, i, 1);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)};
}

HashConfig improved_oct(int ob = 5, int k = -3, int db = 3, CombineMode c = CombineMode::kConcat) {
  HashConfig h = improved(ob, k, db);
  h.dir_code = DirCode::kOct;
  h.combine = c;
  return h;
}

TEST(HashOct, AxisAlignedDirections) {
  for (int b = 1; b <= 8; ++b) {
    const uint32_t top = (1u << (b - 1)) - 1;                       // the largest magnitude bin
    EXPECT_EQ(oct(0, 0, 1, b), oct_code(0, 0, 0, 0, b)) << b;       // +z: the centre
    EXPECT_EQ(oct(0, 0, -1, b), oct_code(0, top, 0, top, b)) << b;  // -z: folded to a corner
    EXPECT_EQ(oct(1, 0, 0, b), oct_code(0, top, 0, 0, b)) << b;     // +x
    EXPECT_EQ(oct(-1, 0, 0, b), oct_code(1, top, 0, 0, b)) << b;    // -x
    EXPECT_EQ(oct(0, 1, 0, b), oct_code(0, 0, 0, top, b)) << b;     // +y
    EXPECT_EQ(oct(0, -1, 0, b), oct_code(0, 0, 1, top, b)) << b;    // -y
    // -0 components are +0 (canonical): -0 in z is the upper hemisphere, -0 in x a plus sign.
    EXPECT_EQ(oct(-0.f, -0.f, 1, b), oct(0, 0, 1, b)) << b;
    EXPECT_EQ(oct(1, -0.f, -0.f, b), oct(1, 0, 0, b)) << b;
    EXPECT_EQ(oct(-0.f, 1, -0.f, b), oct(0, 1, 0, b)) << b;
    // The zero direction (never hashed): L = 0, every compare 0 >= 0 holds.
    EXPECT_EQ(oct(0, -0.f, 0, b), oct_code(0, top, 0, top, b)) << b;
  }
  // b = 1: only the signs of x and y.
  EXPECT_EQ(oct(-0.3f, 0.4f, -0.5f, 1), 0b10u);
  EXPECT_EQ(oct(0.3f, -0.4f, 0.5f, 1), 0b01u);
}

TEST(HashOct, ExactBinBoundaries) {
  // (1, 1, 0) / 2: u = v = 1/2 exactly, the boundary of bin 2^(b-2) (b >= 2), which it belongs to.
  for (int b = 2; b <= 8; ++b) {
    const uint32_t h4 = 1u << (b - 2);
    EXPECT_EQ(oct(0.5f, 0.5f, 0, b), oct_code(0, h4, 0, h4, b)) << b;
    EXPECT_EQ(oct(0.7f, 0.7f, 0, b), oct_code(0, h4, 0, h4, b)) << b;  // only the ratio matters
    EXPECT_EQ(oct(-0.5f, 0.5f, -0.f, b), oct_code(1, h4, 0, h4, b)) << b;
  }
  // One ulp less on y: u just above 1/2, v just below.
  const float below = std::nextafter(0.5f, 0.f);
  EXPECT_EQ(oct(0.5f, below, 0, 2), oct_code(0, 1, 0, 0, 2));
  // (1, 1, -2) / 4: lower hemisphere, u' = v' = (1 + 2) / 4 = 3/4: bin 3 of 4 (b = 3) exactly.
  EXPECT_EQ(oct(0.25f, 0.25f, -0.5f, 3), oct_code(0, 3, 0, 3, 3));
  // y one ulp below 1/4: u' = 1 - |v| just above 3/4 (bin 3), v' = 1 - |u| just below (bin 2).
  EXPECT_EQ(oct(0.25f, below / 2, -0.5f, 3), oct_code(0, 3, 0, 2, 3));
  // (1, 2, 1) / 4 upper: u = 1/4 (bin 1 of 4 exactly), v = 1/2 (bin 2).
  EXPECT_EQ(oct(0.25f, 0.5f, 0.25f, 3), oct_code(0, 1, 0, 2, 3));
}

TEST(HashOct, DenormalsAndWildlyDifferentExponents) {
  const float den = flt(0x00000001), big = 1e30f;
  for (int b = 1; b <= 8; ++b) {
    EXPECT_EQ(oct(den, -den, 1, b), oct(0, 0, 1, b));      // denormals are zero
    EXPECT_EQ(oct(0.5f, 0, -den, b), oct(0.5f, 0, 0, b));  // -denormal z: upper hemisphere
    // A component 2^24 below the largest aligns to 0; 2^23 below to 1 (truncated alignment).
    EXPECT_EQ(oct(1, 0, -std::ldexp(1.f, -24), b), oct(1, 0, 0, b));
    EXPECT_EQ(oct(1, std::ldexp(1.f, -23), 0, b), oct(1, 0, 0, b));
    EXPECT_EQ(oct(big, -1e-30f, 1e-20f, b), oct_code(0, (1u << (b - 1)) - 1, 1, 0, b));
  }
  // Lower hemisphere with a tiny z that aligns to 0: the fold still applies (s_z = 1).
  EXPECT_EQ(oct(1, 0, -std::ldexp(1.f, -24), 3), oct_code(0, 3, 0, 0, 3));
  EXPECT_EQ(oct(0, 1, -std::ldexp(1.f, -30), 3), oct_code(0, 0, 0, 3, 3));
}

TEST(HashOct, InfinityAndNaNAreTotal) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
  for (int b = 1; b <= 8; ++b) {
    EXPECT_EQ(oct(nan, 0, 0, b), oct(inf, 0, 0, b));  // every NaN is +inf
    EXPECT_EQ(oct(flt(0xFFC12345), 0.5f, 0, b), oct(inf, 0.5f, 0, b));
    EXPECT_EQ(oct(inf, 0.5f, 0, b), oct(1, 0, 0, b));  // 0.5 is 2^-128 of inf's 2^128: aligns to 0
    EXPECT_EQ(oct(-inf, 0, 0, b), oct(-1, 0, 0, b));
    for (float x : {inf, -inf, nan, 1e38f, -3.f})
      for (float y : {inf, -inf, nan, 0.f, 2.f})
        for (float z : {inf, -inf, nan, -0.f, -1.f}) {
          const uint32_t f = oct(x, y, z, b);
          EXPECT_LT(f, 1u << (2 * b));
          EXPECT_EQ(f, oct_ref(x, y, z, b)) << x << " " << y << " " << z << " b=" << b;
        }
  }
}

TEST(HashOct, MatchesReferenceOnRandomPatternsAndSpecialClasses) {
  std::vector<uint32_t> special = {0,          0x80000000, 1,          0x807FFFFF, 0x00800000,
                                   0x80800000, 0x3F800000, 0xBF800000, 0x3F7FFFFF, 0x3F000000,
                                   0xBF000000, 0x7F7FFFFF, 0xFF7FFFFF, 0x7F800000, 0xFF800000,
                                   0x7FC00000, 0xFFC00000, 0x33800000, 0x34000000, 0xB3800000};
  uint64_t z = 777;
  auto next = [&] {
    z = z * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint32_t>(z >> 32);
  };
  for (int b = 1; b <= 8; ++b) {
    for (uint32_t x : special)
      for (uint32_t y : special)
        for (uint32_t w : special)
          ASSERT_EQ(oct_dir_field({x, y, w}, b), ref_oct_dir({flt(x), flt(y), flt(w)}, b))
              << std::hex << x << " " << y << " " << w << std::dec << " b=" << b;
    for (int i = 0; i < 100000; ++i) {
      // Random patterns, and random patterns with exponents near each other (most of the
      // interesting alignments): exponent 120..127 with a random sign and mantissa.
      std::array<uint32_t, 3> p = {next(), next(), next()};
      if (i & 1)
        for (uint32_t& c : p) c = (c & 0x807FFFFF) | ((120 + (c >> 23) % 8) << 23);
      ASSERT_EQ(oct_dir_field(p, b), ref_oct_dir({flt(p[0]), flt(p[1]), flt(p[2])}, b))
          << std::hex << p[0] << " " << p[1] << " " << p[2] << std::dec << " b=" << b;
    }
  }
}

TEST(HashOct, MatchesReferenceOnRandomUnitVectors) {
  for (int b = 1; b <= 8; ++b)
    for (uint64_t i = 0; i < 100000; ++i) {
      const auto d = unit_dir(42, i);
      ASSERT_EQ(oct_dir_field({bits(d[0]), bits(d[1]), bits(d[2])}, b), ref_oct_dir(d, b))
          << d[0] << " " << d[1] << " " << d[2] << " b=" << b;
    }
}

TEST(HashOct, EveryCodeIsReachableByUnitDirections) {
  for (int b = 1; b <= 4; ++b) {
    std::vector<uint64_t> seen(size_t{1} << (2 * b), 0);
    for (uint64_t i = 0; i < 200000; ++i) {
      const auto d = unit_dir(7, i);
      ++seen.at(oct_dir_field({bits(d[0]), bits(d[1]), bits(d[2])}, b));
    }
    for (size_t c = 0; c < seen.size(); ++c) EXPECT_GT(seen[c], 0u) << "b=" << b << " code " << c;
  }
}

TEST(HashOct, KeyCombinationAndWidths) {
  const std::array<uint32_t, 6> r = {bits(1.3f),  bits(-2.7f), bits(0.1f),
                                     bits(-0.6f), bits(0.0f),  bits(-0.8f)};
  for (int ob : {1, 3, 5, 16})
    for (int db : {1, 3, 8}) {
      const HashConfig cat = improved_oct(ob, -3, db),
                       x = improved_oct(ob, -3, db, CombineMode::kXor);
      ASSERT_EQ(cat.validate(), "");
      ASSERT_EQ(x.validate(), "");
      EXPECT_EQ(cat.dir_field_bits(), 2 * db);
      EXPECT_EQ(cat.key_bits(), 3 * ob + 2 * db);
      EXPECT_EQ(x.key_bits(), std::max(3 * ob, 2 * db));
      uint64_t o = 0;
      for (int i = 0; i < 3; ++i) o = (o << ob) | grid_origin_field(r[i], -3, ob);
      const uint64_t d = oct_dir_field({r[3], r[4], r[5]}, db);
      EXPECT_EQ(hash_key(r, cat), (o << (2 * db)) | d);
      EXPECT_EQ(hash_key(r, x), o ^ d);
      std::array<float, 6> f;
      for (int i = 0; i < 6; ++i) f[i] = flt(r[i]);
      EXPECT_EQ(hash_key(r, cat), test::ref_hash_key(f, cat));
      EXPECT_EQ(hash_key(r, x), test::ref_hash_key(f, x));
    }
  // The grid code (the default) is unchanged by the new field.
  EXPECT_EQ(improved().dir_code, DirCode::kGrid);
  EXPECT_EQ(improved(5, -3, 3).key_bits(), 24);
}

TEST(HashOct, ConfigValidation) {
  EXPECT_NE(improved_oct(5, -3, 9).validate().find("must be 1..8"), std::string::npos);
  EXPECT_NE(improved_oct(5, -3, 0).validate(), "");
  HashConfig f = faithful();
  f.dir_code = DirCode::kOct;
  EXPECT_NE(f.validate().find("applies only to the improved hash"), std::string::npos);
  HashConfig m = improved_oct();
  m.variant = HashVariant::kMicro21;
  EXPECT_NE(m.validate().find("applies only to the improved hash"), std::string::npos);
  EXPECT_EQ(improved_oct(5, -3, 8).validate(), "");
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
