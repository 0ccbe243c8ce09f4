#include "hrpp/trace/traverse.h"

#include <emmintrin.h>

#include <array>
#include <cstddef>
#include <limits>
#include <stdexcept>

namespace hrpp {

bool intersect_box(const RayPre& r, const Vec3& lo, const Vec3& hi, float tmin, float limit,
                   float* entry) {
  constexpr float kWiden = 1 + 2 * gamma(3);
  float tmax = limit * kCullWiden;
  for (int a = 0; a < 3; ++a) {
    float t0 = (lo[a] - r.org[a]) * r.inv[a];
    float t1 = (hi[a] - r.org[a]) * r.inv[a];
    if (r.inv[a] < 0) std::swap(t0, t1);
    t1 *= kWiden;
    // Written so that a NaN (0 * inf) leaves the interval unchanged.
    tmin = t0 > tmin ? t0 : tmin;
    tmax = t1 < tmax ? t1 : tmax;
  }
  *entry = tmin;
  return tmin <= tmax;
}

namespace {
// The bound a box's entry distance is culled against: the current limit (the closest hit's t, or
// the next float above tfar) widened by kCullWiden (docs/bvh.md, "Culling against the current
// hit"), so that rounding in the box's entry distance and in a triangle's t cannot cull a box
// holding a triangle that the triangle test accepts below the limit. +inf stays +inf.
// intersect_box(..., limit, ...) is BoxRay::hit(..., cull_bound(limit), ...).
[[gnu::always_inline]] inline float cull_bound(float limit) { return limit * kCullWiden; }

// The body of intersect_triangle, inlined into the traversal loop.
[[gnu::always_inline]] inline bool triangle_test(const RayPre& r, const Triangle& tri, float tmin,
                                                 float tlimit, float* t, float* u, float* v) {
  const Vec3 A = tri.v0 - r.org, B = tri.v1 - r.org, C = tri.v2 - r.org;
  const float ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
  const float bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
  const float cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
  float U = cx * by - cy * bx;
  float V = ax * cy - ay * cx;
  float W = bx * ay - by * ax;
  if (U == 0.f || V == 0.f || W == 0.f) {  // edge case: recompute exactly in double
    U = static_cast<float>(double(cx) * by - double(cy) * bx);
    V = static_cast<float>(double(ax) * cy - double(ay) * cx);
    W = static_cast<float>(double(bx) * ay - double(by) * ax);
  }
  if ((U < 0 || V < 0 || W < 0) && (U > 0 || V > 0 || W > 0)) return false;
  const float det = U + V + W;
  if (det == 0.f) return false;
  const float az = r.sz * A[r.kz], bz = r.sz * B[r.kz], cz = r.sz * C[r.kz];
  const float T = U * az + V * bz + W * cz;
  const float rcp = 1.f / det;
  const float tt = T * rcp;
  if (!(tt >= tmin && tt < tlimit) || !std::isfinite(tt)) return false;
  *t = tt;
  *u = V * rcp;
  *v = W * rcp;
  return true;
}
}  // namespace

bool intersect_triangle(const RayPre& r, const Triangle& tri, float tmin, float tlimit, float* t,
                        float* u, float* v) {
  return triangle_test(r, tri, tmin, tlimit, t, u, v);
}

namespace {

constexpr int kStackSize = 1024;

// The triangles first .. first + count - 1 of leaf `node`, for both walks: every test counted, a
// hit nearer than `limit` kept (and `limit` shrunk to it). True when an any-hit walk may stop.
template <bool kAnyHit>
[[gnu::always_inline]] inline bool test_leaf(const Bvh& bvh, const RayPre& r, float tnear,
                                             uint32_t node, uint32_t first, uint32_t count,
                                             float& limit, float& cull, Hit& hit, Counters* c) {
  c->leaf_visits++;
  for (uint32_t i = first, e = first + count; i < e; ++i) {
    c->tri_tests++;
    if (bvh.tri_degenerate[i]) continue;
    float t, u, v;
    if (triangle_test(r, bvh.tris[i], tnear, limit, &t, &u, &v)) {
      hit.t = limit = t;
      cull = cull_bound(limit);
      hit.u = u;
      hit.v = v;
      hit.prim = bvh.prim_ids[i];
      hit.leaf = node;
      if constexpr (kAnyHit) return true;
    }
  }
  return false;
}

// intersect_box for the traversal loop, on the three axes at once (SSE2, the x86-64 baseline).
// The per-axis near/far choice is made once per ray (near plane = hi when inv < 0, else lo), and
// every lane does the same operations on the same operands as intersect_box: maxps(t0, tmin) is
// exactly `t0 > tmin ? t0 : tmin` (a NaN t0 leaves tmin) and minps(t1, tmax) is `t1 < tmax ? t1 :
// tmax`. The fourth lane (the node's right_or_first / count bits, cleared to +0) meets a NaN
// inverse direction, so it is ignored the same way. Once tmin and tmax are folded into every lane
// no lane is NaN and the order of the remaining max/min does not matter (up to the sign of a zero
// entry distance, which compares equal). Hits, entry comparisons and counters are those of
// intersect_box.
struct BoxRay {
  __m128 org, inv, neg;
  explicit BoxRay(const RayPre& r)
      : org(_mm_setr_ps(r.org.x, r.org.y, r.org.z, 0.f)),
        inv(_mm_setr_ps(r.inv.x, r.inv.y, r.inv.z, std::numeric_limits<float>::quiet_NaN())),
        neg(_mm_cmplt_ps(inv, _mm_setzero_ps())) {}
  bool hit(const BvhNode& n, float tmin, float tmax, float* entry) const {
    static_assert(offsetof(BvhNode, lo) == 0 && offsetof(BvhNode, hi) == 16);
    constexpr float kWiden = 1 + 2 * gamma(3);
    // The fourth lane holds right_or_first / count: integers that read as denormal floats, and
    // arithmetic on denormal operands is slow (microcode assists). Cleared to +0.
    const __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
    const __m128 lo = _mm_and_ps(_mm_loadu_ps(&n.lo.x), xyz);
    const __m128 hi = _mm_and_ps(_mm_loadu_ps(&n.hi.x), xyz);
    const __m128 near = _mm_or_ps(_mm_and_ps(neg, hi), _mm_andnot_ps(neg, lo));
    const __m128 far = _mm_or_ps(_mm_and_ps(neg, lo), _mm_andnot_ps(neg, hi));
    const __m128 t0 = _mm_mul_ps(_mm_sub_ps(near, org), inv);
    const __m128 t1 = _mm_mul_ps(_mm_mul_ps(_mm_sub_ps(far, org), inv), _mm_set1_ps(kWiden));
    __m128 a = _mm_max_ps(t0, _mm_set1_ps(tmin));
    __m128 b = _mm_min_ps(t1, _mm_set1_ps(tmax));
    a = _mm_max_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(2, 3, 0, 1)));
    b = _mm_min_ps(b, _mm_shuffle_ps(b, b, _MM_SHUFFLE(2, 3, 0, 1)));
    a = _mm_max_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(1, 0, 3, 2)));
    b = _mm_min_ps(b, _mm_shuffle_ps(b, b, _MM_SHUFFLE(1, 0, 3, 2)));
    *entry = _mm_cvtss_f32(a);
    return _mm_comile_ss(a, b);
  }
};

