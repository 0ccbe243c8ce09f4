// MICRO 2021's BVH, rebuilt with Embree's builder API (hrpp/trace/bvh_micro21.h; their code cited
// by file:line of GitHub ubc-aamodt-group/ray-intersection-predictor at 29eeb01,
// rtao-benchmark/src). Compiled with -ffp-contract=off (model/sources.cmake): the split callback's
// float operations round one by one, as in their build for the x86-64 baseline, which has no FMA.
#include "hrpp/trace/bvh_micro21.h"

#include <embree3/rtcore.h>
#include <embree3/rtcore_builder.h>
#include <tbb/task_arena.h>

#include <cfloat>
#include <chrono>
#include <cmath>
#include <new>
#include <stdexcept>
#include <string>

namespace hrpp {
namespace {

/// What the callbacks build: EmbreeBVHBuilder.h's BVHNNode<2> (7-40), in the BVH's own memory
/// (rtcThreadLocalAlloc, freed with it).
struct EmbreeNode {
  Aabb box[2];  // the children's boxes (SetNodeBounds)
  EmbreeNode* child[2] = {nullptr, nullptr};
  uint32_t children = 0;            // 0: a leaf
  const uint32_t* prims = nullptr;  // a leaf's triangles, in the order Embree gave them
  uint32_t count = 0;
};

struct BuildContext {
  const std::vector<Triangle>* triangles;
};

// ---- the callbacks: EmbreeBVHBuilder.cpp 13-59 (CreateNode, SetNodeChildren, SetNodeBounds,
// CreateLeaf) and 212-247 (SplitPrimitiveTriangle) ----

void* create_node(RTCThreadLocalAllocator alloc, unsigned int, void*) {
  return new (rtcThreadLocalAlloc(alloc, sizeof(EmbreeNode), alignof(EmbreeNode))) EmbreeNode{};
}

void set_node_children(void* node, void** children, unsigned int count, void*) {
  auto* n = static_cast<EmbreeNode*>(node);
  for (unsigned int i = 0; i < count && i < 2; ++i)
    n->child[i] = static_cast<EmbreeNode*>(children[i]);
  n->children = count;
}

void set_node_bounds(void* node, const RTCBounds** bounds, unsigned int count, void*) {
  auto* n = static_cast<EmbreeNode*>(node);
  for (unsigned int i = 0; i < count && i < 2; ++i) {
    const RTCBounds& b = *bounds[i];
    n->box[i] = {Vec3(b.lower_x, b.lower_y, b.lower_z), Vec3(b.upper_x, b.upper_y, b.upper_z)};
  }
}

void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count,
                  void*) {
  auto* n = new (rtcThreadLocalAlloc(alloc, sizeof(EmbreeNode), alignof(EmbreeNode))) EmbreeNode{};
  auto* ids = static_cast<uint32_t*>(rtcThreadLocalAlloc(alloc, count * sizeof(uint32_t), 4));
  for (size_t i = 0; i < count; ++i) ids[i] = prims[i].primID;
  n->prims = ids;
  n->count = static_cast<uint32_t>(count);
  return n;
}

void split_primitive(const RTCBuildPrimitive* prim, unsigned int dim, float pos,
                     RTCBounds* left_out, RTCBounds* right_out, void* user) {
  const auto& tris = *static_cast<const BuildContext*>(user)->triangles;
  const Aabb box{Vec3(prim->lower_x, prim->lower_y, prim->lower_z),
                 Vec3(prim->upper_x, prim->upper_y, prim->upper_z)};
  Aabb l, r;
  micro21_split_triangle(tris[prim->primID], box, int(dim), pos, &l, &r);
  auto put = [](const Aabb& b, RTCBounds* o) {
    o->lower_x = b.lo.x;
    o->lower_y = b.lo.y;
    o->lower_z = b.lo.z;
    o->upper_x = b.hi.x;
    o->upper_y = b.hi.y;
    o->upper_z = b.hi.z;
  };
  put(l, left_out);
  put(r, right_out);
}

void on_error(void* user, RTCError code, const char* str) {
  *static_cast<std::string*>(user) =
      "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (str ? str : "");
}

// helper_math.h's float3 operations as SplitTriangle uses them: fminf / fmaxf per component,
// lerp(a, b, t) = a + t * (b - a) (1165-1168), clamp(f, a, b) = fmaxf(a, fminf(f, b)) (1179-1182).
Vec3 fmin3(const Vec3& a, const Vec3& b) {
  return {std::fmin(a.x, b.x), std::fmin(a.y, b.y), std::fmin(a.z, b.z)};
}
Vec3 fmax3(const Vec3& a, const Vec3& b) {
  return {std::fmax(a.x, b.x), std::fmax(a.y, b.y), std::fmax(a.z, b.z)};
}
Vec3 lerp3(const Vec3& a, const Vec3& b, float t) {
  const Vec3 d = b - a;
  return a + Vec3(t * d.x, t * d.y, t * d.z);
}

}  // namespace

