// The double-precision referee of the cross-check (hrpp/reference/crosscheck.h) and of the
// traversal fuzzer: it tells genuine ties and grazes, on which two float tracers may disagree, from
// real disagreements. Needs no reference tracer.
#pragma once

#include "hrpp/scene/geometry.h"
#include "hrpp/trace/ray.h"

namespace hrpp {

/// Double-precision ray/triangle intersection (the referee).
struct RefereeHit {
  bool hit = false;      // inside the triangle (edges included) and within [tnear, tfar]
  double t = 0;          // distance along the ray to the triangle's plane
  double min_bary = 0;   // smallest barycentric coordinate (negative: outside)
  double edge_dist = 0;  // signed distance in the plane from the hit point to the nearest edge
  double cos_theta = 0;  // |cos| of the angle between the ray and the triangle's normal
};
RefereeHit referee_intersect(const Ray& r, const Triangle& tri);

/// Size of the perturbation (world units) within which two float tracers may legitimately
/// disagree: 128 * FLT_EPSILON times the largest coordinate magnitude of the ray origin, the
/// hit point and the triangle. Float intersection tests are exact for inputs perturbed by a few
/// ulps of the coordinates (backward error), so answers that change within this perturbation
/// are genuine ties or grazes.
double referee_delta(const Ray& r, const Triangle& tri, double t);

/// Tolerance for comparing two tracers' t on the same triangle: a perturbation of delta moves
/// the hit along the ray by delta / (|d| cos theta) (ill-conditioned at grazing incidence).
double t_tolerance(const Ray& r, const Triangle& tri, double t);

/// True when whether the ray hits the triangle changes within the perturbation of
/// referee_delta: the ray passes within it of an edge, or the hit lies within it of tnear or tfar.
/// Two float tracers may disagree on such a hit (a genuine graze).
bool referee_graze(const Ray& ray, const Triangle& tri);

}  // namespace hrpp
