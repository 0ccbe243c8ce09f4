// hrpp_bench: the benchmark of `make bench` (docs/results.md, "Performance"). Not a test.
//
// For every scene it writes one ray stream (primary, shadow and ambient-occlusion rays, Morton
// order) to out/bench/, then runs, R times and interleaved (ours, Embree, predictor, co-simulation;
// the order of ours and Embree alternates between repetitions), each measurement in a fresh
// process of its own so that its peak RSS (wait4's ru_maxrss) is its own:
//   ours     our BVH build (one thread), closest_hit on the primary rays and any_hit on the shadow
//            and AO rays, on one thread and on all threads;
//   embree   the same with Embree 3 as a user gets it: its default ISA for this CPU, default scene
//            flags and build quality, rtcIntersect1 / rtcOccluded1, a device with threads=1,
//            flush-to-zero and denormals-are-zero set as Embree asks (and, as "embree-mxcsr-default",
//            once more without them: the *_mxcsr_default ratios);
//   predict  the predictor (the RTL's default configuration) on all the rays: one core on one
//            thread, and 8 cores (8 tables) on one thread and on all threads;
//   cosim    tb_hrpp --stream (the RTL and the cycle model in lockstep, parity checked on every
//            cycle) on the first --cosim-rays rays, with the testbench's default random
//            handshakes and again at full rate.
// One-thread figures are process CPU time (the machine may be shared); all-thread figures are wall
// time. Ratios are taken within a repetition (ours / Embree, above 1: ours faster) and reported as the
// median with the min and max over the repetitions. A big procedural scene (10 million triangles
// by default) is built and traced last, by ours and by Embree, each in its own process.
//
//   hrpp_bench [--shared DIR] [--scenes a,b,...] [--samples N] [--reps R] [--threads N]
//              [--out FILE] [--tb PATH] [--cosim-rays N] [--big-tris N]
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "hrpp/atomic_file.h"
#include "hrpp/bvh.h"
#include "hrpp/embree_ref.h"
#include "hrpp/predictor.h"
#include "hrpp/ray_stream.h"
#include "hrpp/scene.h"
#include "hrpp/tiled_predictor.h"
#include "hrpp/traverse.h"
#include "hrpp/workload.h"

namespace hrpp::bench {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// One-thread measurements count the process's CPU time: on a shared machine, time spent
// descheduled is not the code's. Several-thread measurements (scaling) need the wall clock.
struct Timer {
  Clock::time_point wall = Clock::now();
  double cpu = process_cpu_seconds();
  double seconds(unsigned threads) const {
    return threads <= 1 ? process_cpu_seconds() - cpu : since(wall);
  }
};

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
    if (r.kind == RayKind::kPrimary) out.primary.push_back(r.ray);
    else if (r.kind == RayKind::kShadow) out.shadow.push_back(r.ray);
    else if (r.kind == RayKind::kAo) out.ao.push_back(r.ray);
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
  return {{"rays", v.size()}, {"hits", hits}, {"seconds", t.seconds(threads)},
          {"wall_seconds", since(t.wall)}};
}

// ---- children: one measurement each, JSON on stdout ---------------------------------------------

struct ChildArgs {
  std::string what, stream, scene;
  unsigned threads = 1;
  uint64_t big_tris = 0;
  uint64_t big_rays = 0;
};

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

// Embree's default configuration: every ISA it was compiled for that the CPU has (it picks the
// best), default scene flags, default build quality (medium), one build thread.
constexpr const char* kEmbreeBenchConfig = "threads=1";

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

// The RTL's default configuration (Makefile PREDICT_DEFAULT, tb_hrpp --config default).
PredictorConfig default_predictor(const Scene& scene, const Bvh& bvh) {
  PredictorConfig c;
  c.hash.variant = HashVariant::kImproved;
  c.hash.origin_bits = 5;
  c.hash.dir_bits = 3;
  c.hash.combine = CombineMode::kConcat;
  c.table.sets = 128;
  c.table.ways = 8;
  c.table.nodes_per_entry = 2;
  c.mode = PredictMode::kClosestExact;
  if (const std::string e = resolve_for_scene(scene, bvh, &c, {.tag_bits = 8}); !e.empty())
    throw std::runtime_error("predictor configuration: " + e);
  return c;
}

constexpr uint32_t kBenchCores = 8;

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
    j["primary"] = time_rays(rays, 1, [&](const Ray& r) { return uint64_t(es.intersect(r).hit()); });
  }
  return j;
}

