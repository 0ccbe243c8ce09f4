#include "hrpp/workload.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <sstream>

#include "hrpp/rng.h"

namespace hrpp {

// ---- orders, effects ------------------------------------------------------------------------

std::string_view ray_order_name(RayOrder o) {
  switch (o) {
    case RayOrder::kScanline: return "scanline";
    case RayOrder::kTiled: return "tiled";
    case RayOrder::kMorton: return "morton";
  }
  return "?";
}

bool parse_ray_order(std::string_view name, RayOrder* out) {
  for (RayOrder o : {RayOrder::kScanline, RayOrder::kTiled, RayOrder::kMorton})
    if (ray_order_name(o) == name) {
      *out = o;
      return true;
    }
  return false;
}

bool is_specular_reflector(const Material& m) {
  return m.metallic >= kReflectMinMetallic && m.roughness <= kReflectMaxRoughness;
}

bool is_transmissive(const Material& m) { return m.transmission > 0.f && !is_specular_reflector(m); }

namespace {

std::string fmt(float v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

/// "a, b, c and 2 more"
std::string join_limited(const std::vector<std::string>& items, size_t limit = 4) {
  std::string out;
  for (size_t i = 0; i < items.size() && i < limit; ++i) out += (i ? ", " : "") + items[i];
  if (items.size() > limit) out += " and " + std::to_string(items.size() - limit) + " more";
  return out;
}

std::string plural(size_t n, const char* word) {
  return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

/// Materials (with triangle counts) that satisfy pred, among those hit-able without being
/// emitters (an emissive hit spawns no secondary ray).
std::vector<std::string> materials_where(const Scene& s, bool (*pred)(const Material&),
                                         std::string (*what)(const Material&)) {
  std::vector<uint64_t> tris(s.materials.size(), 0);
  for (uint32_t m : s.tri_material) tris[m]++;
  std::vector<std::string> out;
  for (size_t i = 0; i < s.materials.size(); ++i) {
    const Material& m = s.materials[i];
    if (tris[i] == 0 || m.is_emissive() || !pred(m)) continue;
    out.push_back("'" + m.name + "' (" + what(m) + "; " + plural(tris[i], "triangle") + ")");
  }
  return out;
}

constexpr std::array<const char*, 5> kEffectNames = {"shadow", "ao", "reflection", "refraction",
                                                     "diffuse"};

/// The flag of an effect (nullptr for an unknown name); const or not, as o is.
template <class Options>
auto effect_flag(Options* o, std::string_view name) -> decltype(&o->shadow) {
  if (name == "shadow") return &o->shadow;
  if (name == "ao") return &o->ao;
  if (name == "reflection") return &o->reflection;
  if (name == "refraction") return &o->refraction;
  if (name == "diffuse") return &o->diffuse;
  return nullptr;
}

std::string trim(std::string_view s) {
  size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string_view::npos ? std::string() : std::string(s.substr(a, b - a + 1));
}

std::vector<std::string> split_list(std::string_view spec) {
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    size_t c = spec.find(',', start);
    out.push_back(trim(spec.substr(start, c == std::string_view::npos ? c : c - start)));
    if (c == std::string_view::npos) break;
    start = c + 1;
  }
  return out;
}

}  // namespace

EffectChoice derive_effects(const Scene& s) {
  EffectChoice c;
  std::vector<std::string> lights;
  for (const Light& l : s.lights) lights.push_back(l.name + " " + light_type_name(l.type));
  SceneLights sl(s);
  std::vector<std::string> meshes;
  for (size_t i = 0; i < sl.mesh_count(); ++i)
    meshes.push_back(sl.name(static_cast<uint32_t>(sl.punctual_count() + i)));
  c.shadow = !lights.empty() || !meshes.empty();
  if (c.shadow) {
    std::vector<std::string> parts;
    if (!lights.empty())
      parts.push_back(plural(lights.size(), "punctual light") + " (" + join_limited(lights) + ")");
    if (!meshes.empty())
      parts.push_back(plural(meshes.size(), "emissive mesh") + " (" + join_limited(meshes) + ")");
    c.shadow_why = parts.size() == 2 ? parts[0] + "; " + parts[1] : parts[0];
  } else {
    c.shadow_why = "no punctual light and no emissive material";
  }

  auto refl = materials_where(s, is_specular_reflector, [](const Material& m) {
    return "metallic " + fmt(m.metallic) + ", roughness " + fmt(m.roughness);
  });
  c.reflection = !refl.empty();
  c.reflection_why = c.reflection ? "material " + join_limited(refl)
                                  : "no material with metallic >= " + fmt(kReflectMinMetallic) +
                                        " and roughness <= " + fmt(kReflectMaxRoughness);
  auto refr = materials_where(s, is_transmissive, [](const Material& m) {
    return "transmission " + fmt(m.transmission) + ", ior " + fmt(m.ior);
  });
  c.refraction = !refr.empty();
  c.refraction_why = c.refraction ? "material " + join_limited(refr)
                                  : "no material with transmission > 0";
  return c;
}

std::string apply_effects(std::string_view spec, const Scene& scene, WorkloadOptions* opt) {
  const std::string expected =
      "expected 'auto', 'none', or a comma-separated list of: auto, primary, shadow, ao, "
      "reflection, refraction, diffuse";
  WorkloadOptions o = *opt;
  for (const char* n : kEffectNames) *effect_flag(&o, n) = false;
  const std::vector<std::string> items = split_list(spec);
  for (const std::string& item : items) {
    if (item == "auto") {
      const EffectChoice c = derive_effects(scene);
      o.shadow |= c.shadow;
      o.reflection |= c.reflection;
      o.refraction |= c.refraction;
    } else if (item == "none") {
      if (items.size() != 1) return "'none' cannot be combined with other effects";
    } else if (item == "primary") {
      // always traced
    } else if (bool* f = effect_flag(&o, item)) {
      *f = true;
    } else {
      return "unknown effect '" + item + "' in '" + std::string(spec) + "': " + expected;
    }
  }
  *opt = o;
  return {};
}

std::vector<std::string> describe_effects(const Scene& scene, const WorkloadOptions& opt,
                                          std::string_view spec) {
  const EffectChoice c = derive_effects(scene);
  const std::vector<std::string> items = split_list(spec);
  const bool is_auto = std::find(items.begin(), items.end(), "auto") != items.end();
  std::vector<std::string> lines;
  for (const char* name : kEffectNames) {
    const bool on = *effect_flag(&opt, name);
    const bool listed = std::find(items.begin(), items.end(), name) != items.end();
    const std::string_view n = name;
    const bool derivable = n == "shadow" ? c.shadow : n == "reflection" ? c.reflection
                                                    : n == "refraction" ? c.refraction : false;
    const std::string why = n == "shadow"       ? c.shadow_why
                            : n == "reflection" ? c.reflection_why
                            : n == "refraction" ? c.refraction_why
                            : n == "ao"         ? "ambient occlusion: only on request"
                                                : "diffuse bounces: only on request";
    std::string line = std::string(name) + std::string(12 - n.size(), ' ') + (on ? "on   " : "off  ");
    if (on && listed && !derivable && (n == "shadow" || n == "reflection" || n == "refraction"))
      line += "requested, but " + why + ": no " + name + " rays";
    else if (on && listed)
      line += "requested" + (derivable ? ": " + why : std::string());
    else if (on)
      line += "derived: " + why;
    else if (derivable)
      line += "not requested (the scene calls for it: " + why + ")";
    else if (is_auto || n == "ao" || n == "diffuse")
      line += (n == "ao" || n == "diffuse") ? why + " (add it with --effects auto," + name + ")"
                                            : "not derived: " + why;
    else
      line += "not requested";
    lines.push_back(line);
  }
  return lines;
}

void workload_resolution(const Scene& scene, const WorkloadOptions& opt, int* width, int* height) {
  *width = opt.width > 0 ? opt.width : scene.camera.width;
  *height = opt.height > 0 ? opt.height : scene.camera.height;
}

static float ao_distance_for(const Scene& scene, const WorkloadOptions& opt) {
  return opt.ao_distance > 0 ? opt.ao_distance : 0.05f * scene.bounds.diagonal();
}

nlohmann::json workload_json(const Scene& scene, const WorkloadOptions& opt) {
  int w, h;
  workload_resolution(scene, opt, &w, &h);
  nlohmann::json effects = nlohmann::json::array({"primary"});
  for (const char* n : kEffectNames)
    if (*effect_flag(&opt, n)) effects.push_back(n);
  return {{"scene", scene.path},
          {"resolution", {w, h}},
          {"spp", opt.spp},
          {"seed", opt.seed},
          {"effects", effects},
          {"order", std::string(ray_order_name(opt.order))},
          {"tile", opt.tile},
          {"max_depth", opt.max_depth},
          {"ao_distance", ao_distance_for(scene, opt)}};
}

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
  return scene_.meshes[m.range].name + ": " + plural(m.tris.size(), "triangle");
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
  const float cos_t = 1.f / std::sqrt(1.f + tan2), sin_t = std::sqrt(std::max(0.f, 1.f - cos_t * cos_t));
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
      : scene_(scene), bvh_(bvh), opt_(opt), w_(w), h_(h), spp_(std::max(1, opt.spp)),
        ao_dist_(ao_distance_for(scene, opt)), lights_(scene), sink_(sink) {}

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

}  // namespace

void generate_rays(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                   const std::function<void(const RayRecord&, const Hit*)>& sink) {
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
