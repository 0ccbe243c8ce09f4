#include "stress.h"

#include <array>
#include <bit>
#include <deque>
#include <random>
#include <unordered_set>

namespace hrpp::tb {

namespace {

constexpr int kBurst = 24, kGap = 8;

RayRecord aimed_ray(const Scene& scene, std::mt19937_64& rng, uint64_t pos) {
  std::uniform_real_distribution<float> u(0, 1);
  std::uniform_int_distribution<size_t> pick(0, scene.triangles.size() - 1);
  const Vec3 c = scene.bounds.center(), e = scene.bounds.extent();
  for (;;) {
    const Triangle& t = scene.triangles[pick(rng)];
    float a = u(rng), b = u(rng);
    if (a + b > 1) {
      a = 1 - a;
      b = 1 - b;
    }
    const Vec3 p = t.v0 + a * (t.v1 - t.v0) + b * (t.v2 - t.v0);
    const Vec3 o = c + (Vec3(u(rng), u(rng), u(rng)) - 0.5f) * e * 1.5f;
    const Vec3 d = p - o;
    const float len = glm::length(d);
    if (!(len > 1e-4f * max_abs(e))) continue;
    RayRecord r;
    r.ray.org = o;
    r.ray.dir = d / len;
    r.kind = pos % 4 == 3 ? RayKind::kShadow : RayKind::kPrimary;
    r.id = pos;
    if (validate_ray(r.ray) == RayError::kNone) return r;
  }
}

float flip_low_bits(float v, std::mt19937_64& rng, int bits) {
  const uint32_t mask = (1u << bits) - 1;
  return std::bit_cast<float>(std::bit_cast<uint32_t>(v) ^ (uint32_t(rng()) & mask));
}

}  // namespace

bool parse_stress(const std::string& name, StressKind* kind) {
  if (name == "set-burst")
    *kind = StressKind::kSetBurst;
  else if (name == "one-key")
    *kind = StressKind::kOneKey;
  else if (name == "evict")
    *kind = StressKind::kEvict;
  else if (name == "spread")
    *kind = StressKind::kSpread;
  else
    return false;
  return true;
}

StressStream make_stress_stream(StressKind kind, const Scene& scene, const HashConfig& hash,
                                uint64_t n, uint64_t seed) {
  StressStream s;
  std::mt19937_64 rng(seed ^ 0x5354'5245'5353ull);
  const RayRecord first = aimed_ray(scene, rng, 0);
  const HashKey k0 = hash_ray(first.ray, hash);
  s.target_set = k0.index;
  // set-burst: rays of the target set with distinct keys, found among a bounded number of
  // random rays (one in `sets` is of the set; the scene's rays reach only so many keys of it).
  std::vector<RayRecord> pool{first};
  size_t pool_next = 0;
  if (kind == StressKind::kSetBurst) {
    std::unordered_set<uint64_t> pool_keys{k0.key};
    const uint64_t sets = uint64_t{1} << hash.index_bits;
    const uint64_t budget = std::min<uint64_t>(2'000'000, std::max<uint64_t>(200'000, n * sets));
    for (uint64_t t = 0; t < budget && pool.size() < n; ++t) {
      const RayRecord c = aimed_ray(scene, rng, 0);
      const HashKey k = hash_ray(c.ray, hash);
      if (k.index == s.target_set && pool_keys.insert(k.key).second) pool.push_back(c);
    }
  }
  std::array<std::deque<RayRecord>, 4> by_set_mod4;  // spread: random rays not yet placed
  while (s.rays.size() < n) {
    const uint64_t pos = s.rays.size();
    RayRecord r;
    switch (kind) {
      case StressKind::kSetBurst:
        if (pos % (kBurst + kGap) < kBurst) {
          // The rays of the target set (distinct keys) in turn.
          r = pool[pool_next++ % pool.size()];
          r.id = pos;
          r.kind = pos % 4 == 3 ? RayKind::kShadow : RayKind::kPrimary;
        } else {
          r = aimed_ray(scene, rng, pos);
        }
        break;
      case StressKind::kOneKey:
        r = first;
        r.id = pos;
        r.kind = pos % 4 == 3 ? RayKind::kShadow : RayKind::kPrimary;
        if (pos % 2) {  // a copy differing below the hash's precision, if its key is the same
          RayRecord v = r;
          for (int i = 0; i < 3; ++i) {
            v.ray.org[i] = flip_low_bits(r.ray.org[i], rng, 6);
            v.ray.dir[i] = flip_low_bits(r.ray.dir[i], rng, 6);
          }
          if (validate_ray(v.ray) == RayError::kNone && hash_ray(v.ray, hash).key == k0.key) r = v;
        }
        break;
      case StressKind::kEvict: {
        // Aimed rays reach few direction codes of a coarse hash (a flat scene seen from inside
        // its bounds); every second ray takes a uniform random direction instead, so that the
        // keys outnumber the table's entries for every configuration's hash.
        r = aimed_ray(scene, rng, pos);
        if (pos % 2 == 1) {
          std::normal_distribution<float> g(0, 1);
          for (Vec3 d;;) {
            d = Vec3(g(rng), g(rng), g(rng));
            if (glm::length(d) > 1e-3f) {
              r.ray.dir = d / glm::length(d);
              break;
            }
          }
        }
        break;
      }
      case StressKind::kSpread: {
        auto& want = by_set_mod4[pos % 4];
        while (want.empty()) {
          const RayRecord c = aimed_ray(scene, rng, 0);
          by_set_mod4[hash_ray(c.ray, hash).index % 4].push_back(c);
        }
        r = want.front();
        want.pop_front();
        r.id = pos;
        r.kind = pos % 8 >= 6 ? RayKind::kShadow : RayKind::kPrimary;
        break;
      }
    }
    s.rays.push_back(r);
  }
  // Measure what the stream is.
  std::unordered_set<uint64_t> keys, sets, target_keys, patterns;
  uint64_t run = 0, prev_set = ~0ull, position = 0;
  for (const RayRecord& r : s.rays) {
    const HashKey k = hash_ray(r.ray, hash);
    uint64_t h = 0;
    for (int i = 0; i < 3; ++i)
      for (float v : {r.ray.org[i], r.ray.dir[i]})
        h = (h ^ std::bit_cast<uint32_t>(v)) * 0x100000001b3ull;
    patterns.insert(h);
    keys.insert(k.key);
    sets.insert(k.index);
    if (k.index == s.target_set) {
      s.target_set_rays++;
      target_keys.insert(k.key);
    }
    s.spread_misplaced += k.index % 4 != position++ % 4;
    run = k.index == prev_set ? run + 1 : 1;
    prev_set = k.index;
    s.longest_set_run = std::max(s.longest_set_run, run);
  }
  s.distinct_rays = patterns.size();
  s.distinct_keys = keys.size();
  s.distinct_sets = sets.size();
  s.target_set_keys = target_keys.size();
  return s;
}

std::string check_stress_stream(StressKind kind, const StressStream& s, uint32_t sets,
                                uint32_t ways) {
  switch (kind) {
    case StressKind::kSetBurst:
      if (s.longest_set_run < uint64_t(std::min<size_t>(kBurst, s.rays.size())))
        return "no burst of " + std::to_string(kBurst) + " rays of one set";
      if (s.target_set_keys <= ways)
        return "the burst set has " + std::to_string(s.target_set_keys) + " keys, not more than " +
               std::to_string(ways) + " ways";
      return {};
    case StressKind::kOneKey:
      if (s.distinct_keys != 1) return std::to_string(s.distinct_keys) + " keys, not one";
      if (s.rays.size() >= 100 && s.distinct_rays < 10)
        return "only " + std::to_string(s.distinct_rays) +
               " distinct rays (copies below the precision)";
      return {};
    case StressKind::kSpread:
      if (s.spread_misplaced != 0)
        return std::to_string(s.spread_misplaced) + " rays whose set mod 4 is not their position's";
      [[fallthrough]];
    case StressKind::kEvict:
      if (s.distinct_keys < 4ull * sets * ways)
        return std::to_string(s.distinct_keys) + " distinct keys, fewer than 4 per table entry (" +
               std::to_string(4ull * sets * ways) + ")";
      return {};
  }
  return "unknown stress kind";
}

}  // namespace hrpp::tb
