// Ray generation from a scene: camera rays, and secondary rays spawned from their hits with
// offset origins (Waechter and Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
// Ray Tracing Gems ch. 6). Deterministic: each random number is a function of (seed, ray).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "hrpp/bvh.h"
#include "hrpp/ray.h"
#include "hrpp/scene.h"
#include "hrpp/traverse.h"

namespace hrpp {

struct RayRecord {
  Ray ray;
  RayKind kind = RayKind::kPrimary;
  uint32_t pixel = 0;   // y * width + x
  uint32_t sample = 0;  // sample index within the pixel
  uint64_t id = 0;      // position in the stream
  uint64_t parent = ~0ull;  // id of the ray whose hit spawned this one
};

struct WorkloadOptions {
  int width = 0, height = 0;  // 0: from the camera (its image size)
  int spp = 1;
  uint64_t seed = 1;
  bool shadow = true;         // towards punctual lights and emissive meshes
  bool ao = true;             // one cosine-weighted ambient-occlusion ray per primary hit
  float ao_distance = 0.f;    // 0: 5% of the scene's bounding-box diagonal
};

/// Offsets p along the unit normal n (pointing to the side the new ray leaves on) so that a
/// ray started there does not re-hit the surface (Ray Tracing Gems ch. 6, listing 6-1).
Vec3 offset_ray_origin(const Vec3& p, const Vec3& n);

/// Camera ray through pixel (x, y) for sample s, stratified and jittered.
Ray camera_ray(const Camera& cam, int width, int height, int x, int y, int s, int spp,
               uint64_t seed);

/// Resolution for about `rays` camera samples at the camera's aspect ratio.
void resolution_for(const Camera& cam, uint64_t rays, int spp, int* width, int* height);

/// Generates primary rays in scanline order and, for each primary hit (found with our BVH),
/// the shadow and AO rays the options ask for. Calls sink for every ray, primary first.
void generate_rays(const Scene& scene, const Bvh& bvh, const WorkloadOptions& opt,
                   const std::function<void(const RayRecord&, const Hit* primary_hit)>& sink);

}  // namespace hrpp
