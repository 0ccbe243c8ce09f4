// Binned SAH BVH builder (Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies",
// 2007) with depth-first node numbering, what every builder's BVH gets on top (finish_bvh), and
// the invariant checker used by the tests.
#include "hrpp/trace/bvh.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "hrpp/trace/bvh_micro21.h"

namespace hrpp {
namespace {

/// SAH bin of a centroid offset `d` from the centroid box's lower corner, for `scale` = bins per
/// unit. Clamped before the conversion to an integer: with a tiny extent (denormal centroids)
/// scale is +inf, d * scale inf or NaN (0 * inf), and converting those is undefined behaviour
/// (found by fuzz_traverse: fuzz/regressions/traverse/). NaN goes to bin 0.
uint32_t bin_of(float d, float scale, uint32_t nbins) {
  const float f = d * scale;
  return f >= float(nbins - 1) ? nbins - 1 : f > 0 ? static_cast<uint32_t>(f) : 0;
}

struct PrimRef {
  Aabb box;
  Vec3 centroid;
  uint32_t id;
};

struct Task {
  uint32_t begin, end;
  uint32_t parent;
  bool is_right;
  uint16_t depth;
};

struct Bin {
  Aabb box;
  uint32_t count = 0;
};

}  // namespace

std::string_view bvh_builder_name(BvhBuilder b) {
  return b == BvhBuilder::kMicro21Sbvh ? "micro21-sbvh" : "sah";
}

bool parse_bvh_builder(std::string_view name, BvhBuilder* out) {
  for (BvhBuilder b : {BvhBuilder::kSah, BvhBuilder::kMicro21Sbvh})
    if (name == bvh_builder_name(b)) {
      *out = b;
      return true;
    }
  return false;
}

size_t Bvh::memory_bytes() const {
  return nodes.size() * sizeof(BvhNode) + tris.size() * sizeof(Triangle) + prim_ids.size() * 4 +
         tri_degenerate.size() + parent.size() * 4 + depth.size() * 2 +
         pairs.size() * sizeof(BvhPair) + pair_of.size() * 4;
}

void build_pairs(Bvh& bvh) {
  const size_t nn = bvh.nodes.size();
  bvh.pairs.clear();
  bvh.pair_of.assign(nn, kNoNode);
  uint32_t count = 0;
  for (size_t i = 0; i < nn; ++i) {
    const BvhNode& n = bvh.nodes[i];
    if (n.is_leaf()) {
      if (n.count > 0xFFFFu) {  // does not fit the 16-bit count: no traversal layout
        bvh.pair_of.clear();
        return;
      }
    } else {
      bvh.pair_of[i] = count++;
    }
  }
  bvh.pairs.resize(count);
  for (size_t i = 0; i < nn; ++i) {
    const BvhNode& n = bvh.nodes[i];
    if (n.is_leaf()) continue;
    BvhPair& p = bvh.pairs[bvh.pair_of[i]];
    const uint32_t child[2] = {static_cast<uint32_t>(i + 1), n.right_or_first};
    p.right = n.right_or_first;
    p.leaf_counts = 0;
    for (int c = 0; c < 2; ++c) {
      const BvhNode& ch = bvh.nodes[child[c]];
      for (int a = 0; a < 3; ++a) {
        p.box[a][c] = ch.lo[a];
        p.box[a][2 + c] = ch.hi[a];
      }
      p.data[c] = ch.is_leaf() ? ch.right_or_first : bvh.pair_of[child[c]];
      p.leaf_counts |= ch.count << (16 * c);
    }
  }
}

Bvh build_bvh(const std::vector<Triangle>& triangles, const BvhBuildOptions& opt) {
  if (opt.builder == BvhBuilder::kMicro21Sbvh) return build_bvh_micro21(triangles);
  auto t0 = std::chrono::steady_clock::now();
  Bvh bvh;
  bvh.options = opt;
  const uint32_t max_leaf = std::max<uint32_t>(1, opt.max_leaf_size);
  const uint32_t nbins = std::clamp<uint32_t>(opt.bins, 2, 256);
  const size_t n = triangles.size();
  if (n == 0) throw std::invalid_argument("build_bvh: no triangles");

  std::vector<PrimRef> refs(n);
  for (size_t i = 0; i < n; ++i) {
    refs[i].box = triangles[i].bounds();
    refs[i].centroid = refs[i].box.center();
    refs[i].id = static_cast<uint32_t>(i);
  }
  bvh.nodes.reserve(n ? 2 * n / std::min<size_t>(max_leaf, 2) : 1);

  std::vector<Task> stack;
  stack.push_back({0, static_cast<uint32_t>(n), kNoNode, false, 0});
  std::vector<Bin> bins(nbins);
  std::vector<float> right_area(nbins);
  std::vector<uint32_t> right_count(nbins);

  while (!stack.empty()) {
    Task task = stack.back();
    stack.pop_back();
    const uint32_t idx = bvh.add_node(task.parent, task.depth, task.is_right);

    Aabb box, cbox;
    for (uint32_t i = task.begin; i < task.end; ++i) {
      box.grow(refs[i].box);
      cbox.grow(refs[i].centroid);
    }
    const uint32_t count = task.end - task.begin;
    BvhNode& node = bvh.nodes[idx];
    node.lo = box.empty() ? Vec3(0) : box.lo;
    node.hi = box.empty() ? Vec3(0) : box.hi;

    // Best binned SAH split over the three axes.
    int best_axis = -1;
    uint32_t best_bin = 0;
    float best_cost = kInf;
    const Vec3 cext = cbox.extent();
    for (int axis = 0; axis < 3 && count > 1; ++axis) {
      if (!(cext[axis] > 0)) continue;
      for (auto& b : bins) b = Bin{};
      const float scale = nbins * (1 - 1e-6f) / cext[axis];
      for (uint32_t i = task.begin; i < task.end; ++i) {
        const uint32_t b = bin_of(refs[i].centroid[axis] - cbox.lo[axis], scale, nbins);
        bins[b].box.grow(refs[i].box);
        bins[b].count++;
      }
      Aabb acc;
      uint32_t cnt = 0;
      for (uint32_t b = nbins - 1; b > 0; --b) {
        acc.grow(bins[b].box);
        cnt += bins[b].count;
        right_area[b] = acc.half_area();
        right_count[b] = cnt;
      }
      acc = Aabb{};
      cnt = 0;
      for (uint32_t b = 0; b + 1 < nbins; ++b) {
        acc.grow(bins[b].box);
        cnt += bins[b].count;
        if (cnt == 0 || right_count[b + 1] == 0) continue;
        float cost = acc.half_area() * cnt + right_area[b + 1] * right_count[b + 1];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_bin = b;
        }
      }
    }
    const float box_area = box.half_area();
    const float split_cost = box_area > 0 ? opt.traversal_cost + best_cost / box_area : kInf;
    const bool make_leaf =
        count <= 1 || (count <= max_leaf && (best_axis < 0 || split_cost >= float(count)));
    if (make_leaf) {
      node.right_or_first = task.begin;
      node.count = count;
      continue;
    }

    uint32_t mid;
    if (best_axis >= 0) {
      const float scale = nbins * (1 - 1e-6f) / cext[best_axis];
      auto it =
          std::partition(refs.begin() + task.begin, refs.begin() + task.end, [&](const PrimRef& r) {
            return bin_of(r.centroid[best_axis] - cbox.lo[best_axis], scale, nbins) <= best_bin;
          });
      mid = static_cast<uint32_t>(it - refs.begin());
    } else {
      // All centroids coincide (or the box is flat): split the range in halves by object.
      const int axis = cbox.largest_axis();
      mid = task.begin + count / 2;
      std::nth_element(refs.begin() + task.begin, refs.begin() + mid, refs.begin() + task.end,
                       [&](const PrimRef& a, const PrimRef& b) {
                         return a.centroid[axis] < b.centroid[axis] ||
                                (a.centroid[axis] == b.centroid[axis] && a.id < b.id);
                       });
    }
    if (mid == task.begin || mid == task.end) mid = task.begin + count / 2;
    node.count = 0;
    const uint16_t d = static_cast<uint16_t>(task.depth + 1);
    stack.push_back({mid, task.end, idx, true, d});
    stack.push_back({task.begin, mid, idx, false, d});
  }

