// Our binary BVH (docs/bvh.md): built by our binned SAH builder or, as an option, as MICRO 2021's
// simulator builds it (Embree's spatial-split SAH builder, hrpp/trace/bvh_micro21.h); nodes in
// depth-first order either way.
//
// Node layout (32 bytes): the box, then `right_or_first` and `count`.
//   interior (count == 0): left child = this index + 1 (depth-first order),
//                          right child = right_or_first;
//   leaf     (count >= 1): triangles right_or_first .. right_or_first + count - 1 of Bvh::tris.
// Bvh::tris holds triangle references: with our SAH build each scene triangle exactly once; with
// spatial splits (kMicro21Sbvh) a triangle may be referenced by several leaves, each reference a
// full copy of the triangle (with its scene index in prim_ids) in a leaf whose box bounds only the
// part of the triangle inside it.
// Node 0 is the root. parent[] and depth[] sit beside the nodes (the predictor's go-up-level
// walks parent[]); they are not part of the node a traversal unit fetches.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
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

/// Which builder build_bvh runs (docs/bvh.md, "Builders").
enum class BvhBuilder : uint8_t {
  kSah,          // ours: binned SAH, every triangle in exactly one leaf ("sah")
  kMicro21Sbvh,  // MICRO 2021's simulator's: Embree's spatial-split SAH ("micro21-sbvh")
};

/// "sah", "micro21-sbvh" (the names of `--bvh`).
std::string_view bvh_builder_name(BvhBuilder b);
/// The builder of that name; false when there is none.
bool parse_bvh_builder(std::string_view name, BvhBuilder* out);

struct BvhBuildOptions {
  BvhBuilder builder = BvhBuilder::kSah;
  // The SAH build's parameters. kMicro21Sbvh has its own, fixed (hrpp/trace/bvh_micro21.h), and
  // records them here in Bvh::options.
  uint32_t max_leaf_size = 4;  // leaves never hold more triangles than this
  uint32_t bins = 16;          // SAH bins per axis
  float traversal_cost = 1.f;  // SAH cost of an interior node relative to one triangle test
};

struct BvhStats {
  uint32_t nodes = 0, interior = 0, leaves = 0;
  uint32_t references = 0;  // triangle references in the leaves (Bvh::tris.size()): the scene's
                            // triangles, or more with spatial splits
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
  /// A builder's step, in depth-first order: appends an empty node with its parent and depth;
  /// a right child is linked from its parent (right_or_first). Returns its index.
  uint32_t add_node(uint32_t parent_node, uint16_t node_depth, bool is_right) {
    const uint32_t idx = static_cast<uint32_t>(nodes.size());
    nodes.push_back({});
    parent.push_back(parent_node);
    depth.push_back(node_depth);
    if (is_right) nodes[parent_node].right_or_first = idx;
    return idx;
  }
};

/// Builds the BVH over the triangles with opt.builder: our binned SAH (Wald 2007), or MICRO 2021's
/// (build_bvh_micro21). Deterministic.
Bvh build_bvh(const std::vector<Triangle>& triangles, const BvhBuildOptions& opt = {});

/// Completes a BVH whose builder filled nodes, tris, prim_ids, parent, depth and options: fills
/// tri_degenerate, the traversal layout (build_pairs) and the statistics (but build_seconds).
void finish_bvh(Bvh& bvh);

/// Fills bvh.pairs and bvh.pair_of from bvh.nodes (build_bvh calls it; call it again after
/// editing bvh.nodes). Leaves them empty when a
/// leaf holds more than 65535 triangles; the traversal then reads bvh.nodes instead (same results).
void build_pairs(Bvh& bvh);

/// Checks the invariants (docs/bvh.md: every triangle referenced, child boxes inside parent boxes,
/// depth-first numbering, parent links, counts). Our SAH build: every triangle in exactly one leaf
/// whose box contains it. A spatial-split build (kMicro21Sbvh) may reference a triangle from
/// several leaves: each reference is an identical copy, each leaf box meets the triangle's box (or
/// is empty: no ray enters it), and the leaf boxes of its references cover the triangle (to
/// within 2^-20 of the largest coordinate; degenerate triangles, never hit, are exempt). Returns an
/// empty string when all hold, else a description of the first violation.
std::string check_bvh(const Bvh& bvh, size_t num_scene_triangles);

}  // namespace hrpp
