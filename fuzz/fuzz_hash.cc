// Fuzz target: the hash (model/src/predictor/hash.cc) on any six float32 bit patterns and any valid
// configuration, against the simple reference of model/test/hash_ref.h (fields from the
// standard library's float classification and double arithmetic, packing and index folding
// done on strings of binary digits).
//
// Input: byte 0 variant (bit 0), combine (bit 1), index bits (bits 2-7, mod 25); bytes 1-3 the
// variant's parameters; then six float32 (origin x y z, direction x y z), zeros when short.
#include <array>
#include <bit>

#include "fuzz_util.h"
#include "hash_ref.h"
#include "hrpp/predictor/hash.h"

using namespace hrpp;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::Bytes in(data, size);
  HashConfig cfg;
  const uint8_t b0 = in.u8(), b1 = in.u8(), b2 = in.u8(), b3 = in.u8();
  cfg.variant = b0 & 1 ? HashVariant::kImproved : HashVariant::kFaithful;
  cfg.combine = b0 & 2 ? CombineMode::kConcat : CombineMode::kXor;
  cfg.index_bits = (b0 >> 2) % 25;
  cfg.precision = 1 + b1 % 23;
  cfg.exp_bits = b2 % 9;
  cfg.origin_bits = 1 + b1 % 16;
  cfg.dir_bits = 1 + b2 % 16;
  cfg.origin_cell_exp = -149 + b3 % 277;
  if (!cfg.validate().empty()) {
    // Only two reasons may refuse these parameters (each within its documented range).
    if (cfg.key_bits() <= 64 && cfg.index_bits <= cfg.key_bits())
      fuzz::violated("validate() refused a valid configuration: " + cfg.validate());
    return 0;
  }
  std::array<uint32_t, 6> bits;
  std::array<float, 6> f;
  for (int i = 0; i < 6; ++i) {
    bits[i] = in.u32();
    f[i] = std::bit_cast<float>(bits[i]);
  }
  const uint64_t key = hash_key(bits, cfg), ref = test::ref_hash_key(f, cfg);
  if (key != ref)
    fuzz::violated("hash_key " + std::to_string(key) + " != reference " + std::to_string(ref) +
                   " (" + hash_variant_name(cfg.variant) + ")");
  if (cfg.key_bits() < 64 && key >> cfg.key_bits()) fuzz::violated("key wider than key_bits()");
  const HashKey k = split_key(key, cfg);
  if (k.index != test::ref_index(key, cfg.index_bits))
    fuzz::violated("split_key index " + std::to_string(k.index) + " != reference " +
                   std::to_string(test::ref_index(key, cfg.index_bits)));
  if (k.tag != (cfg.index_bits ? key >> cfg.index_bits : key)) fuzz::violated("split_key tag");
  Ray r;
  r.org = Vec3(f[0], f[1], f[2]);
  r.dir = Vec3(f[3], f[4], f[5]);
  const HashKey kr = hash_ray(r, cfg);
  if (kr.key != key || kr.index != k.index || kr.tag != k.tag)
    fuzz::violated("hash_ray differs from hash_key on the same bits");
  return 0;
}