  bvh.tris.resize(n);
  bvh.prim_ids.resize(n);
  for (size_t i = 0; i < n; ++i) {
    bvh.prim_ids[i] = refs[i].id;
    bvh.tris[i] = triangles[refs[i].id];
  }

  finish_bvh(bvh);
  bvh.stats.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return bvh;
}

void finish_bvh(Bvh& bvh) {
  bvh.tri_degenerate.resize(bvh.tris.size());
  for (size_t i = 0; i < bvh.tris.size(); ++i) bvh.tri_degenerate[i] = bvh.tris[i].degenerate();

  build_pairs(bvh);

  // Statistics.
  BvhStats& st = bvh.stats;
  st = BvhStats{};
  st.nodes = static_cast<uint32_t>(bvh.nodes.size());
  st.references = static_cast<uint32_t>(bvh.tris.size());
  st.leaf_size_histogram.assign(std::max<uint32_t>(1, bvh.options.max_leaf_size) + 1, 0);
  const float root_area = bvh.nodes[0].box().half_area();
  double depth_sum = 0;
  for (uint32_t i = 0; i < st.nodes; ++i) {
    const BvhNode& nd = bvh.nodes[i];
    // A node as large as the root counts 1, also when both are infinite (the MICRO 2021 build's
    // leaf root, wrapped under a root of box +-FLT_MAX: hrpp/trace/bvh_micro21.h).
    const float area = nd.box().half_area();
    const double rel = area == root_area ? 1.0 : root_area > 0 ? area / root_area : 1.0;
    st.max_depth = std::max<uint32_t>(st.max_depth, bvh.depth[i]);
    if (nd.is_leaf()) {
      st.leaves++;
      depth_sum += bvh.depth[i];
      if (nd.count >= st.leaf_size_histogram.size()) st.leaf_size_histogram.resize(nd.count + 1);
      st.leaf_size_histogram[nd.count]++;
      st.sah_cost += rel * nd.count;
    } else {
      st.interior++;
      st.sah_cost += rel * bvh.options.traversal_cost;
    }
  }
  st.mean_leaf_depth = st.leaves ? depth_sum / st.leaves : 0;
}

