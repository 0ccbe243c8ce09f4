#include "hrpp/trace/referee.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hrpp {

RefereeHit referee_intersect(const Ray& r, const Triangle& tri) {
  // Moeller-Trumbore in double precision, no culling.
  const DVec3 o(r.org), d(r.dir), v0(tri.v0), v1(tri.v1), v2(tri.v2);
  const DVec3 e1 = v1 - v0, e2 = v2 - v0;
  const DVec3 p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  RefereeHit h;
  if (det == 0) return h;
  const double inv = 1.0 / det;
  const DVec3 s = o - v0;
  const double b1 = glm::dot(s, p) * inv;
  const DVec3 q = glm::cross(s, e1);
  const double b2 = glm::dot(d, q) * inv;
  const double b0 = 1 - b1 - b2;
  h.t = glm::dot(e2, q) * inv;
  h.min_bary = std::min({b0, b1, b2});
  // b_i times the height over the edge opposite vertex i is the distance to that edge.
  const DVec3 n = glm::cross(e1, e2);
  const double twice_area = glm::length(n);
  const double lens[3] = {glm::length(v2 - v1), glm::length(v2 - v0), glm::length(e1)};
  const double bs[3] = {b0, b1, b2};
  h.edge_dist = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) h.edge_dist = std::min(h.edge_dist, bs[i] * twice_area / lens[i]);
  h.cos_theta = std::fabs(glm::dot(n, d)) / (twice_area * glm::length(d));
  h.hit = h.min_bary >= 0 && h.t >= r.tnear && h.t <= r.tfar;
  return h;
}

double referee_delta(const Ray& r, const Triangle& tri, double t) {
  const DVec3 hitp = DVec3(r.org) + (std::isfinite(t) ? t : 0.0) * DVec3(r.dir);
  const double m =
      std::max({double(max_abs(r.org)), std::fabs(hitp.x), std::fabs(hitp.y), std::fabs(hitp.z),
                double(max_abs(tri.v0)), double(max_abs(tri.v1)), double(max_abs(tri.v2))});
  return 128.0 * std::numeric_limits<float>::epsilon() * m;
}

double t_tolerance(const Ray& r, const Triangle& tri, double t) {
  const RefereeHit h = referee_intersect(r, tri);
  const double c = std::max(h.cos_theta, 1e-9);
  return referee_delta(r, tri, t) / (glm::length(DVec3(r.dir)) * c);
}

bool referee_graze(const Ray& ray, const Triangle& tri) {
  const RefereeHit r = referee_intersect(ray, tri);
  const double delta = referee_delta(ray, tri, r.t);
  if (std::fabs(r.edge_dist) * r.cos_theta <= delta) return true;
  const double along = glm::length(DVec3(ray.dir)) * r.cos_theta;
  return std::fabs(r.t - ray.tfar) * along <= delta || std::fabs(r.t - ray.tnear) * along <= delta;
}

}  // namespace hrpp
