// Binned SAH BVH builder (Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies",
// 2007) with depth-first node numbering, and the invariant checker used by the tests.
#include "hrpp/trace/bvh.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <sstream>
#include <stdexcept>

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
    const uint32_t idx = static_cast<uint32_t>(bvh.nodes.size());
    bvh.nodes.push_back({});
    bvh.parent.push_back(task.parent);
    bvh.depth.push_back(task.depth);
    if (task.is_right) bvh.nodes[task.parent].right_or_first = idx;

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
  bvh.tri_degenerate.resize(n);
  for (size_t i = 0; i < n; ++i) {
    bvh.prim_ids[i] = refs[i].id;
    bvh.tris[i] = triangles[refs[i].id];
    bvh.tri_degenerate[i] = bvh.tris[i].degenerate();
  }

  build_pairs(bvh);

  // Statistics.
  BvhStats& st = bvh.stats;
  st.nodes = static_cast<uint32_t>(bvh.nodes.size());
  st.leaf_size_histogram.assign(max_leaf + 1, 0);
  const float root_area = bvh.nodes[0].box().half_area();
  double depth_sum = 0;
  for (uint32_t i = 0; i < st.nodes; ++i) {
    const BvhNode& nd = bvh.nodes[i];
    const double rel = root_area > 0 ? nd.box().half_area() / root_area : 1.0;
    st.max_depth = std::max<uint32_t>(st.max_depth, bvh.depth[i]);
    if (nd.is_leaf()) {
      st.leaves++;
      depth_sum += bvh.depth[i];
      if (nd.count >= st.leaf_size_histogram.size()) st.leaf_size_histogram.resize(nd.count + 1);
      st.leaf_size_histogram[nd.count]++;
      st.sah_cost += rel * nd.count;
    } else {
      st.interior++;
      st.sah_cost += rel * opt.traversal_cost;
    }
  }
  st.mean_leaf_depth = st.leaves ? depth_sum / st.leaves : 0;
  st.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return bvh;
}

std::string check_bvh(const Bvh& bvh, size_t num_scene_triangles) {
  std::ostringstream err;
  const size_t nn = bvh.nodes.size();
  if (nn == 0) return "no nodes";
  if (bvh.parent.size() != nn || bvh.depth.size() != nn) return "parent/depth size mismatch";
  if (bvh.tris.size() != num_scene_triangles || bvh.prim_ids.size() != num_scene_triangles)
    return "triangle count mismatch";
  if (bvh.parent[0] != kNoNode) return "root has a parent";
  std::vector<uint32_t> covered(bvh.tris.size(), 0);
  std::vector<uint32_t> seen_prim(num_scene_triangles, 0);
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
      if (size_t(n.right_or_first) + n.count > bvh.tris.size()) {
        err << "leaf " << i << " triangle range out of bounds";
        return err.str();
      }
      for (uint32_t k = 0; k < n.count; ++k) {
        uint32_t t = n.right_or_first + k;
        covered[t]++;
        if (!n.box().contains(bvh.tris[t].bounds())) {
          err << "leaf " << i << " box does not contain triangle " << bvh.prim_ids[t];
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
  for (size_t t = 0; t < covered.size(); ++t) {
    if (covered[t] != 1) {
      err << "triangle slot " << t << " is in " << covered[t] << " leaves";
      return err.str();
    }
    if (bvh.prim_ids[t] >= num_scene_triangles || seen_prim[bvh.prim_ids[t]]++) {
      err << "prim_ids is not a permutation (slot " << t << ")";
      return err.str();
    }
  }
  if (leaves != bvh.stats.leaves || interior != bvh.stats.interior || nn != bvh.stats.nodes)
    return "node counts in stats inconsistent";
  if (interior + 1 != leaves) return "binary tree must have leaves = interior + 1";
  return {};
}

}  // namespace hrpp