int child_main(const ChildArgs& a) {
  json j;
  if (a.what == "ours") j = child_ours(a);
  else if (a.what == "embree" || a.what == "embree-mxcsr-default") j = child_embree(a);
  else if (a.what == "predict") j = child_predict(a);
  else if (a.what == "big-ours" || a.what == "big-embree") j = child_big(a);
  else {
    std::fprintf(stderr, "hrpp_bench: unknown --child %s\n", a.what.c_str());
    return 2;
  }
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

// ---- the driver ----------------------------------------------------------------------------------

struct Proc {
  std::string out;
  int status = -1;
  double max_rss_mb = 0;
  double seconds = 0;
};

// Runs argv in a child process; its stdout is captured, its stderr passes through.
Proc run_process(const std::vector<std::string>& argv) {
  int fd[2];
  if (pipe(fd) != 0) throw std::runtime_error("pipe failed");
  const auto t0 = Clock::now();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    dup2(fd[1], 1);
    close(fd[0]);
    close(fd[1]);
    std::vector<char*> av;
    for (const auto& s : argv) av.push_back(const_cast<char*>(s.c_str()));
    av.push_back(nullptr);
    execv(av[0], av.data());
    std::fprintf(stderr, "hrpp_bench: cannot run %s: %s\n", av[0], std::strerror(errno));
    _exit(127);
  }
  close(fd[1]);
  Proc p;
  char buf[65536];
  for (ssize_t k; (k = read(fd[0], buf, sizeof buf)) > 0;) p.out.append(buf, size_t(k));
  close(fd[0]);
  struct rusage ru {};
  wait4(pid, &p.status, 0, &ru);
  p.seconds = since(t0);
  p.max_rss_mb = ru.ru_maxrss / 1024.0;  // Linux: kilobytes
  return p;
}

std::string self_exe() { return fs::read_symlink("/proc/self/exe").string(); }

json run_child(const std::string& what, const std::vector<std::string>& args, double* rss) {
  std::vector<std::string> argv{self_exe(), "--child", what};
  argv.insert(argv.end(), args.begin(), args.end());
  const Proc p = run_process(argv);
  if (!WIFEXITED(p.status) || WEXITSTATUS(p.status) != 0)
    throw std::runtime_error("the " + what + " measurement failed (exit status " +
                             std::to_string(p.status) + ")");
  *rss = p.max_rss_mb;
  return json::parse(p.out);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// {"median", "min", "max", "runs"}
json summary(const std::vector<double>& v) {
  if (v.empty()) return nullptr;
  return {{"median", median(v)},
          {"min", *std::min_element(v.begin(), v.end())},
          {"max", *std::max_element(v.begin(), v.end())},
          {"runs", v}};
}

std::string fmt_ratio(const json& s) {
  if (s.is_null()) return "-";
  char b[64];
  std::snprintf(b, sizeof b, "%.2f (%.2f-%.2f)", s["median"].get<double>(), s["min"].get<double>(),
                s["max"].get<double>());
  return b;
}

double rate(const json& m) { return m["rays"].get<double>() / m["seconds"].get<double>(); }
// Rays per second over several kinds (total rays / total seconds).
double rate_of(const json& t, std::initializer_list<const char*> kinds) {
  double r = 0, s = 0;
  for (const char* k : kinds) {
    r += t[k]["rays"].get<double>();
    s += t[k]["seconds"].get<double>();
  }
  return s > 0 ? r / s : 0;
}

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

// What Embree reports about the CPU and the ISA it selected (a device with verbose=1 prints it
// to stdout, so it is run in a child process and its output parsed).
std::string embree_isa_report() {
  const Proc p = run_process({self_exe(), "--child", "embree-verbose"});
  std::string keep;
  std::istringstream in(p.out);
  bool selected = false;
  for (std::string line; std::getline(in, line);) {
    if (line.find("selected scene intersector") != std::string::npos) selected = true;
    if ((line.find("CPU  ") != std::string::npos || line.find("Targets") != std::string::npos ||
         line.find("building BVH") != std::string::npos ||
         (selected && line.find("intersector1 ") != std::string::npos)) &&
        keep.find(line) == std::string::npos)
      keep += line + "\n";
  }
  return keep;
}

struct DriverArgs {
  std::string shared = "../shared", scenes, out = "out/bench.json", tb = "build/tb_hrpp",
              hrpp = "build/hrpp";
  uint64_t samples = 262144, cosim_rays = 300000, big_tris = 10000000, big_rays = 1000000;
  int reps = 5;
  unsigned threads = 0;
};

// Writes the scene's bench stream (primary, shadow, AO; Morton order) unless it exists.
std::string make_stream(const std::string& scene_path, uint64_t samples, const std::string& dir) {
  const Scene scene = load_scene(scene_path);
  const Bvh bvh = build_bvh(scene.triangles);
  WorkloadOptions wo;
  resolution_for(scene.camera, samples, 1, &wo.width, &wo.height);
  wo.shadow = wo.ao = true;
  wo.order = RayOrder::kMorton;
  json opts = workload_json(scene, wo);
  opts["generator"] = "hrpp_bench";
  StreamHeader h;
  h.scene_fingerprint = scene_fingerprint(scene);
  h.options = opts.dump();
  const std::string path = dir + "/" + fs::path(scene_path).stem().string() + "-" +
                           std::to_string(samples) + ".rays";
  if (fs::exists(path)) {
    RayStreamReader rd(path);
    if (rd.header().scene_fingerprint == h.scene_fingerprint && rd.header().options == h.options)
      return path;
  }
  RayStreamWriter w(path, h);
  uint64_t invalid = 0;
  generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit*) {
    if (validate_ray(r.ray) != RayError::kNone) ++invalid;
    w.write(r);
  });
  w.close();
  if (invalid)
    std::fprintf(stderr, "bench: %s: %llu invalid rays in the stream (skipped by every side)\n",
                 scene_path.c_str(), (unsigned long long)invalid);
  return path;
}

