// Synthetic ray streams that stress one part of the RTL (tb/README.md, "Stress modes"): bursts
// of rays of one table set, every ray with one key, and many distinct keys that keep a small
// table full and evicting. Each stream is measured (distinct keys and sets, runs of one set) so
// that the testbench can check it does what it claims.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hrpp/predictor/hash.h"
#include "hrpp/scene/scene.h"
#include "hrpp/workload/workload.h"

namespace hrpp::tb {

enum class StressKind { kSetBurst, kOneKey, kEvict, kSpread };

/// "set-burst", "one-key", "evict", "spread".
bool parse_stress(const std::string& name, StressKind* kind);

struct StressStream {
  std::vector<RayRecord> rays;
  uint64_t distinct_rays = 0;  // distinct (origin, direction) bit patterns
  uint64_t distinct_keys = 0;
  uint64_t distinct_sets = 0;
  uint32_t target_set = 0;        // set-burst: the set of the bursts
  uint64_t target_set_rays = 0;   // ... rays of that set
  uint64_t target_set_keys = 0;   // ... distinct keys among them
  uint64_t longest_set_run = 0;   // longest run of consecutive rays of one set
  uint64_t spread_misplaced = 0;  // rays i whose set mod 4 is not i mod 4 (spread: none)
};

/// n rays aimed at random points of the scene's triangles from random origins in (1.5 times)
/// its bounds, every fourth a shadow (any-hit) ray, shaped by `kind`:
///   set-burst: bursts of 24 rays of one set (its distinct keys found among up to 2 million
///              random rays, used in turn), then 8 rays of any set;
///   one-key:   one ray, repeated, and copies whose low mantissa bits differ (below the hash's
///              precision: each copy is kept only if its key equals the first ray's);
///   evict:     independent rays (as many distinct keys as the hash gives).
///   spread:    independent rays, ray i of a set s with s mod 4 = i mod 4: with 2 or 4 lanes
///              (lane l taking rays l, l + lanes, ...) each lane's rays are of one bank, its own
///              (the multi-lane design's peak rate: docs/microarchitecture.md, "Lanes").
/// `hash` must have index_bits and origin_cell_exp set as the RTL uses them.
StressStream make_stress_stream(StressKind kind, const Scene& scene, const HashConfig& hash,
                                uint64_t n, uint64_t seed);

/// "" if the stream does what its kind claims for a table of `sets` x `ways`, else why not:
/// set-burst: at least 3 runs' worth of rays in one set with more distinct keys than ways;
/// one-key: exactly one key; evict: at least 4 distinct keys per table entry.
std::string check_stress_stream(StressKind kind, const StressStream& s, uint32_t sets,
                                uint32_t ways);

}  // namespace hrpp::tb
