// Building blocks shared by the ray generator and the renderer (hrpp/workload/sampling.h).
#include "hrpp/workload/sampling.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "hrpp/util/rng.h"

namespace hrpp {

// ---- building blocks --------------------------------------------------------------------------

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

SurfacePoint surface_point(const Scene& scene, const Ray& ray, const Hit& hit) {
  SurfacePoint sp;
  const Triangle& tri = scene.triangles[hit.prim];
  sp.p = tri.v0 + hit.u * (tri.v1 - tri.v0) + hit.v * (tri.v2 - tri.v0);
  sp.ng = glm::normalize(tri.normal());
  sp.front = glm::dot(sp.ng, ray.dir) <= 0;
  sp.n = sp.front ? sp.ng : -sp.ng;  // the side the ray came from
  sp.prim = hit.prim;
  sp.material = &scene.material_of(hit.prim);
  return sp;
}

uint64_t camera_key(uint32_t pixel, uint32_t sample) {
  return mix64((uint64_t{pixel} << 32) | sample);
}

uint64_t child_key(uint64_t parent, RayKind kind, uint32_t slot) {
  return mix64(parent ^ mix64((uint64_t{static_cast<uint8_t>(kind)} << 32) | slot));
}

SceneLights::SceneLights(const Scene& scene) : scene_(scene) {
  for (uint32_t r = 0; r < scene.meshes.size(); ++r) {
    const MeshRange& m = scene.meshes[r];
    const Material& mat = scene.materials[m.material];
    if (!mat.is_emissive()) continue;
    Mesh l;
    l.range = r;
    l.emission = mat.emission();
    l.one_sided = !mat.double_sided;
    float acc = 0;
    for (uint32_t t = m.first; t < m.first + m.count; ++t) {
      if (scene.triangles[t].degenerate()) continue;
      acc += scene.triangles[t].area();
      l.tris.push_back(t);
      l.cdf.push_back(acc);
    }
    if (!l.tris.empty()) meshes_.push_back(std::move(l));
  }
}

std::string SceneLights::name(uint32_t i) const {
  if (i < scene_.lights.size()) return scene_.lights[i].name;
  const Mesh& m = meshes_[i - scene_.lights.size()];
  const size_t n = m.tris.size();
  return scene_.meshes[m.range].name + ": " + std::to_string(n) +
         (n == 1 ? " triangle" : " triangles");
}

void SceneLights::sample(const Vec3& o, const Vec3& n, uint64_t seed, uint64_t key,
                         std::vector<LightSample>* out) const {
  out->clear();
  const uint32_t np = static_cast<uint32_t>(scene_.lights.size());
  for (uint32_t i = 0; i < np; ++i) {
    const Light& l = scene_.lights[i];
    const bool dir_light = l.type == Light::Type::kDirectional;
    const Vec3 d = dir_light ? -l.direction : l.position - o;
    const float dist = dir_light ? kInf : glm::length(d);
    if (!(dist > 0) || glm::dot(d, n) <= 0) continue;  // light behind the surface
    LightSample s;
    s.dir = glm::normalize(d);
    s.tfar = dir_light ? kInf : dist * (1.f - 1e-5f);
    s.light = i;
    s.irradiance = l.color * l.intensity / (dir_light ? 1.f : dist * dist);
    out->push_back(s);
  }
  for (uint32_t k = 0; k < meshes_.size(); ++k) {
    const Mesh& al = meshes_[k];
    const uint64_t lk = child_key(key, RayKind::kShadow, np + k);
    const float u0 = uniform01(seed, lk, 0) * al.cdf.back();
    const size_t t = std::min<size_t>(
        std::upper_bound(al.cdf.begin(), al.cdf.end(), u0) - al.cdf.begin(), al.tris.size() - 1);
    const Triangle& lt = scene_.triangles[al.tris[t]];
    float a = uniform01(seed, lk, 1), b = uniform01(seed, lk, 2);
    if (a + b > 1.f) {
      a = 1.f - a;
      b = 1.f - b;
    }
    const Vec3 q = lt.v0 + a * (lt.v1 - lt.v0) + b * (lt.v2 - lt.v0);
    const Vec3 d = q - o;
    const float dist = glm::length(d);
    if (!(dist > 0) || glm::dot(d, n) <= 0) continue;
    const float cos_l = glm::dot(-d / dist, glm::normalize(lt.normal()));
    if (al.one_sided && cos_l <= 0) continue;  // the emitter faces away
    LightSample s;
    s.dir = d / dist;
    s.tfar = dist * (1.f - 1e-4f);
    s.light = np + k;
    s.irradiance = al.emission * std::fabs(cos_l) * al.cdf.back() / (dist * dist);
    out->push_back(s);
  }
}

}  // namespace hrpp
