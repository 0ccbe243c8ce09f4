// Small hand-made glTF scenes for the workload tests: meshes with materials, punctual lights and
// a camera file, written as NAME.gltf + NAME.bin + NAME.camera.json and loaded with load_scene.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hrpp/scene/geometry.h"

namespace hrpp::test {

struct MaterialSpec {
  std::string name = "matte";
  Vec3 base{0.7f};
  float metallic = 0.f, roughness = 1.f;
  Vec3 emissive{0.f};
  float emissive_strength = 1.f;
  float transmission = 0.f, ior = 1.5f;
  bool double_sided = true;
};

class SceneBuilder {
 public:
  SceneBuilder();
  int material(const MaterialSpec& m);
  /// Adds a mesh node; returns the scene index of its first triangle (meshes are flattened in
  /// the order they are added).
  uint32_t mesh(const std::string& name, const std::vector<Vec3>& verts,
                const std::vector<uint32_t>& indices, int material);
  /// A quad with corners c, c+a, c+a+b, c+b, wound so that its normal points along `facing`.
  uint32_t quad(const std::string& name, Vec3 c, Vec3 a, Vec3 b, Vec3 facing, int material);
  /// A UV sphere (triangles wound outwards); returns the first triangle.
  uint32_t sphere(const std::string& name, Vec3 centre, float radius, int material, int stacks = 12,
                  int slices = 24);
  /// An axis-aligned box (triangles wound outwards).
  uint32_t box(const std::string& name, Vec3 lo, Vec3 hi, int material);
  void point_light(const std::string& name, Vec3 pos, float intensity);
  void camera(Vec3 eye, Vec3 target, Vec3 up, float fov_y_deg, int width, int height);
  uint32_t triangles() const { return tris_; }
  /// Writes DIR/NAME.gltf, .bin and .camera.json; returns the .gltf path.
  std::string write(const std::string& dir, const std::string& name) const;

 private:
  nlohmann::json j_, camera_;
  std::vector<uint8_t> bin_;
  uint32_t tris_ = 0;
};

}  // namespace hrpp::test
