// The ray generator: camera samples in the chosen order and the secondary rays spawned from
// their hits (generate_rays, docs/workloads.md).
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "hrpp/predictor/hash.h"
#include "hrpp/util/rng.h"
#include "hrpp/workload/workload.h"

namespace hrpp {

// ---- generation -------------------------------------------------------------------------------

namespace {

/// Cosine-weighted direction about the unit normal n (Malley's method).
Vec3 cosine_direction(const Vec3& n, float r1, float r2) {
  const float rad = std::sqrt(r1), phi = 6.28318530718f * r2;
  const Vec3 t = glm::normalize(std::fabs(n.x) > 0.9f ? glm::cross(n, Vec3(0, 1, 0))
                                                      : glm::cross(n, Vec3(1, 0, 0)));
  const Vec3 bt = glm::cross(n, t);
  return glm::normalize(rad * std::cos(phi) * t + rad * std::sin(phi) * bt +
                        std::sqrt(std::max(0.f, 1.f - r1)) * n);
}

Vec3 mirror(const Vec3& d, const Vec3& n) { return d - 2.f * glm::dot(d, n) * n; }

/// Reflection about a microfacet normal drawn from the GGX distribution with alpha =
/// roughness^2 around n (roughness 0: the mirror direction); the mirror direction when the
/// sampled one would go below the surface.
Vec3 glossy_reflection(const Vec3& d, const Vec3& n, float roughness, float u1, float u2) {
  const float alpha = roughness * roughness;
  const float tan2 = alpha * alpha * u1 / (1.f - u1);
  const float cos_t = 1.f / std::sqrt(1.f + tan2),
              sin_t = std::sqrt(std::max(0.f, 1.f - cos_t * cos_t));
  const float phi = 6.28318530718f * u2;
  const Vec3 t = glm::normalize(std::fabs(n.x) > 0.9f ? glm::cross(n, Vec3(0, 1, 0))
                                                      : glm::cross(n, Vec3(1, 0, 0)));
  const Vec3 bt = glm::cross(n, t);
  const Vec3 m = sin_t * std::cos(phi) * t + sin_t * std::sin(phi) * bt + cos_t * n;
  const Vec3 r = glm::normalize(mirror(d, m));
  return glm::dot(r, n) > 0 ? r : glm::normalize(mirror(d, n));
}

struct Pending {
  RayRecord rec;
  uint64_t key;
};
struct Traced {
  RayRecord rec;
  uint64_t key;
  Hit hit;
};

class Generator {
 public:
  Generator(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt, int w, int h,
            const std::function<void(const RayRecord&, const Hit*)>& sink)
      : scene_(scene),
        bvh_(bvh),
        opt_(opt),
        w_(w),
        h_(h),
        spp_(std::max(1, opt.spp)),
        ao_dist_(ao_distance_for(scene, opt)),
        lights_(scene),
        sink_(sink) {}

  int spp() const { return spp_; }

  /// Adds camera sample s of pixel (x, y) to the current group.
  void add_sample(int x, int y, int s) {
    Pending p;
    p.rec.ray = camera_ray(scene_.camera, w_, h_, x, y, s, spp_, opt_.seed);
    p.rec.pixel = static_cast<uint32_t>(y) * static_cast<uint32_t>(w_) + static_cast<uint32_t>(x);
    p.rec.sample = static_cast<uint32_t>(s);
    p.key = camera_key(p.rec.pixel, p.rec.sample);
    pending_[0].push_back(p);
  }
  /// Adds all of pixel (x, y)'s camera samples to the current group.
  void add_pixel(int x, int y) {
    for (int s = 0; s < spp_; ++s) add_sample(x, y, s);
  }

  /// Issues the group: its primary rays, then generation by generation the rays they spawn,
  /// each generation grouped by kind.
  void flush() {
    while (true) {
      traced_.clear();
      bool any = false;
      for (auto& bucket : pending_) {
        for (Pending& p : bucket) {
          any = true;
          p.rec.id = next_id_++;
          if (is_any_hit(p.rec.kind)) {
            sink_(p.rec, nullptr);
            continue;
          }
          Counters c;
          Traced t{p.rec, p.key, closest_hit(bvh_, p.rec.ray, &c)};
          sink_(t.rec, &t.hit);
          traced_.push_back(t);
        }
        bucket.clear();
      }
      if (!any) return;
      for (const Traced& t : traced_) spawn(t);
    }
  }

 private:
  void push(const Traced& parent, RayKind kind, uint32_t slot, const Vec3& org, const Vec3& dir,
            float tfar) {
    Pending p;
    p.rec.ray.org = org;
    p.rec.ray.dir = dir;
    p.rec.ray.tnear = 0.f;
    p.rec.ray.tfar = tfar;
    p.rec.kind = kind;
    p.rec.pixel = parent.rec.pixel;
    p.rec.sample = parent.rec.sample;
    p.rec.parent = parent.rec.id;
    p.rec.spawn_prim = parent.hit.prim;
    p.rec.depth = static_cast<uint8_t>(std::min(255, parent.rec.depth + 1));
    p.key = child_key(parent.key, kind, slot);
    pending_[static_cast<int>(kind)].push_back(p);
  }

