// Closest-hit and any-hit BVH traversal with per-ray work counters (docs/bvh.md).
//
// Robustness: the slab test follows Ize, "Robust BVH Ray Traversal" (JCGT 2013) and pbrt-v4's
// Bounds3::IntersectP: the far distance is widened by 1 + 2*gamma(3), and a NaN slab distance
// (0 * inf: origin on a box face with a zero direction component) is ignored rather than
// poisoning the interval. The triangle test is the watertight test of Woop, Benthin and Wald,
// "Watertight Ray/Triangle Intersection" (JCGT 2013), with its double-precision fallback for
// zero edge functions and no backface culling.
//
// Counters: an interior-node test is one fetch of an interior node and the test of both of its
// children's boxes (box_tests counts the single boxes, including the start node's own box);
// a leaf visit is one leaf whose triangles are tested; tri_tests counts triangle tests.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "hrpp/trace/bvh.h"
#include "hrpp/trace/ray.h"

namespace hrpp {

constexpr uint32_t kNoPrim = 0xFFFFFFFFu;

struct Counters {
  uint64_t interior_tests = 0;
  uint64_t box_tests = 0;
  uint64_t leaf_visits = 0;
  uint64_t tri_tests = 0;

  Counters& operator+=(const Counters& o) {
    interior_tests += o.interior_tests;
    box_tests += o.box_tests;
    leaf_visits += o.leaf_visits;
    tri_tests += o.tri_tests;
    return *this;
  }
  bool operator==(const Counters&) const = default;
};

struct Hit {
  float t = kInf;
  float u = 0, v = 0;       // barycentrics of v1 and v2
  uint32_t prim = kNoPrim;  // scene triangle index
  uint32_t leaf = kNoNode;  // BVH leaf where the hit was found
  bool hit() const { return prim != kNoPrim; }
};

/// Per-ray precomputation shared by the box and triangle tests.
struct RayPre {
  Vec3 org, dir, inv;
  int kx, ky, kz;
  float sx, sy, sz;
  explicit RayPre(const Ray& r) : org(r.org), dir(r.dir) {
    inv = Vec3(1.f / dir.x, 1.f / dir.y, 1.f / dir.z);  // +-0 gives +-inf
    const Vec3 a = glm::abs(dir);
    kz = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (dir[kz] < 0) std::swap(kx, ky);  // keep the winding
    sx = dir[kx] / dir[kz];
    sy = dir[ky] / dir[kz];
    sz = 1.f / dir[kz];
  }
};

/// The factor by which a walk widens its limit (the closest hit's t so far, or the next float
/// above tfar) before it culls a box against it: 1 + 2^-20 = 1 + 16 u (u = 2^-24, the unit
/// roundoff). A box whose entry distance is not above limit * kCullWiden is walked. With it no
/// box is culled that holds a triangle the triangle test accepts below the limit, when the box
/// is entered through a face across the ray's dominant axis (a triangle in that face plane
/// included); the proof, and what remains for the other faces, in docs/bvh.md ("Culling against
/// the current hit").
inline constexpr float kCullWiden = 1 + 0x1p-20f;

/// Conservative slab test of the interval [tmin, limit * kCullWiden] (the walks' box test: limit
/// is the closest hit so far, or the next float above tfar); on a hit *entry is the entry
/// distance.
bool intersect_box(const RayPre& r, const Vec3& lo, const Vec3& hi, float tmin, float limit,
                   float* entry);

/// Watertight ray/triangle test. Accepts t with tmin <= t < tlimit (strict upper bound, so a
/// closest-hit search keeps the first of equal hits). Never returns a non-finite t.
bool intersect_triangle(const RayPre& r, const Triangle& tri, float tmin, float tlimit, float* t,
                        float* u, float* v);

struct TraceRequest {
  uint32_t start_node = 0;                // walk the subtree of this node (0: the whole BVH)
  std::vector<uint32_t>* path = nullptr;  // if set, receives every visited node in order
};

/// Closest hit in [ray.tnear, ray.tfar]. The ray must be valid (validate_ray). Near child first.
Hit closest_hit(const Bvh& bvh, const Ray& ray, Counters* counters, const TraceRequest& req = {});

/// First hit found in [ray.tnear, ray.tfar] (shadow / occlusion queries).
Hit any_hit(const Bvh& bvh, const Ray& ray, Counters* counters, const TraceRequest& req = {});

/// Two closest-hit walks from the root in one pass: *base is closest_hit(bvh, ray, base_c) and
/// *bounded is closest_hit(bvh, ray with tfar = bounded_tfar, bounded_c), hits and counters bit
/// for bit (requires bounded_tfar <= ray.tfar). The bounded walk visits, in the same order, a
/// subsequence of the nodes the full walk visits as long as its limit stays at or below the full
/// walk's; in the rare case where it does not (a hit nearer than a culled box's entry distance,
/// by rounding), the bounded walk is run again on its own. Used by the predictor's closest-exact
/// mode (the walk shortened by a predicted hit beside the baseline walk).
void closest_hit_pair(const Bvh& bvh, const Ray& ray, float bounded_tfar, Hit* base,
                      Counters* base_c, Hit* bounded, Counters* bounded_c);

/// Reference: tests every triangle (for tests and fuzzing).
Hit brute_force_closest(const Bvh& bvh, const Ray& ray);

}  // namespace hrpp