template <bool kAnyHit, bool kPath>
Hit traverse(const Bvh& bvh, const Ray& ray, Counters* counters, const TraceRequest& req) {
  const RayPre r(ray);
  const BoxRay br(r);
  // Counted locally (in registers) and added to *counters on every return.
  Counters local;
  Counters* c = &local;
  struct Flush {
    Counters* from;
    Counters* to;
    ~Flush() { *to += *from; }
  } flush{&local, counters};
  const BvhNode* nodes = bvh.nodes.data();
  const Triangle* tris = bvh.tris.data();
  Hit hit;
  float limit = next_float_up(ray.tfar);  // accept t <= tfar
  float cull = cull_bound(limit);         // cull a box whose entry is beyond it
  struct Entry {
    uint32_t node;
    float t;
  };
  std::array<Entry, kStackSize> stack;
  int sp = 0;
  uint32_t node = req.start_node;
  float entry;
  c->box_tests++;
  if (!br.hit(nodes[node], ray.tnear, cull, &entry)) return hit;
  while (true) {
    const BvhNode& n = nodes[node];
    if constexpr (kPath) req.path->push_back(node);
    if (n.is_leaf()) {
      if (test_leaf<kAnyHit>(bvh, r, ray.tnear, node, n.right_or_first, n.count, limit, cull, hit,
                             c))
        return hit;
    } else {
      c->interior_tests++;
      c->box_tests += 2;
      const uint32_t l = node + 1, rr = n.right_or_first;
      float tl, tr;
      const BvhNode &nl = nodes[l], &nr = nodes[rr];
      // Whichever child is walked next needs its own right child (its left child is adjacent)
      // or its triangles: start fetching them while the boxes are tested. Prefetches change no
      // result.
      __builtin_prefetch(nl.is_leaf() ? static_cast<const void*>(&tris[nl.right_or_first])
                                      : static_cast<const void*>(&nodes[nl.right_or_first]));
      __builtin_prefetch(nr.is_leaf() ? static_cast<const void*>(&tris[nr.right_or_first])
                                      : static_cast<const void*>(&nodes[nr.right_or_first]));
      const bool hl = br.hit(nl, ray.tnear, cull, &tl);
      const bool hr = br.hit(nr, ray.tnear, cull, &tr);
      if (hl && hr) {
        if (sp >= kStackSize) throw std::runtime_error("traversal stack overflow");
        if (tr < tl) {
          stack[sp++] = {l, tl};
          node = rr;
        } else {
          stack[sp++] = {rr, tr};
          node = l;
        }
        continue;
      }
      if (hl || hr) {
        node = hl ? l : rr;
        continue;
      }
    }
    // Pop the next node whose box entry is not beyond the cull bound (the box test's rule).
    while (sp > 0) {
      const Entry e = stack[--sp];
      if (e.t <= cull) {
        node = e.node;
        goto next;
      }
    }
    return hit;
  next:;
  }
}

