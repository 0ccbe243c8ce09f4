// hrpp_bench: the driver (driver.h).
#include "driver.h"

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "children.h"
#include "hrpp/hardware/rtl_config.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/workload/ray_stream.h"
#include "hrpp/workload/workload.h"
#include "process.h"
#include "report.h"

namespace hrpp::bench {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The bench's RTL configuration as a preset name (hrpp predict/simulate --preset).
const std::string kBenchPreset = std::string("rtl-") + kBenchRtlConfig;

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

// Writes the scene's bench stream (primary, shadow, AO; Morton order) unless it exists.
std::string make_stream(const std::string& scene_path, uint64_t samples, const std::string& dir,
                        std::string* rtl_misfit) {
  const Scene scene = load_scene(scene_path);
  const Bvh bvh = build_bvh(scene.triangles);
  // The co-simulation and the simulator run the bench's RTL configuration: does it fit?
  CycleConfig cc;
  *rtl_misfit =
      rtl_config(kBenchRtlConfig).cycle_for_scene(PredictMode::kClosestExact, scene, bvh, &cc);
  WorkloadOptions wo;
  resolution_for(scene.camera, samples, 1, &wo.width, &wo.height);
  wo.shadow = wo.ao = true;
  wo.order = RayOrder::kMorton;
  json opts = workload_json(scene, wo);
  opts["generator"] = "hrpp_bench";
  StreamHeader h;
  h.scene_fingerprint = scene_fingerprint(scene);
  h.options = opts.dump();
  const std::string path =
      dir + "/" + fs::path(scene_path).stem().string() + "-" + std::to_string(samples) + ".rays";
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
// tb.throughput.primary); else the testbench's default random handshakes and latencies.
json run_cosim(const DriverArgs& a, const std::string& stream, bool full_rate, double* rss) {
  std::vector<std::string> argv{a.tb,
                                "--stream",
                                stream,
                                "--config",
                                kBenchRtlConfig,
                                "--mode",
                                "closest-exact",
                                "--rays",
                                std::to_string(a.cosim_rays)};
  if (full_rate)
    for (const char* x :
         {"--p-ray", "1", "--p-ready", "1", "--min-latency", "1", "--max-latency", "1"})
      argv.push_back(x);
  const Proc p = run_process(argv);
  std::smatch m;
  const std::regex parity(R"(parity: (\d+) rays, (\d+) cycles, (\d+) mismatches)");
  const std::regex timing(R"(timing: lockstep run [0-9.e+-]+ s \(CPU ([0-9.e+-]+) s\))");
  if (!std::regex_search(p.out, m, parity))
    throw std::runtime_error(a.tb + " printed no parity line:\n" + p.out);
  json j{{"rays", std::stoull(m[1])},
         {"cycles", std::stoull(m[2])},
         {"mismatches", std::stoull(m[3])},
         {"pass", p.out.find("\nPASS") != std::string::npos}};
  if (!std::regex_search(p.out, m, timing))
    throw std::runtime_error(a.tb + " printed no timing line (an old build?)");
  j["seconds"] = std::stod(m[1]);
  j["process_seconds"] = p.seconds;
  if (!j["pass"].get<bool>() || j["mismatches"].get<uint64_t>())
    throw std::runtime_error(a.tb + " failed on " + stream + ":\n" + p.out);
  *rss = p.max_rss_mb;
  return j;
}

// hrpp simulate on a 256x256 AO frame as MICRO 2021 (unbounded AO rays from the primary hits,
// the `mobile` GPU, the RTL's `primary` predictor; no oracle, no per-kind runs): the arguments
// after the scene and --json. rtl: the Verilated RTL in every unit, in lockstep with the cycle
// model.
std::vector<std::string> simulate_args(bool rtl) {
  std::vector<std::string> v{"--res",         "256x256",    "--kinds",     "ao",
                             "--ao-distance", "inf",        "--gpu",       "mobile",
                             "--preset",      kBenchPreset, "--no-oracle", "--no-per-kind"};
  if (rtl) v.push_back("--rtl");
  return v;
}

// One `hrpp simulate` run (simulate_args) on the scene: from its --json report, the preset run's
// and the baseline run's simulated rays per second (wall clock of each run), the whole command's
// seconds (its own wall clock; from wait4, its CPU time), the cycles and, with rtl, the RTL's
// mismatches. Throws when the command fails, its report lacks a figure, or (rtl) the RTL and the
// cycle model differed in any cycle.
json run_simulate(const DriverArgs& a, const std::string& scene, const std::string& dir, bool rtl,
                  double* rss) {
  const std::string report =
      dir + "/" + fs::path(scene).stem().string() + (rtl ? "-simulate-rtl.json" : "-simulate.json");
  fs::remove(report);  // a stale report must not pass for this run's
  std::vector<std::string> argv{a.hrpp, "simulate", scene};
  for (const std::string& x : simulate_args(rtl)) argv.push_back(x);
  argv.insert(argv.end(), {"--json", report});
  std::string cmd;
  for (const std::string& x : argv) cmd.append(cmd.empty() ? "" : " ").append(x);
  const Proc p = run_process(argv);
  if (!WIFEXITED(p.status) || WEXITSTATUS(p.status) != 0)
    throw std::runtime_error(cmd + " failed (" +
                             (WIFEXITED(p.status)
                                  ? "exit code " + std::to_string(WEXITSTATUS(p.status))
                                  : "status " + std::to_string(p.status)) +
                             "; its stdout follows, its stderr is above):\n" + p.out);
  json r;
  try {
    std::ifstream in(report);
    r = json::parse(in);
  } catch (const std::exception& e) {
    throw std::runtime_error(cmd + ": cannot read its report " + report + ": " + e.what());
  }
  auto need = [&](const json& j, const char* key, const std::string& where) -> const json& {
    if (!j.contains(key) || !j[key].is_number())
      throw std::runtime_error(cmd + ": its report has no number " + where + key +
                               " (an old build?)");
    return j[key];
  };
  const json& base = r.contains("baseline") ? r["baseline"] : json();
  json j{{"rays", need(r, "rays", "")},
         {"cycles", need(r, "cycles", "")},
         {"baseline_cycles", need(r, "baseline_cycles", "")},
         {"speedup", need(r, "speedup", "")},
         {"rays_per_second", need(r, "rays_per_second", "")},
         {"run_seconds", need(r, "run_seconds", "")},
         {"baseline_rays_per_second", need(base, "rays_per_second", "baseline.")},
         {"baseline_run_seconds", need(base, "run_seconds", "baseline.")},
         {"seconds", need(r, "seconds", "")},
         {"cpu_seconds", p.cpu_seconds},
         {"process_seconds", p.seconds},
         {"wrong_results", need(r, "wrong_results", "")}};
  if (rtl) {
    j["rtl_mismatches"] = need(r, "rtl_mismatches", "");
    if (j["rtl_mismatches"].get<uint64_t>() != 0)
      throw std::runtime_error(cmd + ": the RTL differed from the cycle model in " +
                               std::to_string(j["rtl_mismatches"].get<uint64_t>()) + " cycles:\n" +
                               p.out);
  }
  *rss = p.max_rss_mb;
  return j;
}

// The scenes: --scenes (names of SHARED/scenes or paths), else every scene of SHARED/scenes,
// else the project's own. False (after a message) when one does not exist.
bool list_scenes(const DriverArgs& a, std::vector<std::string>* out) {
  std::vector<std::string>& scenes = *out;
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
      return false;
    }
  return true;
}

// The machine and Embree's ISA (the report's "machine"), printed.
json describe_machine(unsigned threads) {
  json machine{{"cpu", cpu_model()},
               {"hardware_threads", std::thread::hardware_concurrency()},
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
  return machine;
}

// One repetition: ours and Embree (which goes first alternates), Embree without FTZ/DAZ, the
// predictor, the co-simulation with random handshakes and at full rate, and (with --hrpp)
// hrpp simulate's AO frame with the cycle model and with --rtl, each in its own process. Each
// measurement's peak RSS goes to (*rss)[its name] (the most over the repetitions).
Repetition run_repetition(const DriverArgs& a, const std::vector<std::string>& cargs,
                          const std::string& scene, const std::string& stream, int rep,
                          bool rtl_fits, std::map<std::string, double>* rss) {
  double rs = 0;
  Repetition m;
  json &ours = m.ours, &emb = m.embree;
  if (rep % 2 == 0) {
    ours = run_child("ours", cargs, &rs);
    (*rss)["ours"] = std::max((*rss)["ours"], rs);
    emb = run_child("embree", cargs, &rs);
    (*rss)["embree"] = std::max((*rss)["embree"], rs);
  } else {
    emb = run_child("embree", cargs, &rs);
    (*rss)["embree"] = std::max((*rss)["embree"], rs);
    ours = run_child("ours", cargs, &rs);
    (*rss)["ours"] = std::max((*rss)["ours"], rs);
  }
  m.embree_mxcsr_default = run_child("embree-mxcsr-default", cargs, &rs);
  (*rss)["embree_mxcsr_default"] = std::max((*rss)["embree_mxcsr_default"], rs);
  m.predict = run_child("predict", cargs, &rs);
  (*rss)["predict"] = std::max((*rss)["predict"], rs);
  if (!rtl_fits) return m;  // the `primary` configuration cannot name the BVH's nodes
  m.cosim = run_cosim(a, stream, false, &rs);
  (*rss)["cosim"] = std::max((*rss)["cosim"], rs);
  m.cosim_full_rate = run_cosim(a, stream, true, &rs);
  (*rss)["cosim"] = std::max((*rss)["cosim"], rs);
  if (!a.hrpp.empty()) {
    const std::string dir = fs::path(stream).parent_path().string();
    m.simulate = run_simulate(a, scene, dir, false, &rs);
    (*rss)["simulate"] = std::max((*rss)["simulate"], rs);
    m.simulate_rtl = run_simulate(a, scene, dir, true, &rs);
    (*rss)["simulate_rtl"] = std::max((*rss)["simulate_rtl"], rs);
  }
  return m;
}

// Same rays, same answers (hit counts; Embree's non-robust mode may differ by a few rays).
void check_answers(const std::string& name, const Repetition& m) {
  const json &to = m.ours["trace"], &te = m.embree["trace"];
  for (const char* k : {"primary", "shadow", "ao"})
    if (to[k]["hits"] != te[k]["hits"])
      std::fprintf(stderr, "bench: %s: %s rays: ours hit %llu, Embree %llu\n", name.c_str(), k,
                   (unsigned long long)to[k]["hits"].get<uint64_t>(),
                   (unsigned long long)te[k]["hits"].get<uint64_t>());
}

// One scene: its stream, its repetitions, its entry of the report (printed).
json bench_scene(const DriverArgs& a, const std::string& scene, const std::string& dir,
                 unsigned threads, Figures* for_geomean, Figures* rss_geomean) {
  const std::string name = fs::path(scene).stem().string();
  std::fprintf(stderr, "bench: %s: writing the ray stream\n", name.c_str());
  std::string misfit;
  const std::string stream = make_stream(scene, a.samples, dir, &misfit);
  const bool rtl_fits = misfit.empty();
  std::string rtl_skipped;
  if (!rtl_fits) {
    rtl_skipped = "the RTL's primary configuration: " + misfit + ": no co-simulation, no simulate";
    std::fprintf(stderr, "bench: %s: %s\n", name.c_str(), rtl_skipped.c_str());
  }
  Figures r;
  std::map<std::string, double> rss;
  Repetition last;
  const std::vector<std::string> cargs{"--stream", stream, "--threads", std::to_string(threads)};
  for (int rep = 0; rep < a.reps; ++rep) {
    std::fprintf(stderr, "bench: %s: repetition %d of %d\n", name.c_str(), rep + 1, a.reps);
    const Repetition m = run_repetition(a, cargs, scene, stream, rep, rtl_fits, &rss);
    add_figures(m, threads, &r);
    if (rep == 0) check_answers(name, m);
    last = m;
  }
  json flat = scene_report(r, rss, last, for_geomean, rss_geomean);
  if (!rtl_fits) flat["rtl_skipped"] = rtl_skipped;
  print_scene_line(name, flat, rss, threads);
  return flat;
}

// Memory does not grow with the number of rays: hrpp predict (generated workload, the RTL's
// default table on 8 cores, all threads) on the first scene at two image sizes, 64 times apart.
// (With --table unbounded the table itself grows with the number of distinct keys.)
json memory_vs_rays(const DriverArgs& a, const std::string& scene, unsigned threads) {
  json mem = json::array();
  for (const char* res : {"256x192", "2048x1536"}) {
    std::fprintf(stderr, "bench: hrpp predict %s --res %s: peak memory\n", scene.c_str(), res);
    const Proc p = run_process({a.hrpp, "predict", scene, "--res", res, "--cores", "8", "--threads",
                                std::to_string(threads), "--preset", kBenchPreset});
    if (!WIFEXITED(p.status) || WEXITSTATUS(p.status) != 0)
      throw std::runtime_error(a.hrpp + " predict failed:\n" + p.out);
    std::smatch m;
    const std::regex all(R"(\n  all +(\d+) )");
    const uint64_t nrays = std::regex_search(p.out, m, all) ? std::stoull(m[1]) : 0;
    mem.push_back(
        {{"res", res}, {"rays", nrays}, {"peak_rss_mb", p.max_rss_mb}, {"seconds", p.seconds}});
    std::printf(
        "hrpp predict %s --res %s --cores 8 --threads %u: %llu rays, peak RSS %.0f MB, "
        "%.1f s\n",
        fs::path(scene).stem().c_str(), res, threads, (unsigned long long)nrays, p.max_rss_mb,
        p.seconds);
  }
  return mem;
}

// The big procedural scene, built and traced by ours and by Embree, each in its own process.
json big_scene_runs(const DriverArgs& a) {
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
    std::printf(
        "big scene (%s): %llu triangles, build %.2f s, %.2f M primary rays/s on one "
        "thread, peak RSS %.0f MB\n",
        who + 4, (unsigned long long)j["triangles"].get<uint64_t>(),
        j["build_seconds"].get<double>(), rate(j["primary"]) / 1e6, rs);
  }
  return big;
}

}  // namespace

