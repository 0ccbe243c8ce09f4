// Deliberately simple reference implementations of the hash (docs/hash.md), written from the
// specification with the standard library's float classification and double arithmetic instead
// of bit manipulation. Used by the exhaustive sweep H8 (hash_test.cc) and the hash fuzz target
// (fuzz/fuzz_hash.cc).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "hrpp/predictor/hash.h"

namespace hrpp::test {

// Reference faithful field: classify with the standard library, then take the fields.
inline uint32_t ref_faithful(float x, int e, int p) {
  if (std::isnan(x)) x = std::numeric_limits<float>::infinity();
  if (x == 0 || std::fpclassify(x) == FP_SUBNORMAL) return 0;
  const uint32_t sign = std::signbit(x) ? 1 : 0;
  uint32_t exp_field, man_field;
  if (std::isinf(x)) {
    exp_field = 255;
    man_field = 0;
  } else {
    int ex;
    const float m = std::frexp(std::fabs(x), &ex);  // |x| = m * 2^ex, m in [0.5, 1)
    exp_field = static_cast<uint32_t>(ex - 1 + 127);
    man_field = static_cast<uint32_t>(std::ldexp(static_cast<double>(m) * 2 - 1, 23));
  }
  return (sign << (e + p)) | ((e ? exp_field >> (8 - e) : 0) << p) | (man_field >> (23 - p));
}

// Reference grid origin field: exact floor in double, then the residue mod 2^g.
inline uint32_t ref_grid_origin(float x, int k, int g) {
  if (std::isnan(x) || x == std::numeric_limits<float>::infinity()) return (1u << g) - 1;
  if (x == -std::numeric_limits<float>::infinity()) return 1u << (g - 1);
  if (std::fpclassify(x) == FP_SUBNORMAL) x = 0;
  const double v = std::floor(std::ldexp(static_cast<double>(x), -k));  // exact
  double r = std::fmod(v, std::ldexp(1.0, g));                          // exact
  if (r < 0) r += std::ldexp(1.0, g);
  return static_cast<uint32_t>(r);
}

// Reference grid direction field: floor(d * 2^(g-1)) in double, clamped, as g-bit two's complement.
inline uint32_t ref_grid_dir(float d, int g) {
  if (std::isnan(d)) d = std::numeric_limits<float>::infinity();
  if (std::fpclassify(d) == FP_SUBNORMAL) d = 0;
  const double half = std::ldexp(1.0, g - 1);
  double q = std::floor(static_cast<double>(d) * half);
  q = std::min(std::max(q, -half), half - 1);
  return static_cast<uint32_t>(static_cast<int64_t>(q)) & ((1u << g) - 1);
}

// Reference octahedral direction field (docs/hash.md, "Octahedral direction code"), written from
// the specification on the decoded floats: each magnitude as a double (NaN as +inf, an infinity
// as 2^128, its exponent field 255 with significand 1.0; denormals as 0), the largest exponent by
// std::ilogb, the aligned magnitudes as floor(|d| * 2^(150 - E)) (exact in double), and each bin
// as an integer quotient floor(N * 2^(b-1) / L), clamped, instead of the compares.
inline uint32_t ref_oct_dir(const std::array<float, 3>& d, int b) {
  double mag[3];
  bool neg[3];
  int emax = 0;  // biased; 0 when every component is zero
  for (int i = 0; i < 3; ++i) {
    float x = d[i];
    if (std::isnan(x)) x = std::numeric_limits<float>::infinity();
    if (x == 0 || std::fpclassify(x) == FP_SUBNORMAL) x = 0;  // -0 and denormals: +0
    neg[i] = std::signbit(x);
    mag[i] = std::isinf(x) ? std::ldexp(1.0, 128) : std::fabs(static_cast<double>(x));
    if (mag[i] != 0) emax = std::max(emax, std::ilogb(mag[i]) + 127);
  }
  uint64_t a[3];
  for (int i = 0; i < 3; ++i)
    a[i] = static_cast<uint64_t>(std::floor(std::ldexp(mag[i], 150 - emax)));
  const uint64_t l = a[0] + a[1] + a[2], half = uint64_t{1} << (b - 1);
  // Upper hemisphere (z >= +0): (x, y) / L; lower: the fold (1 - |v|, 1 - |u|) with the signs of
  // x and y, where 1 - |y| / L = (|x| + |z|) / L.
  const uint64_t nu = neg[2] ? l - a[1] : a[0], nv = neg[2] ? l - a[0] : a[1];
  auto bin = [&](uint64_t n) { return l == 0 ? half - 1 : std::min(n * half / l, half - 1); };
  const uint32_t u = (neg[0] ? uint32_t(half) : 0) | uint32_t(bin(nu));
  const uint32_t v = (neg[1] ? uint32_t(half) : 0) | uint32_t(bin(nv));
  return (u << b) | v;
}

// `width` binary digits of v, most significant first.
inline std::string ref_bits(uint64_t v, int width) {
  std::string s;
  for (int i = width - 1; i >= 0; --i) s += (v >> i) & 1 ? '1' : '0';
  return s;
}

// Reference key: the fields as strings of binary digits, packed as docs/hash.md step 3 says
// (origin x|y|z, direction z|y|x; XOR of the right-aligned strings, or concatenation).
inline uint64_t ref_hash_key(const std::array<float, 6>& c, const HashConfig& cfg) {
  const bool faithful = cfg.variant == HashVariant::kFaithful;
  const int fo = faithful ? 1 + cfg.exp_bits + cfg.precision : cfg.origin_bits;
  const int fd = faithful ? 1 + cfg.exp_bits + cfg.precision : cfg.dir_bits;
  std::string o, d;
  for (int a = 0; a < 3; ++a)
    o += ref_bits(faithful ? ref_faithful(c[a], cfg.exp_bits, cfg.precision)
                           : ref_grid_origin(c[a], cfg.origin_cell_exp, fo),
                  fo);
  if (!faithful && cfg.dir_code == DirCode::kOct)  // one field u | v for the whole direction
    d = ref_bits(ref_oct_dir({c[3], c[4], c[5]}, cfg.dir_bits), 2 * cfg.dir_bits);
  else
    for (int a = 2; a >= 0; --a)
      d += ref_bits(faithful ? ref_faithful(c[3 + a], cfg.exp_bits, cfg.precision)
                             : ref_grid_dir(c[3 + a], fd),
                    fd);
  std::string key;
  if (cfg.combine == CombineMode::kConcat) {
    key = o + d;
  } else {
    const size_t w = std::max(o.size(), d.size());
    o.insert(0, w - o.size(), '0');
    d.insert(0, w - d.size(), '0');
    for (size_t i = 0; i < w; ++i) key += o[i] == d[i] ? '0' : '1';
  }
  uint64_t v = 0;
  for (char ch : key) v = v * 2 + (ch == '1');
  return v;
}

// Reference set index: the XOR of the key's index-wide chunks, digit by digit.
inline uint32_t ref_index(uint64_t key, int index_bits) {
  if (index_bits == 0) return 0;
  std::string digits = ref_bits(key, 64);
  uint32_t index = 0;
  for (int i = 0; i < 64; ++i)  // digit i from the least significant end belongs to chunk i / S
    if (digits[63 - i] == '1') index ^= 1u << (i % index_bits);
  return index;
}

}  // namespace hrpp::test
