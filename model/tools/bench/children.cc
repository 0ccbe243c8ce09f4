// hrpp_bench: the measured child processes (children.h).
#include "children.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>
#include <vector>

#include "hrpp/hardware/rtl_config.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/predictor/tiled_predictor.h"
#include "hrpp/reference/embree_ref.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/trace/traverse.h"
#include "hrpp/workload/ray_stream.h"
#include "hrpp/workload/workload.h"
#include "timing.h"

namespace hrpp::bench {
namespace {

using json = nlohmann::json;

// ---- rays ---------------------------------------------------------------------------------------

// The rays of a stream by kind (primary, shadow, AO; other kinds are not in bench streams), and
// all of them in issue order for the predictor.
struct Rays {
  std::vector<Ray> primary, shadow, ao;
  std::vector<RayRecord> all;
  std::string scene;
  uint32_t width = 0;
};

Rays read_rays(const std::string& path) {
  RayStreamReader rd(path);
  Rays out;
  const json opts = json::parse(rd.header().options);
  out.scene = opts.at("scene").get<std::string>();
  out.width = opts.at("resolution")[0].get<uint32_t>();
  RayRecord r;
  while (rd.next(&r)) {
    if (validate_ray(r.ray) != RayError::kNone) continue;  // never in bench streams (checked)
    out.all.push_back(r);
    if (r.kind == RayKind::kPrimary)
      out.primary.push_back(r.ray);
    else if (r.kind == RayKind::kShadow)
      out.shadow.push_back(r.ray);
    else if (r.kind == RayKind::kAo)
      out.ao.push_back(r.ray);
  }
  return out;
}

// Calls fn(i) for i in [0, n) on `threads` threads (blocks of 256 rays handed out dynamically);
// returns the sum of fn's results.
bool g_embree_threads = false;  // worker threads set Embree's MXCSR modes (embree_mxcsr)
void embree_mxcsr();

template <typename F>
uint64_t parallel_count(size_t n, unsigned threads, F fn) {
  if (threads <= 1) {
    uint64_t s = 0;
    for (size_t i = 0; i < n; ++i) s += fn(i);
    return s;
  }
  std::atomic<size_t> next{0};
  std::atomic<uint64_t> total{0};
  std::vector<std::thread> ts;
  for (unsigned t = 0; t < threads; ++t)
    ts.emplace_back([&] {
      if (g_embree_threads) embree_mxcsr();
      uint64_t s = 0;
      for (size_t b; (b = next.fetch_add(256)) < n;)
        for (size_t i = b, e = std::min(n, b + 256); i < e; ++i) s += fn(i);
      total += s;
    });
  for (auto& t : ts) t.join();
  return total;
}

// Times fn over every ray of v on `threads` threads: {"rays", "hits", "seconds"}.
template <typename F>
json time_rays(const std::vector<Ray>& v, unsigned threads, F fn) {
  const Timer t;
  const uint64_t hits = parallel_count(v.size(), threads, [&](size_t i) { return fn(v[i]); });
  return {{"rays", v.size()},
          {"hits", hits},
          {"seconds", t.seconds(threads)},
          {"wall_seconds", since(t.wall)}};
}

// ---- children: one measurement each, JSON on stdout ---------------------------------------------

// Our traversal (closest_hit / any_hit with the work counters, as the predictor uses it).
template <typename Trace>
json trace_all(const Rays& rays, unsigned threads, Trace closest, Trace anyhit) {
  json j;
  for (unsigned th : {1u, threads}) {
    const std::string sfx = th == 1 ? "" : "_mt";
    j["primary" + sfx] = time_rays(rays.primary, th, closest);
    j["shadow" + sfx] = time_rays(rays.shadow, th, anyhit);
    j["ao" + sfx] = time_rays(rays.ao, th, anyhit);
    if (threads == 1) break;
  }
  return j;
}

json child_ours(const ChildArgs& a) {
  const Rays rays = read_rays(a.stream);
  const Scene scene = load_scene(rays.scene);
  const Timer t;
  const Bvh bvh = build_bvh(scene.triangles);
  json j;
  j["build_seconds"] = t.seconds(1);
  j["triangles"] = scene.triangles.size();
  j["nodes"] = bvh.nodes.size();
  auto closest = [&](const Ray& r) {
    Counters c;
    return uint64_t(closest_hit(bvh, r, &c).hit());
  };
  auto anyhit = [&](const Ray& r) {
    Counters c;
    return uint64_t(any_hit(bvh, r, &c).hit());
  };
  j["trace"] = trace_all(rays, a.threads, std::function<uint64_t(const Ray&)>(closest),
                         std::function<uint64_t(const Ray&)>(anyhit));
  return j;
}

// Embree asks every application thread to set flush-to-zero and denormals-are-zero (its verbose
// output warns of a "severe performance impact" otherwise); its tutorials do. Set in Embree's
// processes and threads only: our traversal keeps IEEE denormals.
void embree_mxcsr() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

json child_embree(const ChildArgs& a) {
  // "embree-mxcsr-default": the same without FTZ/DAZ (what a user gets who skips that advice).
  const bool ftz = a.what == "embree";
  if (ftz) embree_mxcsr();
  g_embree_threads = ftz;
  const Rays rays = read_rays(a.stream);
  const Scene scene = load_scene(rays.scene);
  const Timer t;
  EmbreeScene es(scene.triangles, kEmbreeBenchConfig, /*robust=*/false, /*high_quality=*/false);
  json j;
  j["build_seconds"] = t.seconds(1);  // process CPU time: any build thread Embree uses counts
  j["description"] = es.description();
  auto closest = [&](const Ray& r) { return uint64_t(es.intersect(r).hit()); };
  auto anyhit = [&](const Ray& r) { return uint64_t(es.occluded(r)); };
  j["trace"] = trace_all(rays, a.threads, std::function<uint64_t(const Ray&)>(closest),
                         std::function<uint64_t(const Ray&)>(anyhit));
  return j;
}

// The bench's RTL configuration (kBenchRtlConfig; rtl/config/hrpp_configs.json), with the golden
// model's node-id width for the scene.
PredictorConfig default_predictor(const Scene& scene, const Bvh& bvh) {
  PredictorConfig c = rtl_config(kBenchRtlConfig).predictor();
  if (const std::string e = resolve_for_scene(scene, bvh, &c, {.tag_bits = c.table.tag_bits});
      !e.empty())
    throw std::runtime_error("predictor configuration: " + e);
  return c;
}

json child_predict(const ChildArgs& a) {
  const Rays rays = read_rays(a.stream);
  const Scene scene = load_scene(rays.scene);
  const Bvh bvh = build_bvh(scene.triangles);
  const PredictorConfig cfg = default_predictor(scene, bvh);
  json j;
  auto run = [&](uint32_t cores, uint32_t threads) {
    TiledOptions o;
    o.cores = cores;
    o.threads = threads;
    o.width = rays.width;
    const Timer t;
    TiledPredictor p(bvh, cfg, o);
    for (const RayRecord& r : rays.all) p.push(r);
    p.finish();
    const double s = t.seconds(threads);
    const PredictStats st = p.total();
    if (st.exact_mismatches) throw std::runtime_error("predictor: exact mismatches");
    return json{{"rays", st.rays},
                {"seconds", s},
                {"wall_seconds", since(t.wall)},
                {"cpu_seconds", process_cpu_seconds() - t.cpu},
                {"skipped_interior_fraction", st.skipped_interior_fraction()},
                {"true_positive", st.true_positive}};
  };
  j["one_core"] = run(1, 1);
  j["cores_1_thread"] = run(kBenchCores, 1);
  if (a.threads > 1) j["cores_mt"] = run(kBenchCores, a.threads);
  j["cores"] = kBenchCores;
  return j;
}

// A procedural scene of about n triangles: a height field (two triangles per grid cell) of
// gentle waves, seen from above; rays: a grid of vertical camera rays, 1 per sample.
std::vector<Triangle> big_scene(uint64_t n) {
  const uint32_t g = static_cast<uint32_t>(std::ceil(std::sqrt(double(n) / 2)));
  std::vector<Triangle> tris;
  tris.reserve(size_t(2) * g * g);
  auto h = [&](uint32_t i, uint32_t k) {
    const float x = float(i) / g, z = float(k) / g;
    return Vec3(x, 0.02f * std::sin(40 * x) * std::cos(37 * z) + 0.01f * std::sin(300 * x * z), z);
  };
  for (uint32_t k = 0; k < g; ++k)
    for (uint32_t i = 0; i < g; ++i) {
      const Vec3 a = h(i, k), b = h(i + 1, k), c = h(i + 1, k + 1), d = h(i, k + 1);
      tris.push_back({a, b, c});
      tris.push_back({a, c, d});
    }
  return tris;
}

std::vector<Ray> big_rays(uint64_t n) {
  const uint32_t g = static_cast<uint32_t>(std::ceil(std::sqrt(double(n))));
  std::vector<Ray> rays;
  rays.reserve(size_t(g) * g);
  for (uint32_t k = 0; k < g; ++k)
    for (uint32_t i = 0; i < g; ++i) {
      Ray r;
      r.org = Vec3(0.5f, 2.f, 0.5f);
      const Vec3 target((i + 0.5f) / g, 0.f, (k + 0.5f) / g);
      r.dir = glm::normalize(target - r.org);
      rays.push_back(r);
    }
  return rays;
}

json child_big(const ChildArgs& a) {
  auto t0 = Clock::now();
  std::vector<Triangle> tris = big_scene(a.big_tris);
  json j{{"triangles", tris.size()}, {"generate_seconds", since(t0)}};
  const std::vector<Ray> rays = big_rays(a.big_rays);
  auto closest_fn = std::function<uint64_t(const Ray&)>();
  if (a.what == "big-ours") {
    const Timer t;
    const Bvh bvh = build_bvh(tris);
    j["build_seconds"] = t.seconds(1);
    j["nodes"] = bvh.nodes.size();
    j["bvh_bytes"] = bvh.memory_bytes();
    tris = {};
    tris.shrink_to_fit();
    j["primary"] = time_rays(rays, 1, [&](const Ray& r) {
      Counters c;
      return uint64_t(closest_hit(bvh, r, &c).hit());
    });
  } else {
    embree_mxcsr();
    const Timer t;
    EmbreeScene es(tris, kEmbreeBenchConfig, false, false);
    j["build_seconds"] = t.seconds(1);
    tris = {};
    tris.shrink_to_fit();
    j["primary"] =
        time_rays(rays, 1, [&](const Ray& r) { return uint64_t(es.intersect(r).hit()); });
  }
  return j;
}

}  // namespace

int child_main(const ChildArgs& a) {
  json j;
  if (a.what == "ours")
    j = child_ours(a);
  else if (a.what == "embree" || a.what == "embree-mxcsr-default")
    j = child_embree(a);
  else if (a.what == "predict")
    j = child_predict(a);
  else if (a.what == "big-ours" || a.what == "big-embree")
    j = child_big(a);
  else {
    std::fprintf(stderr, "hrpp_bench: unknown --child %s\n", a.what.c_str());
    return 2;
  }
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

int embree_verbose() {
  std::vector<Triangle> tri{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}};
  EmbreeScene es(tri, std::string(kEmbreeBenchConfig) + ",verbose=2", false, false);
  return 0;
}

}  // namespace hrpp::bench
