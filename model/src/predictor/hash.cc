#include "hrpp/predictor/hash.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace hrpp {

const char* hash_variant_name(HashVariant v) {
  switch (v) {
    case HashVariant::kFaithful:
      return "faithful";
    case HashVariant::kImproved:
      return "improved";
    case HashVariant::kMicro21:
      return "micro21";
  }
  return "?";
}
const char* combine_mode_name(CombineMode c) { return c == CombineMode::kXor ? "xor" : "concat"; }
const char* dir_code_name(DirCode c) { return c == DirCode::kGrid ? "grid" : "oct"; }

int HashConfig::origin_field_bits() const {
  return variant == HashVariant::kFaithful ? 1 + exp_bits + precision : origin_bits;
}
int HashConfig::dir_field_bits() const {
  if (variant == HashVariant::kMicro21) return 2 * dir_bits + 1;  // phi | theta
  if (variant == HashVariant::kImproved && dir_code == DirCode::kOct) return 2 * dir_bits;  // u|v
  return variant == HashVariant::kFaithful ? 1 + exp_bits + precision : dir_bits;
}
int HashConfig::key_bits() const {
  const int o = 3 * origin_field_bits();
  // micro21 and oct: one direction field for the whole direction; else one per component.
  const bool whole = variant == HashVariant::kMicro21 ||
                     (variant == HashVariant::kImproved && dir_code == DirCode::kOct);
  const int d = whole ? dir_field_bits() : 3 * dir_field_bits();
  return combine == CombineMode::kXor ? std::max(o, d) : o + d;
}

std::string HashConfig::validate() const {
  if (dir_code != DirCode::kGrid && dir_code != DirCode::kOct)
    return "unknown direction code " + std::to_string(int(dir_code));
  if (dir_code == DirCode::kOct && variant != HashVariant::kImproved)
    return std::string(
               "the octahedral direction code (--dir-code oct) applies only to the "
               "improved hash (--hash improved), not to --hash ") +
           hash_variant_name(variant);
  if (variant == HashVariant::kFaithful) {
    if (precision < 1 || precision > 23)
      return "precision must be 1..23 (the float32 mantissa has 23 bits), got " +
             std::to_string(precision);
    if (exp_bits < 0 || exp_bits > 8)
      return "exponent bits must be 0..8 (the float32 exponent has 8 bits), got " +
             std::to_string(exp_bits);
  } else if (variant == HashVariant::kMicro21) {
    if (origin_bits < 1 || origin_bits > 16)
      return "origin grid bits must be 1..16, got " + std::to_string(origin_bits);
    if (dir_bits < 1 || dir_bits > 8)
      return "micro21 theta bits (--dir-bits) must be 1..8 (theta has 8 bits of whole degrees), "
             "got " +
             std::to_string(dir_bits);
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(bounds_lo[a]) || !std::isfinite(bounds_hi[a]) ||
          bounds_hi[a] < bounds_lo[a])
        return "micro21 needs finite scene bounds with lo <= hi on every axis";
  } else {
    if (origin_bits < 1 || origin_bits > 16)
      return "origin grid bits must be 1..16, got " + std::to_string(origin_bits);
    if (dir_bits < 1 || dir_bits > 16)
      return "direction grid bits must be 1..16, got " + std::to_string(dir_bits);
    if (dir_code == DirCode::kOct && dir_bits > 8)
      return "octahedral direction bits (--dir-bits with --dir-code oct) must be 1..8, got " +
             std::to_string(dir_bits);
    if (origin_cell_exp < -149 || origin_cell_exp > 127)
      return "origin cell exponent must be -149..127, got " + std::to_string(origin_cell_exp);
  }
  if (key_bits() > 64)
    return "the key would have " + std::to_string(key_bits()) +
           " bits; at most 64 are supported (use narrower fields or --combine xor)";
  if (index_bits < 0 || index_bits > 24)
    return "index bits must be 0..24, got " + std::to_string(index_bits);
  if (index_bits > key_bits())
    return "the table has 2^" + std::to_string(index_bits) + " sets but keys have only " +
           std::to_string(key_bits()) + " bits";
  return {};
}

int cell_exp_for(const Aabb& b, int origin_bits) {
  const float ext = std::max(max_abs(b.extent()), 1e-30f);
  // Smallest k with 2^k * 2^origin_bits >= extent.
  return static_cast<int>(std::ceil(std::log2(static_cast<double>(ext)))) - origin_bits;
}

uint32_t canonical_bits(uint32_t b) {
  const uint32_t exp = (b >> 23) & 0xFF, man = b & 0x7FFFFF;
  if (exp == 0) return 0;                          // +-0 and denormals
  if (exp == 0xFF && man != 0) return 0x7F800000;  // every NaN
  return b;
}