void micro21_split_triangle(const Triangle& tri, const Aabb& box, int dim, float pos, Aabb* left,
                            Aabb* right) {
  // SplitTriangle (EmbreeBVHBuilder.cpp 110-210): IndexBuffer[i].x, .y, .z are the triangle's
  // vertices 0, 1, 2 (RayGenerator.cpp 79-86); its edges in their order: (2, 0), (0, 1), (1, 2).
  Aabb nl{Vec3(FLT_MAX), Vec3(-FLT_MAX)}, nr{Vec3(FLT_MAX), Vec3(-FLT_MAX)};
  const Vec3* edges[3][2] = {{&tri.v2, &tri.v0}, {&tri.v0, &tri.v1}, {&tri.v1, &tri.v2}};
  for (const auto& e : edges) {
    const Vec3 &v0 = *e[0], &v1 = *e[1];
    const float p0 = v0[dim], p1 = v1[dim];
    if (p0 <= pos) {
      nl.lo = fmin3(nl.lo, v0);
      nl.hi = fmax3(nl.hi, v0);
    }
    if (p0 >= pos) {
      nr.lo = fmin3(nr.lo, v0);
      nr.hi = fmax3(nr.hi, v0);
    }
    if ((p0 < pos && p1 > pos) || (p0 > pos && p1 < pos)) {
      const Vec3 t = lerp3(v0, v1, std::fmax(0.f, std::fmin((pos - p0) / (p1 - p0), 1.f)));
      nl.lo = fmin3(nl.lo, t);
      nl.hi = fmax3(nl.hi, t);
      nr.lo = fmin3(nr.lo, t);
      nr.hi = fmax3(nr.hi, t);
    }
  }
  // 206-209: intersected with the reference's bounds (SplitPrimitiveTriangle 214-228 passes them).
  left->lo = fmax3(box.lo, nl.lo);
  left->hi = fmin3(box.hi, nl.hi);
  right->lo = fmax3(box.lo, nr.lo);
  right->hi = fmin3(box.hi, nr.hi);
}