  void spawn(const Traced& t) {
    if (!t.hit.hit()) return;
    const SurfacePoint sp = surface_point(scene_, t.rec.ray, t.hit);
    const Material& mat = *sp.material;
    if (mat.is_emissive()) return;  // a light: nothing to spawn
    const Vec3 o = offset_ray_origin(sp.p, sp.n);
    const Vec3& d = t.rec.ray.dir;
    const uint64_t seed = opt_.seed;
    if (opt_.shadow) {
      lights_.sample(o, sp.n, seed, t.key, &samples_);
      for (const LightSample& s : samples_) push(t, RayKind::kShadow, s.light, o, s.dir, s.tfar);
    }
    if (opt_.ao && t.rec.kind == RayKind::kPrimary) {
      const uint64_t k = child_key(t.key, RayKind::kAo, 0);
      push(t, RayKind::kAo, 0, o,
           cosine_direction(sp.n, uniform01(seed, k, 0), uniform01(seed, k, 1)), ao_dist_);
    }
    if (t.rec.depth >= opt_.max_depth) return;
    if (opt_.reflection && is_specular_reflector(mat)) {
      const uint64_t k = child_key(t.key, RayKind::kReflection, 0);
      push(t, RayKind::kReflection, 0, o,
           glossy_reflection(glm::normalize(d), sp.n, mat.roughness, uniform01(seed, k, 0),
                             uniform01(seed, k, 1)),
           kInf);
    }
    if (opt_.refraction && is_transmissive(mat)) {
      // Snell's law at the interface; n faces the incoming ray, so cos_i > 0. Entering when the
      // ray arrives on the side the geometric normal points to (closed meshes wound outwards).
      const Vec3 dn = glm::normalize(d);
      const float eta = sp.front ? 1.f / mat.ior : mat.ior;
      const float cos_i = std::min(1.f, -glm::dot(sp.n, dn));
      const float sin2_t = eta * eta * std::max(0.f, 1.f - cos_i * cos_i);
      if (sin2_t >= 1.f) {  // total internal reflection: the reflected ray instead
        push(t, RayKind::kReflection, 0, o, glm::normalize(mirror(dn, sp.n)), kInf);
      } else {
        const Vec3 dir = glm::normalize(eta * dn + (eta * cos_i - std::sqrt(1.f - sin2_t)) * sp.n);
        push(t, RayKind::kRefraction, 0, offset_ray_origin(sp.p, -sp.n), dir, kInf);
      }
    }
    if (opt_.diffuse) {
      const uint64_t k = child_key(t.key, RayKind::kDiffuse, 0);
      push(t, RayKind::kDiffuse, 0, o,
           cosine_direction(sp.n, uniform01(seed, k, 0), uniform01(seed, k, 1)), kInf);
    }
  }