// The traversal over bvh.pairs (the same walk as `traverse`, node for node): an interior node's
// two child boxes come from one cache line and are tested together, lane 0 the left child and
// lane 1 the right, with exactly intersect_box's operations in its order (per axis: the near
// plane is hi when the inverse direction is negative, t0 = (near - org) * inv, t1 = (far - org) *
// inv * (1 + 2 gamma(3)), tmin = maxps(t0, tmin) = `t0 > tmin ? t0 : tmin`, tmax = minps(t1,
// tmax) = `t1 < tmax ? t1 : tmax`; hit when tmin <= tmax), so hits, entry distances and
// counters are bit for bit those of intersect_box.
struct PairRay {
  __m128 org[3], inv[3];
  int near_off[3], far_off[3];  // float offsets of the near / far planes in BvhPair::box
  explicit PairRay(const RayPre& r) {
    for (int a = 0; a < 3; ++a) {
      org[a] = _mm_set1_ps(r.org[a]);
      inv[a] = _mm_set1_ps(r.inv[a]);
      const bool neg = r.inv[a] < 0;
      near_off[a] = 4 * a + (neg ? 2 : 0);
      far_off[a] = 4 * a + (neg ? 0 : 2);
    }
  }
  static __m128 load2(const float* p) {  // p[0], p[1] in lanes 0 and 1
    return _mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(p)));
  }
  // Bit c of the result: child c's box is hit; entry[c] its entry distance.
  int hit(const BvhPair& p, __m128 tmin, __m128 tmax, float entry[4]) const {
    constexpr float kWiden = 1 + 2 * gamma(3);
    const float* b = &p.box[0][0];
    for (int a = 0; a < 3; ++a) {
      const __m128 t0 = _mm_mul_ps(_mm_sub_ps(load2(b + near_off[a]), org[a]), inv[a]);
      const __m128 t1 = _mm_mul_ps(_mm_mul_ps(_mm_sub_ps(load2(b + far_off[a]), org[a]), inv[a]),
                                   _mm_set1_ps(kWiden));
      tmin = _mm_max_ps(t0, tmin);
      tmax = _mm_min_ps(t1, tmax);
    }
    _mm_storeu_ps(entry, tmin);
    return _mm_movemask_ps(_mm_cmple_ps(tmin, tmax)) & 3;
  }
};

