// Fuzz target: the scene loader (model/src/scene/scene.cc, tinygltf underneath) on any bytes, as a
// .glb (bytes starting with "glTF") or a .gltf (anything else). Properties: it either returns a
// consistent scene or throws a SceneError whose message names the input; a returned scene has
// triangles, finite vertices, a material for every triangle, mesh ranges inside the triangle
// list and finite bounds and camera; the BVH built over it satisfies check_bvh.
#include <cmath>
#include <string>

#include "fuzz_util.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"

using namespace hrpp;

namespace {

bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string name = "fuzz-input.gltf";
  Scene s;
  try {
    s = load_scene_from_memory(data, size, name);
  } catch (const SceneError& e) {
    if (std::string(e.what()).rfind(name + ": ", 0) != 0)
      fuzz::violated(std::string("SceneError message does not name the input: ") + e.what());
    return 0;
  }
  if (s.triangles.empty()) fuzz::violated("a scene without triangles was accepted");
  if (s.tri_material.size() != s.triangles.size())
    fuzz::violated("tri_material has " + std::to_string(s.tri_material.size()) + " entries for " +
                   std::to_string(s.triangles.size()) + " triangles");
  for (uint32_t m : s.tri_material)
    if (m >= s.materials.size()) fuzz::violated("material index out of range");
  for (const Triangle& t : s.triangles)
    if (!finite(t.v0) || !finite(t.v1) || !finite(t.v2)) fuzz::violated("non-finite vertex");
  uint64_t covered = 0;
  for (const MeshRange& m : s.meshes) {
    if (uint64_t{m.first} + m.count > s.triangles.size()) fuzz::violated("mesh range outside");
    covered += m.count;
  }
  if (covered != s.triangles.size())
    fuzz::violated("mesh ranges cover " + std::to_string(covered) + " of " +
                   std::to_string(s.triangles.size()) + " triangles");
  if (!finite(s.bounds.lo) || !finite(s.bounds.hi)) fuzz::violated("non-finite bounds");
  if (!finite(s.camera.eye) || !finite(s.camera.target) || !std::isfinite(s.camera.fov_y_deg))
    fuzz::violated("non-finite camera");
  for (const Light& l : s.lights)
    if (!finite(l.position) || !finite(l.direction) || !std::isfinite(l.intensity))
      fuzz::violated("non-finite light");
  if (s.triangles.size() <= 100000) {
    const Bvh bvh = build_bvh(s.triangles);
    const std::string err = check_bvh(bvh, s.triangles.size());
    if (!err.empty()) fuzz::violated("check_bvh: " + err);
  }
  return 0;
}
