// Rays, ray kinds, and the validation that keeps invalid rays out of traversal, hashing and
// Embree (Debian's Embree 3.13.5 aborts on NaN/inf fields, huge directions and tnear < 0).
#pragma once

#include <cstdint>
#include <string_view>

#include "hrpp/scene/geometry.h"

namespace hrpp {

enum class RayKind : uint8_t {
  kPrimary = 0,
  kShadow = 1,      // any-hit
  kAo = 2,          // ambient occlusion, any-hit
  kReflection = 3,  // closest-hit
  kRefraction = 4,  // closest-hit
  kDiffuse = 5,     // closest-hit
};
constexpr int kNumRayKinds = 6;

std::string_view ray_kind_name(RayKind k);
/// Parses a kind name ("primary", "shadow", ...); returns false when unknown.
bool parse_ray_kind(std::string_view name, RayKind* out);
/// Any-hit kinds end at the first hit found; the others need the closest hit.
inline bool is_any_hit(RayKind k) { return k == RayKind::kShadow || k == RayKind::kAo; }

struct Ray {
  Vec3 org{0};
  Vec3 dir{0, 0, 1};
  float tnear = 0;
  float tfar = kInf;
};

/// Why a ray is invalid. Invalid rays are counted and never traced, hashed or sent to Embree.
enum class RayError : uint8_t {
  kNone = 0,
  kNotFinite,          // NaN or infinity in origin, direction or tnear; NaN in tfar
  kZeroDirection,      // all direction components are (+-)0
  kDirectionTooLarge,  // a direction component above kMaxDirection (Embree asserts)
  kNegativeTnear,      // tnear < 0
  kTnearAboveTfar,     // tnear > tfar: an empty interval
};
constexpr int kNumRayErrors = 6;
/// Direction components above this magnitude are rejected (Embree 3.13.5 asserts near 1.8e18).
constexpr float kMaxDirection = 1e18f;

std::string_view ray_error_name(RayError e);

/// Classifies a ray. tfar = +inf is valid; everything else must be finite.
RayError validate_ray(const Ray& r);

}  // namespace hrpp