template <bool kAnyHit, bool kPath>
Hit traverse_pairs(const Bvh& bvh, const Ray& ray, Counters* counters, const TraceRequest& req) {
  const RayPre r(ray);
  Counters local;
  Counters* c = &local;
  struct Flush {
    Counters* from;
    Counters* to;
    ~Flush() { *to += *from; }
  } flush{&local, counters};
  const BvhPair* pairs = bvh.pairs.data();
  const Triangle* tris = bvh.tris.data();
  Hit hit;
  float limit = next_float_up(ray.tfar);  // accept t <= tfar
  float cull = cull_bound(limit);         // cull a box whose entry is beyond it
  // The current node: its id, and its pair (interior, count 0) or first triangle and count (leaf).
  uint32_t node = req.start_node, data, count;
  {
    const BvhNode& s = bvh.nodes[node];
    c->box_tests++;
    float entry;
    if (!BoxRay(r).hit(s, ray.tnear, cull, &entry)) return hit;
    data = s.is_leaf() ? s.right_or_first : bvh.pair_of[node];
    count = s.count;
  }
  const PairRay pr(r);
  const __m128 tnear = _mm_set1_ps(ray.tnear);
  struct Entry {
    uint32_t node, data, count;
    float t;
  };
  std::array<Entry, kStackSize> stack;
  int sp = 0;
  while (true) {
    if constexpr (kPath) req.path->push_back(node);
    if (count) {
      if (test_leaf<kAnyHit>(bvh, r, ray.tnear, node, data, count, limit, cull, hit, c)) return hit;
    } else {
      c->interior_tests++;
      c->box_tests += 2;
      const BvhPair& p = pairs[data];
      const uint32_t cl = p.leaf_counts & 0xFFFFu, cr = p.leaf_counts >> 16;
      // Start fetching both children (their pairs or triangles) while their boxes are tested.
      // Prefetches change no result.
      __builtin_prefetch(cl ? static_cast<const void*>(&tris[p.data[0]]) : &pairs[p.data[0]]);
      __builtin_prefetch(cr ? static_cast<const void*>(&tris[p.data[1]]) : &pairs[p.data[1]]);
      alignas(16) float t[4];
      const int m = pr.hit(p, tnear, _mm_set1_ps(cull), t);
      if (m == 3) {
        if (sp >= kStackSize) throw std::runtime_error("traversal stack overflow");
        if (t[1] < t[0]) {
          stack[sp++] = {node + 1, p.data[0], cl, t[0]};
          node = p.right, data = p.data[1], count = cr;
        } else {
          stack[sp++] = {p.right, p.data[1], cr, t[1]};
          node = node + 1, data = p.data[0], count = cl;
        }
        continue;
      }
      if (m == 1) {
        node = node + 1, data = p.data[0], count = cl;
        continue;
      }
      if (m == 2) {
        node = p.right, data = p.data[1], count = cr;
        continue;
      }
    }
    // Pop the next node whose box entry is not beyond the cull bound (the box test's rule).
    while (sp > 0) {
      const Entry& e = stack[--sp];
      if (e.t <= cull) {
        node = e.node, data = e.data, count = e.count;
        goto next;
      }
    }
    return hit;
  next:;
  }
}

