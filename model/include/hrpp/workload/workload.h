// Ray workloads from a scene (docs/workloads.md): camera rays, and the secondary rays the scene's
// lights and materials call for (shadow, reflection, refraction), plus ambient occlusion and
// diffuse bounces on request, issued in scanline, tiled or Morton order.
//
// Secondary rays start from offset origins (Waechter and Binder, "A Fast and Robust Method for
// Avoiding Self-Intersection", Ray Tracing Gems ch. 6). Deterministic: every random number is a
// function of (seed, camera sample, the ray's path from the camera), never of the issue order,
// so every order gives the same multiset of rays.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/trace/ray.h"
#include "hrpp/trace/traverse.h"
#include "hrpp/workload/sampling.h"

namespace hrpp {

struct RayRecord {
  Ray ray;
  RayKind kind = RayKind::kPrimary;
  uint32_t pixel = 0;             // y * width + x
  uint32_t sample = 0;            // sample index within the pixel
  uint64_t id = 0;                // position in the stream
  uint64_t parent = ~0ull;        // id of the ray whose hit spawned this one
  uint32_t spawn_prim = kNoPrim;  // scene triangle whose hit spawned this ray (kNoPrim: primary)
  uint8_t depth = 0;  // bounces from the camera: primary 0, a ray spawned by a depth-d hit d+1
};

/// Issue order of the camera samples (docs/workloads.md). Rays are issued per group: the
/// group's primary rays, then its secondary rays generation by generation, each generation's
/// rays grouped by kind (shadow, ao, reflection, refraction, diffuse).
enum class RayOrder : uint8_t {
  kScanline = 0,  // group = one camera sample: each sample's rays follow its primary ray
  kTiled = 1,     // group = one tile of tile x tile pixels; tiles and pixels in scanline order
  kMorton = 2,    // group = one tile; tiles and the pixels inside a tile along a Z-order curve
};
std::string_view ray_order_name(RayOrder o);
bool parse_ray_order(std::string_view name, RayOrder* out);

/// Where the rays come from (docs/workloads.md).
enum class WorkloadSource : uint8_t {
  kCamera = 0,     // camera samples and the secondary rays their hits spawn
  kMicro21Ao = 1,  // MICRO 2021's AO benchmark: no camera, one AO ray per triangle
  /// The same rays in the order of MICRO 2021's ray sorting (its benchmark's --sort): by the
  /// key (origin cell << 7) | direction bin, the origin on a 32^3 grid over the scene's vertex
  /// bounds, the direction in 3 theta and 4 phi bits (RayGenerator.cpp 381-413, 444-451,
  /// 494-502 at 29eeb01); rays of one key keep their triangle order.
  kMicro21AoSorted = 2,
};
/// MICRO 2021's ray-sorting key of a ray over the scene's bounds (kMicro21AoSorted).
uint64_t micro21_sort_key(const Ray& ray, const Aabb& bounds);
/// Either of MICRO 2021's AO workloads.
inline bool is_micro21_ao(WorkloadSource s) { return s != WorkloadSource::kCamera; }
std::string_view workload_source_name(WorkloadSource s);
bool parse_workload_source(std::string_view name, WorkloadSource* out);

// MICRO 2021's AO benchmark (GitHub ubc-aamodt-group/ray-intersection-predictor, 29eeb01,
// rtao-benchmark/src): rays start at tmin = 0.1 world units and are unbounded (main.cpp 116:
// RayGenerator(camera, spp, 1, 0.1, FLT_MAX)); points are generated triangle by triangle until
// their count exceeds 1,000,000 (main.cpp 138, RayGenerator.cpp 563), so at most 1,000,001.
constexpr float kMicro21AoTnear = 0.1f;
constexpr uint64_t kMicro21AoMaxRays = 1000001;

struct WorkloadOptions {
  WorkloadSource source = WorkloadSource::kCamera;
  /// MICRO 2021's AO workloads: sample the hemisphere about the opposite of the triangle's
  /// normal as wound. Their benchmark samples about the OBJ file's vertex normals, or, for a face
  /// without them, (v0 - v1) x (v2 - v1), the opposite of ours (OBJ_Loader.h 822-833 at 29eeb01);
  /// its RayGenerator.h 72 notes that the teapot's normals point inwards.
  bool micro21_flip = false;
  int width = 0, height = 0;  // 0: from the camera (its image size)
  int spp = 1;
  uint64_t seed = 1;
  bool shadow = true;       // towards punctual lights and emissive meshes, from every hit
  bool ao = true;           // one cosine-weighted ambient-occlusion ray per primary hit
  bool reflection = false;  // from hits on specular reflectors (is_specular_reflector)
  bool refraction = false;  // from hits on transmissive materials (is_transmissive)
  bool diffuse = false;     // one cosine-weighted closest-hit bounce per hit
  int max_depth = 2;        // generations of reflection / refraction / diffuse rays
  float ao_distance = 0.f;  // 0: 5% of the scene's bounding-box diagonal; +inf: unbounded
  RayOrder order = RayOrder::kScanline;
  int tile = 8;  // tile edge in pixels (tiled and Morton orders)
};

// ---- effect derivation ---------------------------------------------------------------------

/// Reflection rays leave materials with metallic >= kReflectMinMetallic and roughness <=
/// kReflectMaxRoughness (glTF roughness; GGX alpha = roughness^2 <= 0.25).
constexpr float kReflectMinMetallic = 0.5f;
constexpr float kReflectMaxRoughness = 0.5f;
bool is_specular_reflector(const Material& m);
/// Refraction rays leave materials with transmission > 0 (KHR_materials_transmission) that are
/// not specular reflectors.
bool is_transmissive(const Material& m);

/// The effects a scene calls for, each with the reason (which lights, which materials).
struct EffectChoice {
  bool shadow = false, reflection = false, refraction = false;
  std::string shadow_why, reflection_why, refraction_why;
};
EffectChoice derive_effects(const Scene& scene);

/// Applies an --effects value: "auto" (what the scene calls for), "none" (primary rays only),
/// or a comma-separated list of effect names (shadow, ao, reflection, refraction, diffuse) in
/// which "auto" may appear, e.g. "auto,ao". Sets opt's shadow/ao/reflection/refraction/diffuse.
/// Returns an empty string, or the error.
std::string apply_effects(std::string_view spec, const Scene& scene, WorkloadOptions* opt);

/// Lines for the user: each effect on or off, and why.
std::vector<std::string> describe_effects(const Scene& scene, const WorkloadOptions& opt,
                                          std::string_view spec);

/// The generation options with the resolution, AO distance and effects resolved for the scene
/// (what ray-stream headers and reports record).
nlohmann::json workload_json(const Scene& scene, const WorkloadOptions& opt);

/// The width and height opt resolves to (the camera's when opt's are 0).
void workload_resolution(const Scene& scene, const WorkloadOptions& opt, int* width, int* height);

/// The length of ambient-occlusion rays opt resolves to (5% of the scene's bounding-box diagonal
/// when opt's is 0).
float ao_distance_for(const Scene& scene, const WorkloadOptions& opt);

/// Generates the workload in opt.order: primary rays and, from their hits (found with our BVH),
/// the secondary rays the options ask for (docs/workloads.md). With opt.source kMicro21Ao, MICRO
/// 2021's AO benchmark instead: for every non-degenerate triangle in the scene's order, one point
/// uniform on it (Osada et al.'s square-root formula, as RayGenerator.cpp 236) and one
/// cosine-weighted AO ray about its geometric normal as wound, from [kMicro21AoTnear, inf), at
/// most kMicro21AoMaxRays; the options' camera, effects and order do not apply. Calls sink for
/// every ray in issue order, a parent always before its children; `hit` is the ray's closest hit
/// for closest-hit kinds (the generator traces them to spawn their children) and nullptr for
/// any-hit kinds.
void generate_rays(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                   const std::function<void(const RayRecord&, const Hit* hit)>& sink);

}  // namespace hrpp