uint32_t faithful_field(uint32_t bits, int exp_bits, int precision) {
  const uint32_t b = canonical_bits(bits);
  const uint32_t sign = b >> 31, exp = (b >> 23) & 0xFF, man = b & 0x7FFFFF;
  const uint32_t e = exp_bits ? exp >> (8 - exp_bits) : 0;
  const uint32_t m = man >> (23 - precision);
  return (sign << (exp_bits + precision)) | (e << precision) | m;
}

namespace {
inline uint32_t low_bits(uint64_t v, int n) {
  return static_cast<uint32_t>(v & ((uint64_t{1} << n) - 1));
}
}  // namespace

uint32_t grid_origin_field(uint32_t bits, int cell_exp, int field_bits) {
  const uint32_t b = canonical_bits(bits);
  const uint32_t sign = b >> 31, exp = (b >> 23) & 0xFF;
  if (exp == 0xFF) return sign ? 1u << (field_bits - 1) : low_bits(~uint64_t{0}, field_bits);
  if (exp == 0) return 0;
  const uint64_t mant = (b & 0x7FFFFF) | 0x800000;  // value = mant * 2^(exp - 150)
  const int sh = static_cast<int>(exp) - 150 - cell_exp;
  uint64_t mag;  // |x| / 2^k, truncated, low bits only
  bool frac = false;
  if (sh >= 0) {
    mag = sh >= 40 ? 0 : mant << sh;  // only the low field_bits (<= 16) matter
  } else if (sh > -64) {
    mag = mant >> -sh;
    frac = (mant & ((uint64_t{1} << -sh) - 1)) != 0;
  } else {
    mag = 0;
    frac = true;
  }
  // floor(): for negative values, -(trunc + 1) when a fraction was cut off.
  const uint64_t v = sign ? ~(mag + (frac ? 1 : 0)) + 1 : mag;
  return low_bits(v, field_bits);
}

uint32_t grid_dir_field(uint32_t bits, int field_bits) {
  const uint32_t b = canonical_bits(bits);
  const uint32_t sign = b >> 31, exp = (b >> 23) & 0xFF;
  const int64_t hi = (int64_t{1} << (field_bits - 1)) - 1, lo = -(int64_t{1} << (field_bits - 1));
  int64_t q;
  if (exp == 0) {
    q = 0;
  } else if (exp >= 127) {  // |d| >= 1 (and inf / NaN): saturate
    q = sign ? lo : hi;
  } else {
    const uint64_t mant = (b & 0x7FFFFF) | 0x800000;                // |d| = mant * 2^(exp - 150)
    const int sh = 150 - static_cast<int>(exp) - (field_bits - 1);  // > 0 since exp <= 126
    const uint64_t mag = sh >= 64 ? 0 : mant >> sh;
    const bool frac = sh >= 64 ? true : (mant & ((uint64_t{1} << sh) - 1)) != 0;
    q = sign ? -static_cast<int64_t>(mag + (frac ? 1 : 0)) : static_cast<int64_t>(mag);
    q = std::min(std::max(q, lo), hi);
  }
  return low_bits(static_cast<uint64_t>(q), field_bits);
}

uint32_t oct_dir_field(const std::array<uint32_t, 3>& dir_bits, int b) {
  // Step 1: canonical patterns; exponent, 24-bit significand (0 for a zero) and sign.
  uint32_t e[3], sig[3], s[3];
  for (int i = 0; i < 3; ++i) {
    const uint32_t c = canonical_bits(dir_bits[i]);
    e[i] = (c >> 23) & 0xFF;
    sig[i] = e[i] == 0 ? 0 : (1u << 23) | (c & 0x7FFFFF);
    s[i] = c >> 31;
  }
  // Step 2: magnitudes aligned to the largest exponent, truncated.
  const uint32_t emax = std::max({e[0], e[1], e[2]});
  uint64_t a[3];
  for (int i = 0; i < 3; ++i) a[i] = emax - e[i] >= 24 ? 0 : sig[i] >> (emax - e[i]);
  // Step 3: the L1 norm and the numerators (lower hemisphere folded).
  const uint64_t l = a[0] + a[1] + a[2];
  const uint64_t nu = s[2] ? a[0] + a[2] : a[0], nv = s[2] ? a[1] + a[2] : a[1];
  // Step 4: magnitude bins by exact compares against the multiples j * L.
  const uint64_t half = uint64_t{1} << (b - 1);
  auto bin = [&](uint64_t n) {
    uint32_t m = 0;
    for (uint64_t j = 1; j < half; ++j) m += n * half >= j * l ? 1 : 0;
    return m;
  };
  const uint32_t u = (s[0] << (b - 1)) | bin(nu), v = (s[1] << (b - 1)) | bin(nv);
  // Step 5: u | v.
  return (u << b) | v;
}

// micro21: ubc-aamodt-group/ray-intersection-predictor, src/cuda-sim/rt-sim.cc (commit 06c52d6),
// hash_origin_grid, hash_direction_spherical and hash_grid_spherical; PI and clamp from
// src/cuda-sim/vector-math.h (a float constant; std::max(std::min(x, hi), lo)). docs/hash.md.
namespace {
constexpr float kMicro21Pi = 3.14159265358979323846f;
inline float micro21_clamp(float x, float lo, float hi) { return std::max(std::min(x, hi), lo); }
}  // namespace