// tb_hrpp's "parity:" and "timing:" lines.
// full_rate: every handshake ready and a one-cycle engine (the RTL's own limit, as the test
// tb.throughput.default); else the testbench's default random handshakes and latencies.
json run_cosim(const DriverArgs& a, const std::string& stream, bool full_rate, double* rss) {
  std::vector<std::string> argv{a.tb, "--stream", stream, "--config", "default", "--mode",
                                "closest-exact", "--rays", std::to_string(a.cosim_rays)};
  if (full_rate)
    for (const char* x : {"--p-ray", "1", "--p-ready", "1", "--min-latency", "1", "--max-latency", "1"})
      argv.push_back(x);
  const Proc p = run_process(argv);
  std::smatch m;
  const std::regex parity(R"(parity: (\d+) rays, (\d+) cycles, (\d+) mismatches)");
  const std::regex timing(R"(timing: lockstep run [0-9.e+-]+ s \(CPU ([0-9.e+-]+) s\))");
  if (!std::regex_search(p.out, m, parity))
    throw std::runtime_error(a.tb + " printed no parity line:\n" + p.out);
  json j{{"rays", std::stoull(m[1])}, {"cycles", std::stoull(m[2])},
         {"mismatches", std::stoull(m[3])}, {"pass", p.out.find("\nPASS") != std::string::npos}};
  if (!std::regex_search(p.out, m, timing))
    throw std::runtime_error(a.tb + " printed no timing line (an old build?)");
  j["seconds"] = std::stod(m[1]);
  j["process_seconds"] = p.seconds;
  if (!j["pass"].get<bool>() || j["mismatches"].get<uint64_t>())
    throw std::runtime_error(a.tb + " failed on " + stream + ":\n" + p.out);
  *rss = p.max_rss_mb;
  return j;
}

double geomean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += std::log(x);
  return v.empty() ? 0 : std::exp(s / v.size());
}