Bvh build_bvh_micro21(const std::vector<Triangle>& triangles) {
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = triangles.size();
  if (n == 0) throw std::invalid_argument("build_bvh: no triangles");
  if (n > 0xFFFFFFFFu / 2) throw std::invalid_argument("build_bvh: too many triangles for Embree");

  // The build primitives (EmbreeBVHBuilder.cpp 303-331): the triangles' bounds, geomID 0, primID
  // the triangle's index, in an array of twice the triangle count (the spatial splits' room).
  std::vector<RTCBuildPrimitive> prims(2 * n);
  for (size_t i = 0; i < n; ++i) {
    const Triangle& t = triangles[i];
    RTCBuildPrimitive& p = prims[i];
    p.lower_x = std::fmin(std::fmin(t.v0.x, t.v1.x), t.v2.x);
    p.lower_y = std::fmin(std::fmin(t.v0.y, t.v1.y), t.v2.y);
    p.lower_z = std::fmin(std::fmin(t.v0.z, t.v1.z), t.v2.z);
    p.upper_x = std::fmax(std::fmax(t.v0.x, t.v1.x), t.v2.x);
    p.upper_y = std::fmax(std::fmax(t.v0.y, t.v1.y), t.v2.y);
    p.upper_z = std::fmax(std::fmax(t.v0.z, t.v1.z), t.v2.z);
    p.geomID = 0;
    p.primID = static_cast<unsigned int>(i);
  }

  // 333-350: the device and the build.
  struct Handles {
    RTCDevice device = nullptr;
    RTCBVH bvh = nullptr;
    ~Handles() {
      if (bvh) rtcReleaseBVH(bvh);
      if (device) rtcReleaseDevice(device);
    }
  } h;
  std::string error;
  h.device = rtcNewDevice(nullptr);
  if (!h.device) throw std::runtime_error("build_bvh micro21-sbvh: cannot create an Embree device");
  rtcSetDeviceErrorFunction(h.device, on_error, &error);
  h.bvh = rtcNewBVH(h.device);
  BuildContext ctx{&triangles};
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_HIGH;
  args.bvh = h.bvh;
  args.primitives = prims.data();
  args.primitiveCount = n;
  args.primitiveArrayCapacity = 2 * n;
  args.createNode = create_node;
  args.setNodeChildren = set_node_children;
  args.setNodeBounds = set_node_bounds;
  args.createLeaf = create_leaf;
  args.userPtr = &ctx;
  args.splitPrimitive = split_primitive;
  void* built = nullptr;
  // One thread: the same BVH every time (bvh_micro21.h, "Deterministic").
  tbb::task_arena(1).execute([&] { built = rtcBuildBVH(&args); });
  if (!built)
    throw std::runtime_error("build_bvh micro21-sbvh: " + (error.empty() ? "no BVH" : error));

  // ConvertToGPUBVH2 (GPUBVHConverter.cpp 23-142). A root that is a leaf, wrapped (36-53).
  const EmbreeNode* root = static_cast<const EmbreeNode*>(built);
  EmbreeNode wrapper, single;
  if (root->children == 0) {
    single.prims = root->prims;  // the leaf's first triangle
    single.count = 1;
    wrapper.children = 2;
    wrapper.child[0] = const_cast<EmbreeNode*>(root);
    wrapper.child[1] = &single;
    wrapper.box[0] = {Vec3(-FLT_MAX), Vec3(FLT_MAX)};
    wrapper.box[1] = {Vec3(FLT_MAX), Vec3(-FLT_MAX)};
    root = &wrapper;
  }
  Bvh bvh;
  bvh.options.builder = BvhBuilder::kMicro21Sbvh;
  bvh.options.max_leaf_size = kMicro21MaxLeafSize;
  bvh.options.bins = kMicro21ObjectBins;
  bvh.options.traversal_cost = args.traversalCost;
  bvh.nodes.reserve(2 * n);
  bvh.tris.reserve(2 * n);
  bvh.prim_ids.reserve(2 * n);
  struct Item {
    const EmbreeNode* node;
    Aabb box;
    uint32_t parent;
    uint16_t depth;
    bool is_right;
  };
  Aabb root_box = root->box[0];
  root_box.grow(root->box[1]);
  std::vector<Item> stack{{root, root_box, kNoNode, 0, false}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    const uint32_t idx = bvh.add_node(it.parent, it.depth, it.is_right);
    BvhNode& node = bvh.nodes[idx];
    node.lo = it.box.lo;
    node.hi = it.box.hi;
    const EmbreeNode& e = *it.node;
    if (e.children == 0) {  // a leaf: its triangles, copied in Embree's order (124-133)
      if (e.count == 0) throw std::runtime_error("build_bvh micro21-sbvh: an empty leaf");
      node.right_or_first = static_cast<uint32_t>(bvh.tris.size());
      node.count = e.count;
      for (uint32_t k = 0; k < e.count; ++k) {
        if (e.prims[k] >= n) throw std::runtime_error("build_bvh micro21-sbvh: bad primitive id");
        bvh.prim_ids.push_back(e.prims[k]);
        bvh.tris.push_back(triangles[e.prims[k]]);
      }
      continue;
    }
    if (e.children != 2 || !e.child[0] || !e.child[1])
      throw std::runtime_error("build_bvh micro21-sbvh: a node without two children");
    node.count = 0;
    // Child 0 pushed first, child 1 second (93-101): child 1 comes next, as our left child.
    const uint16_t d = static_cast<uint16_t>(it.depth + 1);
    stack.push_back({e.child[0], e.box[0], idx, d, true});
    stack.push_back({e.child[1], e.box[1], idx, d, false});
  }
  finish_bvh(bvh);
  bvh.stats.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return bvh;
}

}  // namespace hrpp
