#include "hrpp/workload.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "hrpp/rng.h"

namespace hrpp {

Vec3 offset_ray_origin(const Vec3& p, const Vec3& n) {
  constexpr float kOrigin = 1.0f / 32.0f, kFloatScale = 1.0f / 65536.0f, kIntScale = 256.0f;
  Vec3 out;
  for (int a = 0; a < 3; ++a) {
    int32_t of = static_cast<int32_t>(kIntScale * n[a]);
    int32_t bits = std::bit_cast<int32_t>(p[a]) + (p[a] < 0 ? -of : of);
    out[a] = std::fabs(p[a]) < kOrigin ? p[a] + kFloatScale * n[a] : std::bit_cast<float>(bits);
  }
  return out;
}

Ray camera_ray(const Camera& cam, int width, int height, int x, int y, int s, int spp,
               uint64_t seed) {
  const Vec3 fwd = glm::normalize(cam.target - cam.eye);
  const Vec3 right = glm::normalize(glm::cross(fwd, cam.up));
  const Vec3 up = glm::cross(right, fwd);
  const int g = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(spp)))));
  const uint64_t pixel = static_cast<uint64_t>(y) * width + x;
  const float jx = ((s % g) + uniform01(seed, pixel, s, 0)) / g;
  const float jy = ((s / g % g) + uniform01(seed, pixel, s, 1)) / g;
  const float th = std::tan(glm::radians(cam.fov_y_deg) * 0.5f);
  const float aspect = static_cast<float>(width) / height;
  const float px = (2.f * (x + jx) / width - 1.f) * th * aspect;
  const float py = (1.f - 2.f * (y + jy) / height) * th;
  Ray r;
  r.org = cam.eye;
  r.dir = glm::normalize(fwd + px * right + py * up);
  return r;
}

void resolution_for(const Camera& cam, uint64_t rays, int spp, int* width, int* height) {
  double pixels = std::max<double>(1, static_cast<double>(rays) / std::max(1, spp));
  double aspect = cam.aspect > 0 ? cam.aspect : 1.0;
  *height = std::max(1, static_cast<int>(std::lround(std::sqrt(pixels / aspect))));
  *width = std::max(1, static_cast<int>(std::lround(pixels / *height)));
}

namespace {

struct AreaLight {
  std::vector<uint32_t> tris;
  std::vector<float> cdf;  // by area
  bool one_sided;
};

std::vector<AreaLight> area_lights(const Scene& s) {
  std::vector<AreaLight> out;
  for (const MeshRange& m : s.meshes) {
    const Material& mat = s.materials[m.material];
    if (!mat.is_emissive()) continue;
    AreaLight l;
    l.one_sided = !mat.double_sided;
    float acc = 0;
    for (uint32_t t = m.first; t < m.first + m.count; ++t) {
      if (s.triangles[t].degenerate()) continue;
      acc += s.triangles[t].area();
      l.tris.push_back(t);
      l.cdf.push_back(acc);
    }
    if (!l.tris.empty()) out.push_back(std::move(l));
  }
  return out;
}

}  // namespace

void generate_rays(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                   const std::function<void(const RayRecord&, const Hit*)>& sink) {
  int w = opt.width > 0 ? opt.width : scene.camera.width;
  int h = opt.height > 0 ? opt.height : scene.camera.height;
  const float ao_dist = opt.ao_distance > 0 ? opt.ao_distance : 0.05f * scene.bounds.diagonal();
  const std::vector<AreaLight> areas = area_lights(scene);
  uint64_t next_id = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int s = 0; s < opt.spp; ++s) {
        RayRecord pr;
        pr.ray = camera_ray(scene.camera, w, h, x, y, s, opt.spp, opt.seed);
        pr.pixel = static_cast<uint32_t>(y * w + x);
        pr.sample = static_cast<uint32_t>(s);
        pr.id = next_id++;
        pr.kind = RayKind::kPrimary;
        Counters c;
        Hit hit = closest_hit(bvh, pr.ray, &c);
        sink(pr, &hit);
        if (!hit.hit() || scene.material_of(hit.prim).is_emissive()) continue;

        const Triangle& tri = scene.triangles[hit.prim];
        const Vec3 p = tri.v0 + hit.u * (tri.v1 - tri.v0) + hit.v * (tri.v2 - tri.v0);
        Vec3 n = glm::normalize(tri.normal());
        if (glm::dot(n, pr.ray.dir) > 0) n = -n;  // the side the camera ray came from
        const Vec3 o = offset_ray_origin(p, n);
        uint64_t sub = 0;
        auto emit = [&](RayKind kind, const Vec3& dir, float tfar) {
          RayRecord r;
          r.ray.org = o;
          r.ray.dir = dir;
          r.ray.tnear = 0.f;
          r.ray.tfar = tfar;
          r.kind = kind;
          r.pixel = pr.pixel;
          r.sample = pr.sample;
          r.parent = pr.id;
          r.id = next_id++;
          sink(r, nullptr);
        };
        if (opt.shadow) {
          for (const Light& l : scene.lights) {
            Vec3 d = l.type == Light::Type::kDirectional ? -l.direction : l.position - o;
            float dist = l.type == Light::Type::kDirectional ? kInf : glm::length(d);
            if (!(dist > 0) || glm::dot(d, n) <= 0) continue;  // light behind the surface
            emit(RayKind::kShadow, glm::normalize(d),
                 std::isinf(dist) ? kInf : dist * (1.f - 1e-5f));
          }
          for (const AreaLight& al : areas) {
            const float u0 = uniform01(opt.seed, pr.id, 100 + sub, 0) * al.cdf.back();
            const size_t k = std::min<size_t>(
                std::upper_bound(al.cdf.begin(), al.cdf.end(), u0) - al.cdf.begin(),
                al.tris.size() - 1);
            const Triangle& lt = scene.triangles[al.tris[k]];
            float a = uniform01(opt.seed, pr.id, 100 + sub, 1);
            float b = uniform01(opt.seed, pr.id, 100 + sub, 2);
            ++sub;
            if (a + b > 1.f) {
              a = 1.f - a;
              b = 1.f - b;
            }
            const Vec3 q = lt.v0 + a * (lt.v1 - lt.v0) + b * (lt.v2 - lt.v0);
            const Vec3 d = q - o;
            const float dist = glm::length(d);
            if (!(dist > 0) || glm::dot(d, n) <= 0) continue;
            if (al.one_sided && glm::dot(-d, lt.normal()) <= 0) continue;  // emitter faces away
            emit(RayKind::kShadow, d / dist, dist * (1.f - 1e-4f));
          }
        }
        if (opt.ao) {
          // Cosine-weighted direction about n (Malley's method).
          const float r1 = uniform01(opt.seed, pr.id, 7, 0), r2 = uniform01(opt.seed, pr.id, 7, 1);
          const float rad = std::sqrt(r1), phi = 6.28318530718f * r2;
          const Vec3 t = glm::normalize(std::fabs(n.x) > 0.9f ? glm::cross(n, Vec3(0, 1, 0))
                                                               : glm::cross(n, Vec3(1, 0, 0)));
          const Vec3 bt = glm::cross(n, t);
          const Vec3 d = glm::normalize(rad * std::cos(phi) * t + rad * std::sin(phi) * bt +
                                        std::sqrt(std::max(0.f, 1.f - r1)) * n);
          emit(RayKind::kAo, d, ao_dist);
        }
      }
}

}  // namespace hrpp