// The table of docs/results.md ("Performance"), from the report.
std::string markdown(const json& out) {
  std::string md;
  char b[1024];
  std::snprintf(b, sizeof b, "Machine: %s, %u hardware threads; Embree ISA %s (%s).\n\n",
                out["machine"]["cpu"].get<std::string>().c_str(),
                out["machine"]["hardware_threads"].get<unsigned>(),
                out["machine"]["embree_isa"].get<std::string>().c_str(),
                out["machine"]["embree_intersector1"].get<std::string>().c_str());
  md += b;
  const unsigned th = out["machine"]["threads_used"].get<unsigned>();
  auto cell = [](const json& sm, const char* key, const char* f = "%.2f") -> std::string {
    if (!sm.contains(key) || sm[key].is_null()) return "-";
    char c[96], lo[32], hi[32], med[32];
    std::snprintf(med, sizeof med, f, sm[key]["median"].get<double>());
    std::snprintf(lo, sizeof lo, f, sm[key]["min"].get<double>());
    std::snprintf(hi, sizeof hi, f, sm[key]["max"].get<double>());
    std::snprintf(c, sizeof c, "%s (%s-%s)", med, lo, hi);
    return c;
  };
  std::snprintf(b, sizeof b,
                "| scene | triangles | rays | build | primary | any-hit | predictor | primary, %u thr. "
                "| any-hit, %u thr. | predictor scaling, %u thr. | co-sim rays/s | co-sim cycles/s "
                "| peak RSS MB ours / Embree / predictor / co-sim |\n",
                th, th, th);
  md += b;
  md += "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (auto it = out["scenes"].begin(); it != out["scenes"].end(); ++it) {
    const json& sc = *it;
    const json& sm = sc["summary"];
    const json& rss = sc["peak_rss_mb"];
    const uint64_t rays = sc["rays"]["primary"].get<uint64_t>() + sc["rays"]["shadow"].get<uint64_t>() +
                          sc["rays"]["ao"].get<uint64_t>();
    std::snprintf(b, sizeof b, "| %s | %llu | %llu | %s | %s | %s | %s | %s | %s | %s | %s | %s | %.0f / %.0f / %.0f / %.0f |\n",
                  it.key().c_str(), (unsigned long long)sc["triangles"].get<uint64_t>(),
                  (unsigned long long)rays, cell(sm, "build_vs_embree").c_str(),
                  cell(sm, "traversal_vs_embree").c_str(), cell(sm, "anyhit_vs_embree").c_str(),
                  cell(sm, "predict_vs_embree").c_str(), cell(sm, "traversal_vs_embree_mt").c_str(),
                  cell(sm, "anyhit_vs_embree_mt").c_str(), cell(sm, "predict_scaling").c_str(),
                  cell(sm, "cosim_rays_per_s", "%.0f").c_str(),
                  cell(sm, "cosim_cycles_per_s", "%.0f").c_str(), rss.value("ours", 0.0),
                  rss.value("embree", 0.0), rss.value("predict", 0.0), rss.value("cosim", 0.0));
    md += b;
  }
  const json& g = out["geomean"];
  auto gv = [&](const char* k, const char* f = "%.2f") -> std::string {
    if (!g.contains(k)) return "-";
    char c[64];
    std::snprintf(c, sizeof c, f, g[k].get<double>());
    return c;
  };
  std::snprintf(b, sizeof b, "| **geometric mean** | | | %s | %s | %s | %s | %s | %s | %s | %s | %s | |\n",
                gv("build_vs_embree").c_str(), gv("traversal_vs_embree").c_str(),
                gv("anyhit_vs_embree").c_str(), gv("predict_vs_embree").c_str(),
                gv("traversal_vs_embree_mt").c_str(), gv("anyhit_vs_embree_mt").c_str(),
                gv("predict_scaling").c_str(), gv("cosim_rays_per_s", "%.0f").c_str(),
                gv("cosim_cycles_per_s", "%.0f").c_str());
  md += b;
  std::snprintf(b, sizeof b,
                "\nAgainst Embree without FTZ/DAZ (geometric means): primary %s, any-hit %s, "
                "predictor %s. Predictor: one thread's CPU time over %u threads': %s. Co-simulation "
                "at full rate (every handshake ready, one-cycle engine): %s rays/s.\n",
                gv("traversal_vs_embree_mxcsr_default").c_str(),
                gv("anyhit_vs_embree_mxcsr_default").c_str(),
                gv("predict_vs_embree_mxcsr_default").c_str(), th,
                gv("predict_mt_cpu_efficiency").c_str(),
                gv("cosim_full_rate_rays_per_s", "%.0f").c_str());
  md += b;
  if (out.contains("memory_vs_rays")) {
    md += "\nMemory against workload size (`hrpp predict`, the RTL's default table on 8 cores): ";
    for (const json& m : out["memory_vs_rays"]) {
      std::snprintf(b, sizeof b, "%s%s, %llu rays: %.0f MB", m == out["memory_vs_rays"][0] ? "" : "; ",
                    m["res"].get<std::string>().c_str(), (unsigned long long)m["rays"].get<uint64_t>(),
                    m["peak_rss_mb"].get<double>());
      md += b;
    }
    md += ".\n";
  }
  if (out.contains("big_scene")) {
    md += "\n| procedural scene | triangles | build s | primary rays/s (1 thread) | peak RSS MB |\n"
          "|---|--:|--:|--:|--:|\n";
    for (auto it = out["big_scene"].begin(); it != out["big_scene"].end(); ++it) {
      const json& j = *it;
      std::snprintf(b, sizeof b, "| %s | %llu | %.2f | %.0f | %.0f |\n", it.key().c_str(),
                    (unsigned long long)j["triangles"].get<uint64_t>(),
                    j["build_seconds"].get<double>(),
                    j["primary"]["rays"].get<double>() / j["primary"]["seconds"].get<double>(),
                    j["peak_rss_mb"].get<double>());
      md += b;
    }
  }
  return md;
}

