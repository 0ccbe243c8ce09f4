// Scenes: triangles with materials, lights and a camera, loaded from glTF 2.0 (.glb / .gltf).
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hrpp/scene/geometry.h"

namespace hrpp {

/// Any problem with a scene file. The message names the file and the problem.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Material {
  std::string name;
  glm::vec4 base_color{1.f};
  float metallic = 1.f;  // glTF defaults
  float roughness = 1.f;
  Vec3 emissive{0.f};
  float emissive_strength = 1.f;  // KHR_materials_emissive_strength
  float transmission = 0.f;       // KHR_materials_transmission
  float ior = 1.5f;               // KHR_materials_ior
  float specular = 1.f;           // KHR_materials_specular
  bool double_sided = false;

  Vec3 emission() const { return emissive * emissive_strength; }
  bool is_emissive() const { return emission() != Vec3(0.f); }
};

struct Light {
  enum class Type { kPoint, kDirectional, kSpot };
  Type type = Type::kPoint;
  std::string name;
  Vec3 position{0.f};              // world space (point, spot)
  Vec3 direction{0.f, 0.f, -1.f};  // unit, the direction light travels (directional, spot)
  Vec3 color{1.f};
  float intensity = 1.f;
  float range = 0.f;  // 0: unlimited
};
const char* light_type_name(Light::Type t);

struct Camera {
  Vec3 eye{0.f}, target{0.f, 0.f, -1.f}, up{0.f, 1.f, 0.f};
  float fov_y_deg = 45.f;
  float aspect = 1.f;
  int width = 512, height = 512;  // the source's image size where it had one
  std::string source;             // "gltf camera N", "sidecar FILE" or "computed default"
};

/// One glTF mesh primitive after flattening: a contiguous run of the scene's triangles.
struct MeshRange {
  std::string name;  // node name (or mesh name)
  uint32_t first = 0, count = 0;
  uint32_t material = 0;
};

struct Scene {
  std::string path;
  std::string name;  // file stem
  std::vector<Triangle> triangles;
  std::vector<uint32_t> tri_material;  // per triangle, index into materials
  std::vector<MeshRange> meshes;
  std::vector<Material> materials;  // the last one is the default material if any primitive
                                    // had none
  std::vector<Light> lights;        // punctual lights (KHR_lights_punctual)
  Camera camera;
  Aabb bounds;
  uint32_t degenerate_triangles = 0;

  const Material& material_of(uint32_t tri) const { return materials[tri_material[tri]]; }
  /// Indices of the triangles whose material emits light (area lights).
  std::vector<uint32_t> emissive_triangles() const;
};

/// The traceable range (docs/bvh.md, "Valid range"), derived from the float error model of the
/// watertight triangle test: with every vertex coordinate within kMaxSceneCoordinate and every ray
/// origin within kMaxRayOrigin, a unit-direction ray's edge functions, determinant and scaled
/// distance T stay below FLT_MAX (|T| <= 24 sqrt(3) (kMaxSceneCoordinate + kMaxRayOrigin)^3 =
/// 7.9e37), so the test is exact-or-conservative. The loader rejects geometry, cameras and lights
/// outside it; the default camera of in-range geometry is always inside it.
constexpr float kMaxSceneCoordinate = 0x1p37f;  // 1.374e11: vertex coordinates (world space)
constexpr float kMaxRayOrigin = 0x1p40f;        // 1.100e12: camera eye and target, light positions
/// Non-degenerate triangles must have twice their area (|e1 x e2| in double) at least this: below
/// it the reciprocal of the test's determinant overflows at any incidence that is not a graze,
/// and the triangle would silently never be hit.
constexpr double kMinTwiceArea = 0x1p-100;  // 7.9e-31

/// Loads a .glb or .gltf file: every mesh primitive of the default scene with node transforms
/// applied, cameras, KHR_lights_punctual lights and materials. The camera comes from the file's
/// first camera node, else from a sidecar NAME.camera.json next to it, else a computed default.
/// Throws SceneError naming the file and the problem, also for geometry outside the traceable
/// range above (naming the node, mesh and offending value).
Scene load_scene(const std::string& path);

/// Keeps only the triangles of the named meshes (MeshRange::name), in their order: the scene's
/// triangles, materials per triangle, meshes, bounds and degenerate count follow; its camera and
/// lights stay. Throws std::invalid_argument naming an unknown mesh (and the scene's meshes).
void keep_meshes(Scene* scene, const std::vector<std::string>& names);

/// Loads glTF bytes held in memory (binary when they start with "glTF", else JSON; external
/// buffer URIs are not resolved, and the camera is the file's or a computed default). `name`
/// names the bytes in messages. Throws SceneError. Used by the scene-loader fuzz target.
Scene load_scene_from_memory(const unsigned char* data, size_t size, const std::string& name);

/// Reads a camera sidecar (format in ../shared/scenes/SOURCES.md). Throws SceneError.
Camera load_camera_sidecar(const std::string& path);

/// A default camera looking at the bounds from the +z side (used when nothing else is given).
Camera default_camera(const Aabb& bounds);

}  // namespace hrpp
