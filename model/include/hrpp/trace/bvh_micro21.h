// MICRO 2021's BVH (docs/bvh.md, "Builders"): the BVH that the public simulator of "Intersection
// Prediction for Accelerated GPU Ray Tracing" (MICRO 2021) traces, rebuilt here with the same
// Embree builder call, settings and callbacks, then laid out as its converter lays it out. Their
// code: GitHub ubc-aamodt-group/ray-intersection-predictor at commit 29eeb01, rtao-benchmark/src
// (the file:line references below are of that version):
//   - BVHManager.cpp 30-31: the simulator's BVH is BuildBVH2Triangle's (the SBVH; the object-split
//     build beside it is disabled by `#if 0`);
//   - EmbreeBVHBuilder.cpp 303-361, BuildBVH2Triangle: rtcBuildBVH with rtcDefaultBuildArguments()
//     (336) but buildQuality RTC_BUILD_QUALITY_HIGH (337), primitiveArrayCapacity twice the
//     triangle count (340) and splitPrimitive = SplitPrimitiveTriangle (348), which clips the
//     triangle against the split plane (SplitTriangle, 110-210). With a split callback and spare
//     capacity, Embree 3's RTC_BUILD_QUALITY_HIGH is its spatial-split SAH builder
//     (kernels/common/rtcore_builder.cpp, rtcBuildBVH). The defaults (rtcore_builder.h,
//     rtcDefaultBuildArguments): maxBranchingFactor 2, maxDepth 32, sahBlockSize 1, minLeafSize 1,
//     maxLeafSize RTC_BUILD_MAX_PRIMITIVES_PER_LEAF (32), traversalCost 1, intersectionCost 1.
//     Embree orders a node's children by primitive count, the larger first
//     (kernels/builders/bvh_builder_sah.h, GeneralBVHBuilder::BuilderT::recurse).
//   - GPUBVHConverter.cpp 23-142, ConvertToGPUBVH2: binary nodes depth-first from a stack onto
//     which child 0 is pushed first and child 1 second (93-101), so child 1's subtree directly
//     follows its parent; a leaf's triangles are copied into the leaf in the order Embree gave
//     them (124-133); a root that is a leaf is wrapped (36-53) under a new root whose child 0 is
//     that leaf with box [-FLT_MAX, FLT_MAX] and whose child 1 is a new leaf holding the leaf's
//     first triangle with the empty box [FLT_MAX, -FLT_MAX].
// Here: our left child (this node + 1) is their child 1, our right child their child 0; node
// boxes are the child boxes Embree gave (setNodeBounds), the root's the union of its children's.
//
// Deterministic: Embree's build runs on TBB, whose parallel loops and reductions depend on the
// thread schedule (the spatial splits' fragments are numbered by an atomic counter in whatever
// order threads reach them; Embree marks its total-area sum "not deterministic"), so the build
// runs in a TBB task arena of one thread: always the same BVH, that of a single-threaded build.
// Their build ran with every thread of the machine (rtcNewDevice(nullptr)).
#pragma once

#include <cstdint>
#include <vector>

#include "hrpp/trace/bvh.h"

namespace hrpp {

/// Embree's default maxLeafSize (RTC_BUILD_MAX_PRIMITIVES_PER_LEAF), which they keep: no leaf
/// holds more triangle references. Recorded as Bvh::options.max_leaf_size.
inline constexpr uint32_t kMicro21MaxLeafSize = 32;
/// The object-split bins per axis of Embree's spatial-split builder (NUM_OBJECT_BINS in
/// kernels/builders/bvh_builder_sah.h; its spatial splits use 16). Recorded as
/// Bvh::options.bins.
inline constexpr uint32_t kMicro21ObjectBins = 32;

/// Builds MICRO 2021's BVH over the triangles (see above). build_bvh calls it for
/// BvhBuilder::kMicro21Sbvh. Throws std::runtime_error when Embree reports an error.
Bvh build_bvh_micro21(const std::vector<Triangle>& triangles);

/// Their split callback (EmbreeBVHBuilder.cpp 110-247, SplitTriangle and SplitPrimitiveTriangle):
/// the bounds of the parts of `box` (a reference's current bounds) on each side of the plane
/// x[dim] = pos, as the bounds of triangle tri's vertices and edge crossings on that side
/// intersected with `box`. Every float operation in their order.
void micro21_split_triangle(const Triangle& tri, const Aabb& box, int dim, float pos, Aabb* left,
                            Aabb* right);

}  // namespace hrpp