int driver_main(const DriverArgs& a) {
  const unsigned threads = a.threads ? a.threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::string> scenes;
  if (!a.scenes.empty()) {
    std::stringstream ss(a.scenes);
    for (std::string s; std::getline(ss, s, ',');)
      scenes.push_back(fs::exists(s) ? s : a.shared + "/scenes/" + s + ".glb");
  } else if (fs::is_directory(a.shared + "/scenes")) {
    for (const auto& e : fs::directory_iterator(a.shared + "/scenes"))
      if (e.path().extension() == ".glb") scenes.push_back(e.path().string());
    std::sort(scenes.begin(), scenes.end());
  } else {
    std::fprintf(stderr, "bench: %s/scenes is absent: benchmarking the project's own scenes\n",
                 a.shared.c_str());
    for (const auto& e : fs::directory_iterator("scenes"))
      if (e.path().extension() == ".glb") scenes.push_back(e.path().string());
    std::sort(scenes.begin(), scenes.end());
  }
  for (const auto& s : scenes)
    if (!fs::exists(s)) {
      std::fprintf(stderr, "hrpp_bench: --scenes: %s does not exist\n", s.c_str());
      return 2;
    }
  if (!fs::exists(a.tb)) {
    std::fprintf(stderr, "hrpp_bench: --tb: %s does not exist (make build)\n", a.tb.c_str());
    return 2;
  }
  const std::string dir = (fs::path(a.out).parent_path() / "bench").string();
  fs::create_directories(dir);

  json machine{{"cpu", cpu_model()}, {"hardware_threads", std::thread::hardware_concurrency()},
               {"threads_used", threads}};
  const std::string isa = embree_isa_report();
  machine["embree_verbose"] = isa;
  std::smatch im;
  const std::regex isa_re(R"(intersector1 += (\w+)::(\S+))");
  machine["embree_isa"] = std::regex_search(isa, im, isa_re) ? im[1].str() : "unknown";
  machine["embree_intersector1"] = std::regex_search(isa, im, isa_re) ? im[2].str() : "unknown";
  std::printf("machine: %s, %u hardware threads (all-core runs use %u)\n",
              machine["cpu"].get<std::string>().c_str(), std::thread::hardware_concurrency(),
              threads);
  std::printf("Embree ISA: %s (device \"%s\", FTZ/DAZ on; verbose=2 says):\n%s",
              machine["embree_isa"].get<std::string>().c_str(), kEmbreeBenchConfig, isa.c_str());

  json out{{"machine", machine},
           {"settings",
            {{"samples", a.samples}, {"reps", a.reps}, {"cosim_rays", a.cosim_rays},
             {"predictor", "improved hash 5/3 concat, 128x8 table, K=2, 8-bit tags, closest-exact"},
             {"predictor_cores", kBenchCores}}},
           {"scenes", json::object()}};
  const std::vector<std::string> keys{"build_vs_embree",       "traversal_vs_embree",
                                      "anyhit_vs_embree",      "predict_vs_embree",
                                      "traversal_vs_embree_mt", "anyhit_vs_embree_mt",
                                      "predict_scaling",       "predict_mt_cpu_efficiency",
                                      "cosim_rays_per_s",
                                      "cosim_cycles_per_s",    "cosim_full_rate_rays_per_s",
                                      "traversal_vs_embree_mxcsr_default",
                                      "anyhit_vs_embree_mxcsr_default",
                                      "predict_vs_embree_mxcsr_default"};
  std::map<std::string, std::vector<double>> for_geomean;
  std::map<std::string, std::vector<double>> rss_geomean;

  for (const std::string& scene : scenes) {
    const std::string name = fs::path(scene).stem().string();
    std::fprintf(stderr, "bench: %s: writing the ray stream\n", name.c_str());
    const std::string stream = make_stream(scene, a.samples, dir);
    std::map<std::string, std::vector<double>> r;
    std::map<std::string, double> rss;
    json last_ours, last_embree, last_pred, last_cosim;
    const std::vector<std::string> cargs{"--stream", stream, "--threads", std::to_string(threads)};
    for (int rep = 0; rep < a.reps; ++rep) {
      std::fprintf(stderr, "bench: %s: repetition %d of %d\n", name.c_str(), rep + 1, a.reps);
      double rs = 0;
      json ours, emb;
      if (rep % 2 == 0) {
        ours = run_child("ours", cargs, &rs);
        rss["ours"] = std::max(rss["ours"], rs);
        emb = run_child("embree", cargs, &rs);
        rss["embree"] = std::max(rss["embree"], rs);
      } else {
        emb = run_child("embree", cargs, &rs);
        rss["embree"] = std::max(rss["embree"], rs);
        ours = run_child("ours", cargs, &rs);
        rss["ours"] = std::max(rss["ours"], rs);
      }
      const json emb0 = run_child("embree-mxcsr-default", cargs, &rs);
      rss["embree_mxcsr_default"] = std::max(rss["embree_mxcsr_default"], rs);
      const json pred = run_child("predict", cargs, &rs);
      rss["predict"] = std::max(rss["predict"], rs);
      const json cos = run_cosim(a, stream, false, &rs);
      rss["cosim"] = std::max(rss["cosim"], rs);
      const json cos_full = run_cosim(a, stream, true, &rs);
      rss["cosim"] = std::max(rss["cosim"], rs);
      const json &to = ours["trace"], &te = emb["trace"];
      r["build_vs_embree"].push_back(emb["build_seconds"].get<double>() /
                                     ours["build_seconds"].get<double>());
      r["traversal_vs_embree"].push_back(rate(to["primary"]) / rate(te["primary"]));
      // Against Embree without FTZ/DAZ (one thread).
      {
        const json& t0 = emb0["trace"];
        r["traversal_vs_embree_mxcsr_default"].push_back(rate(to["primary"]) / rate(t0["primary"]));
        if (to["shadow"]["rays"].get<uint64_t>() + to["ao"]["rays"].get<uint64_t>() > 0)
          r["anyhit_vs_embree_mxcsr_default"].push_back(rate_of(to, {"shadow", "ao"}) /
                                                        rate_of(t0, {"shadow", "ao"}));
        r["predict_vs_embree_mxcsr_default"].push_back(
            rate(pred["one_core"]) / rate_of(t0, {"primary", "shadow", "ao"}));
      }
      if (to["shadow"]["rays"].get<uint64_t>() + to["ao"]["rays"].get<uint64_t>() > 0)
        r["anyhit_vs_embree"].push_back(rate_of(to, {"shadow", "ao"}) /
                                        rate_of(te, {"shadow", "ao"}));
      r["predict_vs_embree"].push_back(rate(pred["one_core"]) /
                                       rate_of(te, {"primary", "shadow", "ao"}));
      if (threads > 1) {
        r["traversal_vs_embree_mt"].push_back(rate(to["primary_mt"]) / rate(te["primary_mt"]));
        if (to["shadow_mt"]["rays"].get<uint64_t>() + to["ao_mt"]["rays"].get<uint64_t>() > 0)
          r["anyhit_vs_embree_mt"].push_back(rate_of(to, {"shadow_mt", "ao_mt"}) /
                                             rate_of(te, {"shadow_mt", "ao_mt"}));
        // Wall clock against wall clock, measured back to back in one process.
        r["predict_scaling"].push_back(pred["cores_1_thread"]["wall_seconds"].get<double>() /
                                       pred["cores_mt"]["wall_seconds"].get<double>());
        // CPU time per ray on N threads against one: 1 means no overhead from the threads.
        r["predict_mt_cpu_efficiency"].push_back(pred["cores_1_thread"]["cpu_seconds"].get<double>() /
                                                 pred["cores_mt"]["cpu_seconds"].get<double>());
      }
      r["cosim_rays_per_s"].push_back(cos["rays"].get<double>() / cos["seconds"].get<double>());
      r["cosim_cycles_per_s"].push_back(cos["cycles"].get<double>() / cos["seconds"].get<double>());
      r["cosim_full_rate_rays_per_s"].push_back(cos_full["rays"].get<double>() /
                                                cos_full["seconds"].get<double>());
      // Absolute rates, for the table.
      r["ours_primary_rays_per_s"].push_back(rate(to["primary"]));
      r["embree_primary_rays_per_s"].push_back(rate(te["primary"]));
      if (to["shadow"]["rays"].get<uint64_t>() + to["ao"]["rays"].get<uint64_t>() > 0) {
        r["ours_anyhit_rays_per_s"].push_back(rate_of(to, {"shadow", "ao"}));
        r["embree_anyhit_rays_per_s"].push_back(rate_of(te, {"shadow", "ao"}));
      }
      r["predict_rays_per_s"].push_back(rate(pred["one_core"]));
      r["ours_build_s"].push_back(ours["build_seconds"].get<double>());
      r["embree_build_s"].push_back(emb["build_seconds"].get<double>());
      // Same rays, same answers (hit counts; Embree's non-robust mode may differ by a few rays).
      for (const char* k : {"primary", "shadow", "ao"})
        if (rep == 0 && to[k]["hits"] != te[k]["hits"])
          std::fprintf(stderr, "bench: %s: %s rays: ours hit %llu, Embree %llu\n", name.c_str(), k,
                       (unsigned long long)to[k]["hits"].get<uint64_t>(),
                       (unsigned long long)te[k]["hits"].get<uint64_t>());
      last_ours = ours;
      last_embree = emb;
      last_pred = pred;
      last_cosim = cos;
    }
    json js;
    for (auto& [k, v] : r) js[k] = summary(v);
    // The keys of the issue: the medians; the full summaries beside them.
    json flat;
    for (const auto& k : keys)
      if (js.contains(k)) {
        flat[k] = js[k]["median"];
        for_geomean[k].push_back(js[k]["median"].get<double>());
      }
    json rssj;
    for (auto& [k, v] : rss) {
      rssj[k] = v;
      rss_geomean[k].push_back(v);
    }
    flat["peak_rss_mb"] = rssj;
    flat["summary"] = js;
    flat["rays"] = {{"primary", last_ours["trace"]["primary"]["rays"]},
                    {"shadow", last_ours["trace"]["shadow"]["rays"]},
                    {"ao", last_ours["trace"]["ao"]["rays"]}};
    flat["triangles"] = last_ours["triangles"];
    flat["embree"] = last_embree["description"];
    flat["cosim"] = last_cosim;
    flat["predict_skipped_interior_fraction"] = last_pred["one_core"]["skipped_interior_fraction"];
    out["scenes"][name] = flat;
    std::printf("%-13s tris %8llu  build %s  primary %s  any-hit %s  predict %s  | %u threads: "
                "primary %s  any-hit %s  predict scaling %s | cosim %.0f rays/s  RSS MB ours %.0f "
                "embree %.0f predict %.0f cosim %.0f\n",
                name.c_str(), (unsigned long long)flat["triangles"].get<uint64_t>(),
                fmt_ratio(js["build_vs_embree"]).c_str(), fmt_ratio(js["traversal_vs_embree"]).c_str(),
                fmt_ratio(js.value("anyhit_vs_embree", json())).c_str(),
                fmt_ratio(js["predict_vs_embree"]).c_str(), threads,
                fmt_ratio(js.value("traversal_vs_embree_mt", json())).c_str(),
                fmt_ratio(js.value("anyhit_vs_embree_mt", json())).c_str(),
                fmt_ratio(js.value("predict_scaling", json())).c_str(),
                js["cosim_rays_per_s"]["median"].get<double>(), rss["ours"], rss["embree"],
                rss["predict"], rss["cosim"]);
    std::fflush(stdout);
  }
  json gm;
  for (auto& [k, v] : for_geomean) gm[k] = geomean(v);
  for (auto& [k, v] : rss_geomean) gm["peak_rss_mb"][k] = geomean(v);
  out["geomean"] = gm;
  std::printf("geometric mean over %zu scenes (ratios: ours / Embree, above 1 = ours faster):\n",
              scenes.size());
  for (auto it = gm.begin(); it != gm.end(); ++it)
    if (it->is_number()) std::printf("  %-34s %.3f\n", it.key().c_str(), it->get<double>());

  // Memory does not grow with the number of rays: hrpp predict (generated workload, the RTL's
  // default table on 8 cores, all threads) on the first scene at two image sizes, 64 times apart.
  // (With --table unbounded the table itself grows with the number of distinct keys.)
  if (!a.hrpp.empty() && !scenes.empty()) {
    json mem = json::array();
    for (const char* res : {"256x192", "2048x1536"}) {
      std::fprintf(stderr, "bench: hrpp predict %s --res %s: peak memory\n", scenes[0].c_str(), res);
      const Proc p = run_process({a.hrpp, "predict", scenes[0], "--res", res, "--cores", "8",
                                  "--threads", std::to_string(threads), "--hash", "improved",
                                  "--origin-bits", "5", "--dir-bits", "3", "--combine", "concat",
                                  "--table", "128x8", "--nodes-per-entry", "2", "--tag-bits", "8"});
      if (!WIFEXITED(p.status) || WEXITSTATUS(p.status) != 0)
        throw std::runtime_error(a.hrpp + " predict failed:\n" + p.out);
      std::smatch m;
      const std::regex all(R"(\n  all +(\d+) )");
      const uint64_t nrays = std::regex_search(p.out, m, all) ? std::stoull(m[1]) : 0;
      mem.push_back({{"res", res}, {"rays", nrays}, {"peak_rss_mb", p.max_rss_mb},
                     {"seconds", p.seconds}});
      std::printf("hrpp predict %s --res %s --cores 8 --threads %u: %llu rays, peak RSS %.0f MB, "
                  "%.1f s\n", fs::path(scenes[0]).stem().c_str(), res, threads,
                  (unsigned long long)nrays, p.max_rss_mb, p.seconds);
    }
    out["memory_vs_rays"] = mem;
  }

  if (a.big_tris > 0) {
    const std::vector<std::string> bargs{"--big-tris", std::to_string(a.big_tris), "--big-rays",
                                         std::to_string(a.big_rays)};
    json big;
    for (const char* who : {"big-ours", "big-embree"}) {
      std::fprintf(stderr, "bench: procedural scene, %llu triangles: %s\n",
                   (unsigned long long)a.big_tris, who);
      double rs = 0;
      json j = run_child(who, bargs, &rs);
      j["peak_rss_mb"] = rs;
      big[who + 4] = j;
      std::printf("big scene (%s): %llu triangles, build %.2f s, %.2f M primary rays/s on one "
                  "thread, peak RSS %.0f MB\n",
                  who + 4, (unsigned long long)j["triangles"].get<uint64_t>(),
                  j["build_seconds"].get<double>(), rate(j["primary"]) / 1e6, rs);
    }
    out["big_scene"] = big;
  }
  const std::string md_path = (fs::path(a.out).replace_extension(".md")).string();
  try {
    hrpp::write_file_atomic(a.out, out.dump(2) + "\n");
    hrpp::write_file_atomic(md_path, markdown(out));
  } catch (const hrpp::AtomicFileError& e) {
    std::fprintf(stderr, "hrpp_bench: %s\n", e.what());
    return 2;
  }
  std::printf("wrote %s and %s\n", a.out.c_str(), md_path.c_str());
  return 0;
}