namespace {

// ---- check_bvh's coverage test for spatial splits --------------------------------------------

using Polygon = std::vector<DVec3>;  // convex, in double precision

/// The part of convex polygon p whose points x satisfy in(x[axis]) (a half-space bounded by the
/// plane x[axis] = c). Sutherland-Hodgman, the crossing points in double precision.
template <typename In>
Polygon clip(const Polygon& p, int axis, double c, In in) {
  Polygon out;
  for (size_t i = 0; i < p.size(); ++i) {
    const DVec3 &a = p[i], &b = p[(i + 1) % p.size()];
    if (in(a[axis])) out.push_back(a);
    if (in(a[axis]) != in(b[axis])) {
      DVec3 x = a + (b - a) * ((c - a[axis]) / (b[axis] - a[axis]));
      x[axis] = c;
      out.push_back(x);
    }
  }
  return out;
}

double polygon_area(const Polygon& p) {
  DVec3 n(0);
  for (size_t i = 1; i + 1 < p.size(); ++i) n += glm::cross(p[i] - p[0], p[i + 1] - p[0]);
  return 0.5 * glm::length(n);
}

/// The area of the part of triangle t outside every box (closed), each box widened by `margin` on
/// every side: a convex polygon minus a box is at most six convex pieces, one beyond each face
/// plane in turn.
double uncovered_area(const Triangle& t, const std::vector<Aabb>& boxes, double margin) {
  std::vector<Polygon> left{{DVec3(t.v0), DVec3(t.v1), DVec3(t.v2)}}, next;
  for (const Aabb& b : boxes) {
    if (b.empty()) continue;
    next.clear();
    for (Polygon p : left)
      for (int a = 0; a < 3 && p.size() >= 3; ++a) {
        const double lo = double(b.lo[a]) - margin, hi = double(b.hi[a]) + margin;
        Polygon below = clip(p, a, lo, [lo](double x) { return x < lo; });
        if (below.size() >= 3) next.push_back(std::move(below));
        p = clip(p, a, lo, [lo](double x) { return x >= lo; });
        Polygon above = clip(p, a, hi, [hi](double x) { return x > hi; });
        if (above.size() >= 3) next.push_back(std::move(above));
        p = clip(p, a, hi, [hi](double x) { return x <= hi; });
      }
    left.swap(next);
    if (left.empty()) return 0;
  }
  double area = 0;
  for (const Polygon& p : left) area += polygon_area(p);
  return area;
}

/// How far a spatial-split leaf box may fall short of the triangle part it bounds, relative to the
/// triangle's largest coordinate: the clipping callback rounds its crossing points (a few ulps,
/// 2^-24 relative each).
constexpr double kCoverMargin = 0x1p-20;

}  // namespace