int driver_main(const DriverArgs& a) {
  const unsigned threads =
      a.threads ? a.threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::string> scenes;
  if (!list_scenes(a, &scenes)) return 2;
  if (!fs::exists(a.tb)) {
    std::fprintf(stderr, "hrpp_bench: --tb: %s does not exist (make build)\n", a.tb.c_str());
    return 2;
  }
  if (!a.hrpp.empty() && !fs::exists(a.hrpp)) {
    std::fprintf(stderr, "hrpp_bench: --hrpp: %s does not exist (make build)\n", a.hrpp.c_str());
    return 2;
  }
  const std::string dir = (fs::path(a.out).parent_path() / "bench").string();
  fs::create_directories(dir);

  json out{{"machine", describe_machine(threads)},
           {"settings",
            {{"samples", a.samples},
             {"reps", a.reps},
             {"cosim_rays", a.cosim_rays},
             {"predictor", rtl_config(kBenchRtlConfig).describe() + ", closest-exact"},
             {"predictor_cores", kBenchCores},
             {"simulate", a.hrpp.empty() ? json() : json(simulate_args(false))},
             {"simulate_rtl", a.hrpp.empty() ? json() : json(simulate_args(true))}}},
           {"scenes", json::object()}};
  Figures for_geomean, rss_geomean;
  for (const std::string& scene : scenes)
    out["scenes"][fs::path(scene).stem().string()] =
        bench_scene(a, scene, dir, threads, &for_geomean, &rss_geomean);
  out["geomean"] = geomean_report(for_geomean, rss_geomean, scenes.size());
  if (!a.hrpp.empty() && !scenes.empty())
    out["memory_vs_rays"] = memory_vs_rays(a, scenes[0], threads);
  if (a.big_tris > 0) out["big_scene"] = big_scene_runs(a);
  return write_report(a.out, out);
}

}  // namespace hrpp::bench