// closest_hit_pair on the pair layout: traverse_pairs<false, false> for the full walk (limit
// lb), with the bounded walk (limit lv) carried along: a stack entry and the current node carry
// whether the bounded walk visits them too. Returns false if lv rose above lb (the subsequence
// argument no longer holds): the caller then runs the bounded walk alone.
bool traverse_pairs_two(const Bvh& bvh, const Ray& ray, float bounded_tfar, Hit& hb, Counters& cb,
                        Hit& hv, Counters& cv) {
  const RayPre r(ray);
  const BvhPair* pairs = bvh.pairs.data();
  const Triangle* tris = bvh.tris.data();
  float lb = next_float_up(ray.tfar), lv = next_float_up(bounded_tfar);
  float cb_cull = cull_bound(lb), cv_cull = cull_bound(lv);  // each walk's cull bound
  uint32_t node = 0, data, count;
  bool v;  // the bounded walk visits the current node
  {
    const BvhNode& s = bvh.nodes[node];
    cb.box_tests++;
    cv.box_tests++;
    float entry;
    // Not hit with cb_cull: then not with cv_cull <= cb_cull either.
    if (!BoxRay(r).hit(s, ray.tnear, cb_cull, &entry)) return true;
    v = BoxRay(r).hit(s, ray.tnear, cv_cull, &entry);
    data = s.is_leaf() ? s.right_or_first : bvh.pair_of[node];
    count = s.count;
  }
  const PairRay pr(r);
  const __m128 tnear = _mm_set1_ps(ray.tnear);
  struct Entry {
    uint32_t node, data, count;
    float t;
    bool v;
  };
  std::array<Entry, kStackSize> stack;
  int sp = 0;
  while (true) {
    if (count) {
      // test_leaf for both walks: the same triangles, each limit on its own.
      cb.leaf_visits++;
      cv.leaf_visits += v;
      for (uint32_t i = data, e = data + count; i < e; ++i) {
        cb.tri_tests++;
        cv.tri_tests += v;
        if (bvh.tri_degenerate[i]) continue;
        float t, u, w;
        // triangle_test depends on its limit only through `t < limit`, and lv <= lb.
        if (triangle_test(r, tris[i], ray.tnear, lb, &t, &u, &w)) {
          hb.t = lb = t;
          cb_cull = cull_bound(lb);
          hb.u = u;
          hb.v = w;
          hb.prim = bvh.prim_ids[i];
          hb.leaf = node;
          if (v && t < lv) {
            hv.t = lv = t;
            cv_cull = cull_bound(lv);
            hv.u = u;
            hv.v = w;
            hv.prim = bvh.prim_ids[i];
            hv.leaf = node;
          }
          if (lb < lv) return false;
        }
      }
    } else {
      cb.interior_tests++;
      cb.box_tests += 2;
      cv.interior_tests += v;
      cv.box_tests += 2 * v;
      const BvhPair& p = pairs[data];
      const uint32_t cl = p.leaf_counts & 0xFFFFu, cr = p.leaf_counts >> 16;
      __builtin_prefetch(cl ? static_cast<const void*>(&tris[p.data[0]]) : &pairs[p.data[0]]);
      __builtin_prefetch(cr ? static_cast<const void*>(&tris[p.data[1]]) : &pairs[p.data[1]]);
      alignas(16) float t[4];
      const int m = pr.hit(p, tnear, _mm_set1_ps(cb_cull), t);
      // The entry distances t[] do not depend on the bound, and pr.hit's test is entry <=
      // min(exit, bound): with cv_cull <= cb_cull (cull_bound is monotonic and lv <= lb) a child
      // passes the bounded walk's test exactly when it passes the full walk's and its entry is
      // within cv_cull.
      const int mv = v ? m & (int(t[0] <= cv_cull) | int(t[1] <= cv_cull) << 1) : 0;
      if (m == 3) {
        if (sp >= kStackSize) throw std::runtime_error("traversal stack overflow");
        if (t[1] < t[0]) {
          stack[sp++] = {node + 1, p.data[0], cl, t[0], (mv & 1) != 0};
          node = p.right, data = p.data[1], count = cr, v = (mv & 2) != 0;
        } else {
          stack[sp++] = {p.right, p.data[1], cr, t[1], (mv & 2) != 0};
          node = node + 1, data = p.data[0], count = cl, v = (mv & 1) != 0;
        }
        continue;
      }
      if (m == 1) {
        node = node + 1, data = p.data[0], count = cl, v = (mv & 1) != 0;
        continue;
      }
      if (m == 2) {
        node = p.right, data = p.data[1], count = cr, v = (mv & 2) != 0;
        continue;
      }
    }
    while (sp > 0) {
      const Entry& e = stack[--sp];
      if (e.t <= cb_cull) {
        node = e.node, data = e.data, count = e.count, v = e.v && e.t <= cv_cull;
        goto next;
      }
    }
    return true;
  next:;
  }
}

}  // namespace

