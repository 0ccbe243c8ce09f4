// The workload's options resolved for a scene: ray orders, the effects a scene calls for and the
// --effects syntax, the resolution and AO distance, and the options as JSON.
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "hrpp/workload/workload.h"

namespace hrpp {

// ---- orders, effects ------------------------------------------------------------------------

std::string_view ray_order_name(RayOrder o) {
  switch (o) {
    case RayOrder::kScanline:
      return "scanline";
    case RayOrder::kTiled:
      return "tiled";
    case RayOrder::kMorton:
      return "morton";
  }
  return "?";
}

std::string_view workload_source_name(WorkloadSource s) {
  switch (s) {
    case WorkloadSource::kMicro21Ao:
      return "micro21-ao";
    case WorkloadSource::kMicro21AoSorted:
      return "micro21-ao-sorted";
    case WorkloadSource::kCamera:
      break;
  }
  return "camera";
}

bool parse_workload_source(std::string_view name, WorkloadSource* out) {
  for (WorkloadSource s :
       {WorkloadSource::kCamera, WorkloadSource::kMicro21Ao, WorkloadSource::kMicro21AoSorted})
    if (workload_source_name(s) == name) {
      *out = s;
      return true;
    }
  return false;
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

bool is_transmissive(const Material& m) {
  return m.transmission > 0.f && !is_specular_reflector(m);
}

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
  c.refraction_why =
      c.refraction ? "material " + join_limited(refr) : "no material with transmission > 0";
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
    const bool derivable = n == "shadow"       ? c.shadow
                           : n == "reflection" ? c.reflection
                           : n == "refraction" ? c.refraction
                                               : false;
    const std::string why = n == "shadow"       ? c.shadow_why
                            : n == "reflection" ? c.reflection_why
                            : n == "refraction" ? c.refraction_why
                            : n == "ao"         ? "ambient occlusion: only on request"
                                                : "diffuse bounces: only on request";
    std::string line =
        std::string(name) + std::string(12 - n.size(), ' ') + (on ? "on   " : "off  ");
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

float ao_distance_for(const Scene& scene, const WorkloadOptions& opt) {
  return opt.ao_distance > 0 ? opt.ao_distance : 0.05f * scene.bounds.diagonal();
}

nlohmann::json workload_json(const Scene& scene, const WorkloadOptions& opt) {
  if (is_micro21_ao(opt.source)) {
    nlohmann::json j = {{"scene", scene.path},
                        {"workload", std::string(workload_source_name(opt.source))},
                        {"seed", opt.seed},
                        {"effects", {"ao"}},
                        {"tnear", kMicro21AoTnear},
                        {"ao_distance", "inf"},
                        {"max_rays", kMicro21AoMaxRays}};
    if (opt.micro21_flip) j["ao_normal"] = "flipped";
    return j;
  }
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
          // Unbounded AO rays are recorded as the string "inf" (JSON has no infinity, and
          // nlohmann would write null).
          {"ao_distance", std::isinf(ao_distance_for(scene, opt))
                              ? nlohmann::json("inf")
                              : nlohmann::json(ao_distance_for(scene, opt))}};
}

}  // namespace hrpp