std::string check_bvh(const Bvh& bvh, size_t num_scene_triangles) {
  std::ostringstream err;
  const bool spatial = bvh.options.builder == BvhBuilder::kMicro21Sbvh;
  const size_t nn = bvh.nodes.size();
  const size_t nt = bvh.tris.size();
  if (nn == 0) return "no nodes";
  if (bvh.parent.size() != nn || bvh.depth.size() != nn) return "parent/depth size mismatch";
  if (bvh.prim_ids.size() != nt || bvh.tri_degenerate.size() != nt)
    return "prim_ids/tri_degenerate size mismatch";
  if (spatial ? nt < num_scene_triangles : nt != num_scene_triangles)
    return "triangle count mismatch";
  if (bvh.parent[0] != kNoNode) return "root has a parent";
  std::vector<uint32_t> covered(nt, 0);
  std::vector<uint32_t> leaf_of(nt, kNoNode);
  std::vector<uint32_t> reached(nn, 0);
  std::vector<uint32_t> stack{0};
  uint32_t leaves = 0, interior = 0;
  while (!stack.empty()) {
    uint32_t i = stack.back();
    stack.pop_back();
    if (reached[i]++) {
      err << "node " << i << " reached twice";
      return err.str();
    }
    const BvhNode& n = bvh.nodes[i];
    if (n.is_leaf()) {
      ++leaves;
      if (size_t(n.right_or_first) + n.count > nt) {
        err << "leaf " << i << " triangle range out of bounds";
        return err.str();
      }
      for (uint32_t k = 0; k < n.count; ++k) {
        uint32_t t = n.right_or_first + k;
        covered[t]++;
        leaf_of[t] = i;
        const Aabb tb = bvh.tris[t].bounds();
        // Spatial splits: the leaf bounds the triangle's part inside it, so its box meets the
        // triangle's (coverage is checked below), unless it is empty (no ray enters it).
        Aabb meet = n.box();
        meet.lo = glm::max(meet.lo, tb.lo);
        meet.hi = glm::min(meet.hi, tb.hi);
        if (spatial ? !n.box().empty() && meet.empty() : !n.box().contains(tb)) {
          err << "leaf " << i << " box does not " << (spatial ? "meet" : "contain") << " triangle "
              << bvh.prim_ids[t];
          return err.str();
        }
      }
      continue;
    }
    ++interior;
    uint32_t l = i + 1, r = n.right_or_first;
    if (l >= nn || r >= nn || r <= l) {
      err << "node " << i << " children (" << l << ", " << r << ") not in depth-first order";
      return err.str();
    }
    for (uint32_t c : {l, r}) {
      if (bvh.parent[c] != i) {
        err << "node " << c << " has parent " << bvh.parent[c] << ", expected " << i;
        return err.str();
      }
      if (bvh.depth[c] != bvh.depth[i] + 1) {
        err << "node " << c << " depth inconsistent";
        return err.str();
      }
      if (!n.box().contains(bvh.nodes[c].box())) {
        err << "child " << c << " box not inside parent " << i;
        return err.str();
      }
    }
    stack.push_back(r);
    stack.push_back(l);
  }
  for (size_t i = 0; i < nn; ++i)
    if (!reached[i]) {
      err << "node " << i << " unreachable";
      return err.str();
    }
  // Every slot in one leaf; every scene triangle referenced: once (our SAH build), or at least
  // once, each reference an identical copy (spatial splits).
  std::vector<uint32_t> refs(num_scene_triangles, 0);
  std::vector<uint32_t> first_slot(num_scene_triangles, kNoNode);
  for (size_t t = 0; t < nt; ++t) {
    if (covered[t] != 1) {
      err << "triangle slot " << t << " is in " << covered[t] << " leaves";
      return err.str();
    }
    const uint32_t p = bvh.prim_ids[t];
    if (p >= num_scene_triangles) {
      err << "slot " << t << " names triangle " << p << " of " << num_scene_triangles;
      return err.str();
    }
    if (!spatial && refs[p]) {
      err << "prim_ids is not a permutation (slot " << t << ")";
      return err.str();
    }
    if (refs[p]++ == 0) {
      first_slot[p] = uint32_t(t);
    } else if (std::memcmp(&bvh.tris[t], &bvh.tris[first_slot[p]], sizeof(Triangle)) != 0) {
      err << "triangle " << p << ": slots " << first_slot[p] << " and " << t << " differ";
      return err.str();
    }
    if (bvh.tri_degenerate[t] != bvh.tris[t].degenerate()) {
      err << "tri_degenerate wrong in slot " << t;
      return err.str();
    }
  }
  for (size_t p = 0; p < num_scene_triangles; ++p)
    if (!refs[p]) {
      err << "triangle " << p << " is in no leaf";
      return err.str();
    }
  if (spatial) {
    // The leaf boxes of a triangle's references cover it: no ray can pass through the triangle
    // without entering one of them. The slots by triangle (counting sort), then each triangle.
    std::vector<uint32_t> start(num_scene_triangles + 1, 0), slots(nt);
    for (size_t p = 0; p < num_scene_triangles; ++p) start[p + 1] = start[p] + refs[p];
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t t = 0; t < nt; ++t) slots[fill[bvh.prim_ids[t]]++] = uint32_t(t);
    std::vector<Aabb> boxes;
    for (size_t p = 0; p < num_scene_triangles; ++p) {
      const Triangle& tri = bvh.tris[first_slot[p]];
      if (bvh.tri_degenerate[first_slot[p]]) continue;  // never hit
      boxes.clear();
      for (uint32_t k = start[p]; k < start[p + 1]; ++k)
        boxes.push_back(bvh.nodes[leaf_of[slots[k]]].box());
      const double m = kCoverMargin * std::max({max_abs(tri.v0), max_abs(tri.v1), max_abs(tri.v2)});
      const double a = uncovered_area(tri, boxes, m);
      if (a > 0x1p-30 * polygon_area({DVec3(tri.v0), DVec3(tri.v1), DVec3(tri.v2)})) {
        err << "triangle " << p << ": the boxes of its " << boxes.size() << " leaves leave area "
            << a << " of it uncovered";
        return err.str();
      }
    }
  }
  if (leaves != bvh.stats.leaves || interior != bvh.stats.interior || nn != bvh.stats.nodes ||
      nt != bvh.stats.references)
    return "node counts in stats inconsistent";
  if (interior + 1 != leaves) return "binary tree must have leaves = interior + 1";
  return {};
}

}  // namespace hrpp
