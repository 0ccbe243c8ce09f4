// Building blocks of ray generation shared by the workload generator (hrpp/workload/workload.h) and
// the renderer (hrpp/report/render.h): offset origins, camera rays, hit points, light samples, and
// the path keys every random number is drawn from.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hrpp/scene/geometry.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/ray.h"
#include "hrpp/trace/traverse.h"

namespace hrpp {

/// Offsets p along the unit normal n (pointing to the side the new ray leaves on) so that a
/// ray started there does not re-hit the surface (Ray Tracing Gems ch. 6, listing 6-1).
Vec3 offset_ray_origin(const Vec3& p, const Vec3& n);

/// Camera ray through pixel (x, y) for sample s, stratified and jittered.
Ray camera_ray(const Camera& cam, int width, int height, int x, int y, int s, int spp,
               uint64_t seed);

/// Resolution for about `rays` camera samples at the camera's aspect ratio.
void resolution_for(const Camera& cam, uint64_t rays, int spp, int* width, int* height);

/// Where a closest-hit ray hit: the point, the normals and the material.
struct SurfacePoint {
  Vec3 p;             // barycentric interpolation of the triangle's vertices
  Vec3 ng;            // unit geometric normal (v1-v0)x(v2-v0), as wound
  Vec3 n;             // ng turned towards the side the ray came from
  bool front = true;  // the ray arrived on the side ng points to (it is entering a closed mesh)
  uint32_t prim = kNoPrim;
  const Material* material = nullptr;
};
SurfacePoint surface_point(const Scene& scene, const Ray& ray, const Hit& hit);

/// A shadow ray's target: a punctual light, or a point sampled on an emissive mesh.
struct LightSample {
  Vec3 dir;            // unit, from the origin towards the light
  float tfar = 0;      // stops just short of the light (inf for directional lights)
  uint32_t light = 0;  // punctual lights 0..P-1, then emissive meshes P..P+M-1
  Vec3 irradiance{0};  // unoccluded irradiance at the origin over cos(receiver): intensity /
                       // dist^2, or emission * cos(emitter) * mesh area / dist^2 (one sample)
};

/// The scene's lights as shadow rays sample them: every punctual light (spot lights as point
/// lights), and every emissive mesh, one point per mesh chosen uniformly by area.
class SceneLights {
 public:
  explicit SceneLights(const Scene& scene);
  size_t punctual_count() const { return scene_.lights.size(); }
  size_t mesh_count() const { return meshes_.size(); }
  /// Name of light i (punctual light name or emissive mesh name).
  std::string name(uint32_t i) const;
  /// One sample of every light from origin o (an offset origin) with facing unit normal n.
  /// Lights behind the surface, and one-sided emitters facing away, give no sample. The random
  /// numbers of light i are uniform01(seed, light_key(key, i), 0..2).
  void sample(const Vec3& o, const Vec3& n, uint64_t seed, uint64_t key,
              std::vector<LightSample>* out) const;

 private:
  struct Mesh {
    uint32_t range;              // index into scene.meshes
    std::vector<uint32_t> tris;  // non-degenerate triangles
    std::vector<float> cdf;      // by area
    Vec3 emission;
    bool one_sided;
  };
  const Scene& scene_;
  std::vector<Mesh> meshes_;
};

/// Path key of a camera sample, and of a ray spawned from a hit of the ray with key `parent`
/// (kind, and a slot: the light index for shadow rays, else 0). Random numbers are drawn from
/// these keys, so they do not depend on the issue order.
uint64_t camera_key(uint32_t pixel, uint32_t sample);
uint64_t child_key(uint64_t parent, RayKind kind, uint32_t slot);

}  // namespace hrpp