// A one-triangle scene on a verbose device with the bench's settings: Embree prints the CPU, its
// targets and, at the commit, the builder (and so the ISA) it dispatched to.
int embree_verbose() {
  std::vector<Triangle> tri{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}};
  EmbreeScene es(tri, std::string(kEmbreeBenchConfig) + ",verbose=2", false, false);
  return 0;
}

}  // namespace
}  // namespace hrpp::bench

int main(int argc, char** argv) {
  using namespace hrpp::bench;
  CLI::App app{"HRPP benchmark: our BVH build, traversal and predictor against Embree, and the "
               "RTL co-simulation (make bench)"};
  DriverArgs d;
  ChildArgs c;
  app.add_option("--shared", d.shared, "the shared folder (its scenes/*.glb are benchmarked)");
  app.add_option("--scenes", d.scenes, "comma-separated scene names or .glb paths (default: all)");
  app.add_option("--samples", d.samples, "camera samples per scene (shadow and AO rays on top)")
      ->check(CLI::Range(uint64_t{64}, uint64_t{1} << 26));
  app.add_option("--reps", d.reps, "repetitions (interleaved; medians and spread)")
      ->check(CLI::Range(1, 100));
  app.add_option("--threads", d.threads, "threads of the all-core runs (default: all)");
  app.add_option("--out", d.out, "JSON report");
  app.add_option("--tb", d.tb, "the Verilator testbench binary");
  app.add_option("--hrpp", d.hrpp, "the hrpp tool (memory check; empty: skip it)");
  app.add_option("--cosim-rays", d.cosim_rays, "rays of each co-simulation run")
      ->check(CLI::Range(uint64_t{1000}, uint64_t{1} << 32));
  app.add_option("--big-tris", d.big_tris, "triangles of the procedural scene (0: skip it)");
  app.add_option("--big-rays", d.big_rays, "primary rays traced in the procedural scene")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 30));
  app.add_option("--child", c.what, "(internal) run one measurement and print it as JSON");
  app.add_option("--stream", c.stream, "(internal)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // bad input: exit 2, as hrpp
  }
  c.threads = d.threads;
  c.big_tris = d.big_tris;
  c.big_rays = d.big_rays;
  try {
    if (c.what == "embree-verbose") return embree_verbose();
    if (!c.what.empty()) return child_main(c);
    return driver_main(d);
  } catch (const hrpp::SceneError& e) {
    std::fprintf(stderr, "hrpp_bench: %s\n", e.what());
    return 2;
  } catch (const hrpp::StreamError& e) {
    std::fprintf(stderr, "hrpp_bench: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrpp_bench: %s\n", e.what());
    return 1;
  }
}
