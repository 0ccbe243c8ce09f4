// Basic geometry for the golden model: vectors (GLM), axis-aligned boxes, triangles and the
// floating-point helpers the robust intersection tests rely on.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>

namespace hrpp {

using Vec3 = glm::vec3;
using DVec3 = glm::dvec3;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kFloatEps = std::numeric_limits<float>::epsilon() * 0.5f;  // unit roundoff

/// pbrt-v4's gamma(n): bound on the relative error of n chained float operations.
constexpr float gamma(int n) { return (n * kFloatEps) / (1 - n * kFloatEps); }

/// Next representable float above / below v (pbrt-v4 NextFloatUp/Down); +-0 are treated alike.
inline float next_float_up(float v) {
  if (std::isinf(v) && v > 0) return v;
  if (v == -0.f) v = 0.f;
  uint32_t ui = std::bit_cast<uint32_t>(v);
  ui = v >= 0 ? ui + 1 : ui - 1;
  return std::bit_cast<float>(ui);
}
inline float next_float_down(float v) {
  if (std::isinf(v) && v < 0) return v;
  if (v == 0.f) v = -0.f;
  uint32_t ui = std::bit_cast<uint32_t>(v);
  ui = v > 0 ? ui - 1 : ui + 1;
  return std::bit_cast<float>(ui);
}

inline float max_abs(const Vec3& v) {
  return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

struct Aabb {
  Vec3 lo{kInf, kInf, kInf};
  Vec3 hi{-kInf, -kInf, -kInf};

  void grow(const Vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void grow(const Aabb& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  Vec3 extent() const { return empty() ? Vec3(0) : hi - lo; }
  Vec3 center() const { return (lo + hi) * 0.5f; }
  float half_area() const {
    Vec3 e = extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
  /// Computed in double (squaring extents above 1.8e19 overflows float); +inf only when the
  /// diagonal itself is beyond float's range.
  float diagonal() const {
    const Vec3 e = extent();
    return static_cast<float>(std::sqrt(double(e.x) * e.x + double(e.y) * e.y + double(e.z) * e.z));
  }
  bool contains(const Aabb& b) const {
    return b.lo.x >= lo.x && b.lo.y >= lo.y && b.lo.z >= lo.z && b.hi.x <= hi.x && b.hi.y <= hi.y &&
           b.hi.z <= hi.z;
  }
  int largest_axis() const {
    Vec3 e = extent();
    return e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
  }
};

struct Triangle {
  Vec3 v0, v1, v2;

  Aabb bounds() const {
    Aabb b;
    b.grow(v0);
    b.grow(v1);
    b.grow(v2);
    return b;
  }
  /// Unnormalized geometric normal (v1-v0)x(v2-v0).
  Vec3 normal() const { return glm::cross(v1 - v0, v2 - v0); }
  /// True when the triangle has zero area (collinear or repeated vertices), decided in double
  /// precision. Such triangles are kept in the BVH but never reported as hit.
  bool degenerate() const {
    DVec3 e1 = DVec3(v1) - DVec3(v0), e2 = DVec3(v2) - DVec3(v0);
    DVec3 n = glm::cross(e1, e2);
    return n.x == 0 && n.y == 0 && n.z == 0;
  }
  float area() const { return 0.5f * glm::length(normal()); }
};

}  // namespace hrpp