uint32_t micro21_origin_field(const std::array<float, 3>& o, const HashConfig& cfg) {
  const int n = cfg.origin_bits;
  const uint32_t grid = 1u << n;
  uint32_t f = 0;
  for (int a = 0; a < 3; ++a) {
    const float ext = cfg.bounds_hi[a] - cfg.bounds_lo[a];
    uint32_t c = 0;
    // Theirs divides by zero on a flat axis (0/0 = NaN, converted to an integer: undefined);
    // here that axis's cell is 0.
    if (ext > 0.f) {
      const float v = micro21_clamp((o[a] - cfg.bounds_lo[a]) / ext * static_cast<float>(grid), 0.f,
                                    static_cast<float>(grid) - 1.f);
      c = v >= 0.f ? static_cast<uint32_t>(v) : 0;  // NaN (never for valid rays): 0
    }
    f = (f << n) | c;
  }
  return f;
}

uint32_t micro21_dir_field(const std::array<float, 3>& d, int dir_bits) {
  const float th = std::acos(micro21_clamp(d[2], -1.f, 1.f)) / kMicro21Pi * 180.f;
  const float ph = (std::atan2(d[1], d[0]) + kMicro21Pi) / kMicro21Pi * 180.f;
  // Whole degrees by truncation (float to unsigned conversion), 0..180 and 0..360.
  const uint32_t theta = th >= 0.f ? static_cast<uint32_t>(th) : 0;
  const uint32_t phi = ph >= 0.f ? static_cast<uint32_t>(ph) : 0;
  const uint32_t q_theta = theta >> (8 - dir_bits), q_phi = phi >> (8 - dir_bits);
  return (q_phi << dir_bits) | q_theta;
}

uint64_t hash_key(const std::array<uint32_t, 6>& bits, const HashConfig& cfg) {
  if (cfg.variant == HashVariant::kMicro21) {
    std::array<float, 3> o, d;
    for (int i = 0; i < 3; ++i) {
      o[i] = std::bit_cast<float>(bits[i]);
      d[i] = std::bit_cast<float>(bits[3 + i]);
    }
    const uint64_t of = micro21_origin_field(o, cfg), df = micro21_dir_field(d, cfg.dir_bits);
    return cfg.combine == CombineMode::kXor ? of ^ df : (of << cfg.dir_field_bits()) | df;
  }
  const int fo = cfg.origin_field_bits(), fd = cfg.dir_field_bits();
  if (cfg.variant == HashVariant::kImproved && cfg.dir_code == DirCode::kOct) {
    uint64_t o = 0;
    for (int i = 0; i < 3; ++i) o = (o << fo) | grid_origin_field(bits[i], cfg.origin_cell_exp, fo);
    const uint64_t d = oct_dir_field({bits[3], bits[4], bits[5]}, cfg.dir_bits);
    return cfg.combine == CombineMode::kXor ? o ^ d : (o << fd) | d;
  }
  uint64_t o = 0, d = 0;
  // Origin packed x|y|z, direction z|y|x (x in the most significant field of the origin, z in
  // that of the direction), so XOR pairs o.x^d.z, o.y^d.y, o.z^d.x as the study's simulator does.
  for (int i = 0; i < 3; ++i) {
    uint32_t of, df;
    if (cfg.variant == HashVariant::kFaithful) {
      of = faithful_field(bits[i], cfg.exp_bits, cfg.precision);
      df = faithful_field(bits[5 - i], cfg.exp_bits, cfg.precision);
    } else {
      of = grid_origin_field(bits[i], cfg.origin_cell_exp, fo);
      df = grid_dir_field(bits[5 - i], fd);
    }
    o = (o << fo) | of;
    d = (d << fd) | df;
  }
  return cfg.combine == CombineMode::kXor ? o ^ d : (o << (3 * fd)) | d;
}

HashKey split_key(uint64_t key, const HashConfig& cfg) {
  HashKey k;
  k.key = key;
  const int s = cfg.index_bits;
  if (s == 0) {
    k.tag = key;
    return k;
  }
  for (uint64_t rest = key; rest; rest >>= s) k.index ^= low_bits(rest, s);
  k.tag = s >= 64 ? 0 : key >> s;
  return k;
}

HashKey hash_ray(const Ray& r, const HashConfig& cfg) {
  const std::array<uint32_t, 6> bits = {
      std::bit_cast<uint32_t>(r.org.x), std::bit_cast<uint32_t>(r.org.y),
      std::bit_cast<uint32_t>(r.org.z), std::bit_cast<uint32_t>(r.dir.x),
      std::bit_cast<uint32_t>(r.dir.y), std::bit_cast<uint32_t>(r.dir.z)};
  return split_key(hash_key(bits, cfg), cfg);
}

}  // namespace hrpp
