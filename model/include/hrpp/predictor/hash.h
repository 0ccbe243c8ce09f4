// The HRPP ray hash, bit for bit as specified in docs/hash.md. This is the one implementation used
// by the untimed model, the cycle model and the RTL testbench.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "hrpp/scene/geometry.h"
#include "hrpp/trace/ray.h"

namespace hrpp {

enum class HashVariant : uint8_t {
  kFaithful = 0,  // the original study: sign | top E exponent bits | top P mantissa bits
  kImproved = 1,  // exact fixed-point grid: origin cells of 2^k, direction on a uniform grid
  kMicro21 = 2,   // MICRO 2021's grid-spherical hash: origin on a grid over the scene's bounds,
                  // direction as whole-degree theta / phi (acos, atan2 in float; docs/hash.md)
};
enum class CombineMode : uint8_t { kXor = 0, kConcat = 1 };
// The improved hash's direction code (docs/hash.md): each component on a uniform grid, or the
// octahedral map of the direction onto a square (no code is wasted on non-unit directions).
enum class DirCode : uint8_t { kGrid = 0, kOct = 1 };

const char* hash_variant_name(HashVariant v);
const char* combine_mode_name(CombineMode c);
const char* dir_code_name(DirCode c);

struct HashConfig {
  HashVariant variant = HashVariant::kFaithful;
  // Faithful variant.
  int precision = 6;  // P: top mantissa bits per component, 1..23
  int exp_bits = 3;   // E: top exponent bits per component, 0..8
  // Improved variant.
  int origin_bits = 5;                // G_o: bits of each origin axis's cell index, 1..16
  int origin_cell_exp = 0;            // k: cells are 2^k wide (set from the scene by cell_exp_for)
  int dir_bits = 3;                   // G_d: bits of each direction component, 1..16
                                      // (micro21: theta bits, 1..8; phi gets one more;
                                      // oct: bits of each of the two octahedral coordinates, 1..8)
  DirCode dir_code = DirCode::kGrid;  // improved only: grid (per component) or oct
  // micro21 variant: the scene's bounds the origin grid spans (set by resolve_for_scene).
  std::array<float, 3> bounds_lo{0.f, 0.f, 0.f}, bounds_hi{1.f, 1.f, 1.f};
  // Both.
  CombineMode combine = CombineMode::kXor;
  int index_bits = 8;  // the table has 2^index_bits sets (0 for the unbounded table)

  /// Width of one origin / direction component's field (micro21: of one origin axis, and of the
  /// whole direction field phi | theta, 2 * dir_bits + 1; improved with the oct code: of the
  /// whole direction field u | v, 2 * dir_bits).
  int origin_field_bits() const;
  int dir_field_bits() const;
  /// Width of the combined key (at most 64).
  int key_bits() const;
  /// Tag width: the key bits the index does not cover.
  int tag_bits() const { return key_bits() - index_bits; }
  /// Empty when the configuration is valid, else what is wrong.
  std::string validate() const;
};

/// The cell exponent k that divides the scene's largest extent into about 2^origin_bits cells.
int cell_exp_for(const Aabb& bounds, int origin_bits);

/// Canonical float32 bit pattern: -0 and denormals become +0, every NaN becomes 0x7F800000
/// (the +inf pattern; rays with non-finite fields are never hashed, see docs/hash.md).
uint32_t canonical_bits(uint32_t bits);

/// Faithful field of one component: sign | top E exponent bits | top P mantissa bits.
uint32_t faithful_field(uint32_t bits, int exp_bits, int precision);

/// Improved origin field: the low `bits` bits of floor(x / 2^cell_exp) (exact, two's
/// complement); +inf and NaN give all ones, -inf gives 1 followed by zeros.
uint32_t grid_origin_field(uint32_t bits, int cell_exp, int field_bits);

/// Improved direction field: floor(d * 2^(bits-1)) clamped to [-2^(bits-1), 2^(bits-1) - 1],
/// as `bits` bits of two's complement.
uint32_t grid_dir_field(uint32_t bits, int field_bits);

/// micro21 origin field: x | y | z, each min(trunc(clamp((o - lo) / (hi - lo) * 2^bits, 0,
/// 2^bits - 1)), in float as their simulator computes it; an axis with hi == lo gives 0.
uint32_t micro21_origin_field(const std::array<float, 3>& o, const HashConfig& cfg);

/// micro21 direction field: phi | theta with theta = trunc(acos(clamp(d.z, -1, 1)) / pi * 180)
/// >> (8 - dir_bits) and phi = trunc((atan2(d.y, d.x) + pi) / pi * 180) >> (8 - dir_bits), all
/// in float; the direction is not normalised (as theirs).
uint32_t micro21_dir_field(const std::array<float, 3>& d, int dir_bits);

/// Improved hash, octahedral direction code (docs/hash.md, "Octahedral direction code"): the
/// direction's three float32 bit patterns (x, y, z) mapped onto the octahedron's square, each of
/// the two coordinates u, v as sign | magnitude bin (b bits); returns u << b | v (2b bits).
/// b = 1..8. Total: every bit pattern gives a field.
uint32_t oct_dir_field(const std::array<uint32_t, 3>& dir_bits, int b);

struct HashKey {
  uint64_t key = 0;
  uint32_t index = 0;  // set index
  uint64_t tag = 0;    // key >> index_bits
};

/// Hash of the six float bit patterns (origin x, y, z, direction x, y, z).
uint64_t hash_key(const std::array<uint32_t, 6>& bits, const HashConfig& cfg);
HashKey hash_ray(const Ray& r, const HashConfig& cfg);
/// Splits a key into set index (XOR fold of all index-wide chunks) and tag.
HashKey split_key(uint64_t key, const HashConfig& cfg);

}  // namespace hrpp
