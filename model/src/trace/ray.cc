#include "hrpp/trace/ray.h"

namespace hrpp {

std::string_view ray_kind_name(RayKind k) {
  switch (k) {
    case RayKind::kPrimary:
      return "primary";
    case RayKind::kShadow:
      return "shadow";
    case RayKind::kAo:
      return "ao";
    case RayKind::kReflection:
      return "reflection";
    case RayKind::kRefraction:
      return "refraction";
    case RayKind::kDiffuse:
      return "diffuse";
  }
  return "?";
}

bool parse_ray_kind(std::string_view name, RayKind* out) {
  for (int k = 0; k < kNumRayKinds; ++k)
    if (ray_kind_name(static_cast<RayKind>(k)) == name) {
      *out = static_cast<RayKind>(k);
      return true;
    }
  return false;
}

std::string_view ray_error_name(RayError e) {
  switch (e) {
    case RayError::kNone:
      return "valid";
    case RayError::kNotFinite:
      return "NaN or infinite field";
    case RayError::kZeroDirection:
      return "zero direction";
    case RayError::kDirectionTooLarge:
      return "direction component above 1e18";
    case RayError::kNegativeTnear:
      return "tnear < 0";
    case RayError::kTnearAboveTfar:
      return "tnear > tfar";
  }
  return "?";
}

RayError validate_ray(const Ray& r) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(r.org[a]) || !std::isfinite(r.dir[a])) return RayError::kNotFinite;
  if (!std::isfinite(r.tnear) || std::isnan(r.tfar)) return RayError::kNotFinite;
  if (r.tfar == -kInf) return RayError::kNotFinite;
  if (r.dir.x == 0.f && r.dir.y == 0.f && r.dir.z == 0.f) return RayError::kZeroDirection;
  if (max_abs(r.dir) > kMaxDirection) return RayError::kDirectionTooLarge;
  if (r.tnear < 0.f) return RayError::kNegativeTnear;
  if (r.tnear > r.tfar) return RayError::kTnearAboveTfar;
  return RayError::kNone;
}

}  // namespace hrpp