  const Scene& scene_;
  const Bvh& bvh_;
  const WorkloadOptions& opt_;
  const int w_, h_, spp_;
  const float ao_dist_;
  const SceneLights lights_;
  const std::function<void(const RayRecord&, const Hit*)>& sink_;
  std::array<std::vector<Pending>, kNumRayKinds> pending_;  // by kind: the next generation
  std::vector<Traced> traced_;
  std::vector<LightSample> samples_;
  uint64_t next_id_ = 0;
};

/// De-interleaves the even bits of v (Morton decoding).
uint32_t compact_bits(uint64_t v) {
  v &= 0x5555555555555555ull;
  v = (v | (v >> 1)) & 0x3333333333333333ull;
  v = (v | (v >> 2)) & 0x0F0F0F0F0F0F0F0Full;
  v = (v | (v >> 4)) & 0x00FF00FF00FF00FFull;
  v = (v | (v >> 8)) & 0x0000FFFF0000FFFFull;
  v = (v | (v >> 16)) & 0x00000000FFFFFFFFull;
  return static_cast<uint32_t>(v);
}

/// Calls f(x, y) for every cell of a w x h grid along the Z-order curve (x in the even bits).
template <class F>
void morton_walk(uint32_t w, uint32_t h, F&& f) {
  const uint64_t side = std::bit_ceil(std::max({w, h, 1u}));
  for (uint64_t code = 0; code < side * side; ++code) {
    const uint32_t x = compact_bits(code), y = compact_bits(code >> 1);
    if (x < w && y < h) f(x, y);
  }
}

/// MICRO 2021's AO benchmark (generate_rays). The random numbers of triangle i are
/// uniform01(seed, camera_key(i, 0), 0..3): two for the point, two for the direction.
void micro21_ao(const Scene& scene, const WorkloadOptions& opt,
                const std::function<void(const RayRecord&, const Hit*)>& sink) {
  uint64_t id = 0;
  for (uint32_t i = 0; i < scene.triangles.size() && id < kMicro21AoMaxRays; ++i) {
    const Triangle& t = scene.triangles[i];
    if (t.degenerate()) continue;
    const Vec3 ng = glm::cross(t.v1 - t.v0, t.v2 - t.v0);
    const float len = glm::length(ng);
    if (!(len > 0) || !std::isfinite(len)) continue;  // no normal to sample about
    const uint64_t key = camera_key(i, 0);
    const float r1 = uniform01(opt.seed, key, 0), r2 = uniform01(opt.seed, key, 1);
    const float su = std::sqrt(r1);
    RayRecord rec;
    rec.ray.org = (1.f - su) * t.v0 + su * (1.f - r2) * t.v1 + su * r2 * t.v2;
    const Vec3 n = opt.micro21_flip ? -ng / len : ng / len;
    rec.ray.dir = cosine_direction(n, uniform01(opt.seed, key, 2), uniform01(opt.seed, key, 3));
    rec.ray.tnear = kMicro21AoTnear;
    rec.ray.tfar = std::numeric_limits<float>::infinity();
    rec.kind = RayKind::kAo;
    rec.id = id++;
    rec.spawn_prim = i;
    rec.depth = 1;
    sink(rec, nullptr);
  }
}

}  // namespace

uint64_t micro21_sort_key(const Ray& ray, const Aabb& b) {
  // hash_grid_spherical (RayGenerator.cpp 444-451): the origin on a 32^3 grid over the bounds
  // and the direction in 3 theta and 4 phi bits, as the micro21 hash computes its fields
  // (hash_origin_grid and hash_direction_spherical there), concatenated instead of XORed.
  HashConfig cfg;
  cfg.origin_bits = 5;
  cfg.bounds_lo = {b.lo.x, b.lo.y, b.lo.z};
  cfg.bounds_hi = {b.hi.x, b.hi.y, b.hi.z};
  const uint64_t h_o = micro21_origin_field({ray.org.x, ray.org.y, ray.org.z}, cfg);
  return (h_o << 7) | micro21_dir_field({ray.dir.x, ray.dir.y, ray.dir.z}, 3);
}

void generate_rays(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                   const std::function<void(const RayRecord&, const Hit*)>& sink) {
  if (opt.source == WorkloadSource::kMicro21Ao) return micro21_ao(scene, opt, sink);
  if (opt.source == WorkloadSource::kMicro21AoSorted) {
    Aabb bounds;  // their world bounds: every vertex of the model
    for (const Triangle& t : scene.triangles)
      for (const Vec3& v : {t.v0, t.v1, t.v2}) bounds.grow(v);
    std::vector<std::pair<uint64_t, RayRecord>> rays;
    micro21_ao(scene, opt, [&](const RayRecord& r, const Hit*) {
      rays.emplace_back(micro21_sort_key(r.ray, bounds), r);
    });
    std::stable_sort(rays.begin(), rays.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    uint64_t id = 0;
    for (auto& [key, r] : rays) {
      r.id = id++;  // ids in issue order
      sink(r, nullptr);
    }
    return;
  }
  int w, h;
  workload_resolution(scene, opt, &w, &h);
  Generator g(scene, bvh, opt, w, h, sink);
  if (opt.order == RayOrder::kScanline) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int s = 0; s < g.spp(); ++s) {
          g.add_sample(x, y, s);  // one camera sample per group
          g.flush();
        }
    return;
  }
  const uint32_t tile = static_cast<uint32_t>(std::max(1, opt.tile));
  const uint32_t tw = (static_cast<uint32_t>(w) + tile - 1) / tile;
  const uint32_t th = (static_cast<uint32_t>(h) + tile - 1) / tile;
  auto do_tile = [&](uint32_t tx, uint32_t ty) {
    const uint32_t x0 = tx * tile, y0 = ty * tile;
    const uint32_t cw = std::min<uint32_t>(tile, static_cast<uint32_t>(w) - x0);
    const uint32_t ch = std::min<uint32_t>(tile, static_cast<uint32_t>(h) - y0);
    if (opt.order == RayOrder::kMorton) {
      morton_walk(cw, ch, [&](uint32_t x, uint32_t y) { g.add_pixel(x0 + x, y0 + y); });
    } else {
      for (uint32_t y = 0; y < ch; ++y)
        for (uint32_t x = 0; x < cw; ++x) g.add_pixel(x0 + x, y0 + y);
    }
    g.flush();
  };
  if (opt.order == RayOrder::kMorton) {
    morton_walk(tw, th, do_tile);
  } else {
    for (uint32_t ty = 0; ty < th; ++ty)
      for (uint32_t tx = 0; tx < tw; ++tx) do_tile(tx, ty);
  }
}

}  // namespace hrpp
