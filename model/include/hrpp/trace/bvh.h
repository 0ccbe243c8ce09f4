// Our own binary BVH (docs/bvh.md): binned SAH build, nodes in depth-first order.
//
// Node layout (32 bytes): the box, then `right_or_first` and `count`.
//   interior (count == 0): left child = this index + 1 (depth-first order),
//                          right child = right_or_first;
//   leaf     (count >= 1): triangles right_or_first .. right_or_first + count - 1 of Bvh::tris.
// Node 0 is the root. parent[] and depth[] sit beside the nodes (the predictor's go-up-level
// walks parent[]); they are not part of the node a traversal unit fetches.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hrpp/scene/geometry.h"

namespace hrpp {

struct BvhNode {
  Vec3 lo;
  uint32_t right_or_first;
  Vec3 hi;
  uint32_t count;

  bool is_leaf() const { return count != 0; }
  Aabb box() const { return {lo, hi}; }
};
static_assert(sizeof(BvhNode) == 32);

constexpr uint32_t kNoNode = 0xFFFFFFFFu;

/// The traversal's copy of an interior node (docs/bvh.md, "Traversal layout"): the boxes of its
/// two children side by side in one cache line, so that one fetch gives both boxes and both are
/// tested at once. Derived from `nodes` by build_bvh (node ids, boxes and counters are those of
/// the binary BVH; this is only where the traversal reads them from).
struct alignas(64) BvhPair {
  float box[3]
           [4];    // axis a: lo of the left child, lo of the right, hi of the left, hi of the right
  uint32_t right;  // the right child's node id (the left child is this node's id + 1)
  uint32_t leaf_counts;  // child c (0 left, 1 right): its triangle count in bits 16c..16c+15; 0:
                         // interior
  uint32_t data[2];  // child c: interior: the index of its own BvhPair; leaf: its first triangle
};
static_assert(sizeof(BvhPair) == 64);

struct BvhBuildOptions {
  uint32_t max_leaf_size = 4;  // leaves never hold more triangles than this
  uint32_t bins = 16;          // SAH bins per axis
  float traversal_cost = 1.f;  // SAH cost of an interior node relative to one triangle test
};

struct BvhStats {
  uint32_t nodes = 0, interior = 0, leaves = 0;
  uint32_t max_depth = 0;
  double mean_leaf_depth = 0;
  std::vector<uint32_t> leaf_size_histogram;  // [k] = leaves holding k triangles
  double sah_cost = 0;  // sum over nodes of area/area(root) * (ct or count), Ci = 1
  double build_seconds = 0;
};

struct Bvh {
  std::vector<BvhNode> nodes;
  std::vector<Triangle> tris;           // triangles in leaf order
  std::vector<uint32_t> prim_ids;       // tris[i] is scene triangle prim_ids[i]
  std::vector<uint8_t> tri_degenerate;  // never hit (zero area)
  std::vector<uint32_t> parent;         // kNoNode for the root
  std::vector<uint16_t> depth;          // root = 0
  std::vector<BvhPair> pairs;     // traversal layout: one per interior node, depth-first order
  std::vector<uint32_t> pair_of;  // node id -> index in pairs (interior nodes; else kNoNode)
  BvhBuildOptions options;
  BvhStats stats;

  /// The ancestor `levels` levels above node (stops at the root).
  uint32_t ancestor(uint32_t node, uint32_t levels) const {
    while (levels-- > 0 && parent[node] != kNoNode) node = parent[node];
    return node;
  }
  size_t memory_bytes() const;
};

/// Builds the BVH over the triangles (binned SAH, Wald 2007). Deterministic.
Bvh build_bvh(const std::vector<Triangle>& triangles, const BvhBuildOptions& opt = {});

/// Fills bvh.pairs and bvh.pair_of from bvh.nodes (build_bvh calls it; call it again after
/// editing bvh.nodes). Leaves them empty when a
/// leaf holds more than 65535 triangles; the traversal then reads bvh.nodes instead (same results).
void build_pairs(Bvh& bvh);

/// Checks the invariants (every triangle in exactly one leaf, child boxes inside parent boxes,
/// depth-first numbering, parent links, counts). Returns an empty string when all hold, else a
/// description of the first violation.
std::string check_bvh(const Bvh& bvh, size_t num_scene_triangles);

}  // namespace hrpp