void closest_hit_pair(const Bvh& bvh, const Ray& ray, float bounded_tfar, Hit* base,
                      Counters* base_c, Hit* bounded, Counters* bounded_c) {
  if (!(bounded_tfar <= ray.tfar))
    throw std::invalid_argument("closest_hit_pair: bounded_tfar above the ray's tfar");
  Ray shrunk = ray;
  shrunk.tfar = bounded_tfar;
  if (bvh.pair_of.empty()) {  // the node layout: two walks
    *base = closest_hit(bvh, ray, base_c);
    *bounded = closest_hit(bvh, shrunk, bounded_c);
    return;
  }
  Hit hb, hv;
  Counters cb, cv;
  if (traverse_pairs_two(bvh, ray, bounded_tfar, hb, cb, hv, cv)) {
    *bounded = hv;
    *bounded_c += cv;
  } else {
    *bounded = closest_hit(bvh, shrunk, bounded_c);
    // The full walk: from the start again (cb is of an unfinished walk).
    cb = {};
    hb = closest_hit(bvh, ray, &cb);
  }
  *base = hb;
  *base_c += cb;
}

Hit closest_hit(const Bvh& bvh, const Ray& ray, Counters* c, const TraceRequest& req) {
  if (!bvh.pair_of.empty())
    return req.path ? traverse_pairs<false, true>(bvh, ray, c, req)
                    : traverse_pairs<false, false>(bvh, ray, c, req);
  return req.path ? traverse<false, true>(bvh, ray, c, req)
                  : traverse<false, false>(bvh, ray, c, req);
}

Hit any_hit(const Bvh& bvh, const Ray& ray, Counters* c, const TraceRequest& req) {
  if (!bvh.pair_of.empty())
    return req.path ? traverse_pairs<true, true>(bvh, ray, c, req)
                    : traverse_pairs<true, false>(bvh, ray, c, req);
  return req.path ? traverse<true, true>(bvh, ray, c, req)
                  : traverse<true, false>(bvh, ray, c, req);
}

Hit brute_force_closest(const Bvh& bvh, const Ray& ray) {
  const RayPre r(ray);
  Hit hit;
  float limit = next_float_up(ray.tfar);
  for (uint32_t i = 0; i < bvh.tris.size(); ++i) {
    if (bvh.tri_degenerate[i]) continue;
    float t, u, v;
    if (intersect_triangle(r, bvh.tris[i], ray.tnear, limit, &t, &u, &v)) {
      hit.t = limit = t;
      hit.u = u;
      hit.v = v;
      hit.prim = bvh.prim_ids[i];
    }
  }
  return hit;
}

}  // namespace hrpp
