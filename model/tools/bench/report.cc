// hrpp_bench: the report (report.h).
#include "report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "hrpp/util/atomic_file.h"

namespace hrpp::bench {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string fmt_ratio(const json& s, const char* f = "%.2f") {
  if (s.is_null()) return "-";
  char med[32], lo[32], hi[32], b[112];
  std::snprintf(med, sizeof med, f, s["median"].get<double>());
  std::snprintf(lo, sizeof lo, f, s["min"].get<double>());
  std::snprintf(hi, sizeof hi, f, s["max"].get<double>());
  std::snprintf(b, sizeof b, "%s (%s-%s)", med, lo, hi);
  return b;
}

// The headline figures: their medians at the top of a scene's entry and their geometric means
// over the scenes.
const std::vector<std::string> kHeadlineKeys{"build_vs_embree",
                                             "traversal_vs_embree",
                                             "anyhit_vs_embree",
                                             "predict_vs_embree",
                                             "traversal_vs_embree_mt",
                                             "anyhit_vs_embree_mt",
                                             "predict_scaling",
                                             "predict_mt_cpu_efficiency",
                                             "cosim_rays_per_s",
                                             "cosim_cycles_per_s",
                                             "cosim_full_rate_rays_per_s",
                                             "traversal_vs_embree_mxcsr_default",
                                             "anyhit_vs_embree_mxcsr_default",
                                             "predict_vs_embree_mxcsr_default",
                                             "sim_rays_per_s",
                                             "sim_baseline_rays_per_s",
                                             "sim_frame_s",
                                             "sim_frame_cpu_s",
                                             "sim_rtl_rays_per_s",
                                             "sim_rtl_baseline_rays_per_s",
                                             "sim_rtl_frame_s",
                                             "sim_rtl_frame_cpu_s"};

}  // namespace

// {"median", "min", "max", "runs"}
json summary(const std::vector<double>& v) {
  if (v.empty()) return nullptr;
  return {{"median", median(v)},
          {"min", *std::min_element(v.begin(), v.end())},
          {"max", *std::max_element(v.begin(), v.end())},
          {"runs", v}};
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

double geomean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += std::log(x);
  return v.empty() ? 0 : std::exp(s / v.size());
}

void add_figures(const Repetition& m, unsigned threads, Figures* figures) {
  const json &ours = m.ours, &emb = m.embree, &emb0 = m.embree_mxcsr_default, &pred = m.predict,
             &cos = m.cosim, &cos_full = m.cosim_full_rate;
  Figures& r = *figures;
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
    r["predict_vs_embree_mxcsr_default"].push_back(rate(pred["one_core"]) /
                                                   rate_of(t0, {"primary", "shadow", "ao"}));
  }
  if (to["shadow"]["rays"].get<uint64_t>() + to["ao"]["rays"].get<uint64_t>() > 0)
    r["anyhit_vs_embree"].push_back(rate_of(to, {"shadow", "ao"}) / rate_of(te, {"shadow", "ao"}));
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
  if (!cos.is_null()) {  // null: the RTL cannot represent the scene's BVH (bench_scene says why)
    r["cosim_rays_per_s"].push_back(cos["rays"].get<double>() / cos["seconds"].get<double>());
    r["cosim_cycles_per_s"].push_back(cos["cycles"].get<double>() / cos["seconds"].get<double>());
    r["cosim_full_rate_rays_per_s"].push_back(cos_full["rays"].get<double>() /
                                              cos_full["seconds"].get<double>());
  }
  // hrpp simulate's AO frame (absent without --hrpp): simulated rays per second of the preset's
  // run and of the baseline's (each run's wall clock), the whole command's seconds (its wall
  // clock) and CPU seconds (wait4).
  for (const auto& [sim, pre] : {std::pair{&m.simulate, "sim_"}, {&m.simulate_rtl, "sim_rtl_"}}) {
    if (sim->is_null()) continue;
    const std::string p = pre;
    r[p + "rays_per_s"].push_back((*sim)["rays_per_second"].get<double>());
    r[p + "baseline_rays_per_s"].push_back((*sim)["baseline_rays_per_second"].get<double>());
    r[p + "frame_s"].push_back((*sim)["seconds"].get<double>());
    r[p + "frame_cpu_s"].push_back((*sim)["cpu_seconds"].get<double>());
  }
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
}

json scene_report(const Figures& r, const std::map<std::string, double>& rss,
                  const Repetition& last, Figures* for_geomean, Figures* rss_geomean) {
  const json &last_ours = last.ours, &last_embree = last.embree, &last_pred = last.predict,
             &last_cosim = last.cosim;
  json js;
  for (auto& [k, v] : r) js[k] = summary(v);
  // The headline figures: the medians; the full summaries beside them.
  json flat;
  for (const auto& k : kHeadlineKeys)
    if (js.contains(k)) {
      flat[k] = js[k]["median"];
      (*for_geomean)[k].push_back(js[k]["median"].get<double>());
    }
  json rssj;
  for (auto& [k, v] : rss) {
    rssj[k] = v;
    (*rss_geomean)[k].push_back(v);
  }
  flat["peak_rss_mb"] = rssj;
  flat["summary"] = js;
  flat["rays"] = {{"primary", last_ours["trace"]["primary"]["rays"]},
                  {"shadow", last_ours["trace"]["shadow"]["rays"]},
                  {"ao", last_ours["trace"]["ao"]["rays"]}};
  flat["triangles"] = last_ours["triangles"];
  flat["embree"] = last_embree["description"];
  flat["cosim"] = last_cosim;
  if (!last.simulate.is_null()) flat["simulate"] = last.simulate;
  if (!last.simulate_rtl.is_null()) flat["simulate_rtl"] = last.simulate_rtl;
  flat["predict_skipped_interior_fraction"] = last_pred["one_core"]["skipped_interior_fraction"];
  return flat;
}

void print_scene_line(const std::string& name, const json& flat,
                      const std::map<std::string, double>& rss, unsigned threads) {
  const json& js = flat["summary"];
  std::printf(
      "%-13s tris %8llu  build %s  primary %s  any-hit %s  predict %s  | %u threads: "
      "primary %s  any-hit %s  predict scaling %s | cosim %.0f rays/s  RSS MB ours %.0f "
      "embree %.0f predict %.0f cosim %.0f\n",
      name.c_str(), (unsigned long long)flat["triangles"].get<uint64_t>(),
      fmt_ratio(js["build_vs_embree"]).c_str(), fmt_ratio(js["traversal_vs_embree"]).c_str(),
      fmt_ratio(js.value("anyhit_vs_embree", json())).c_str(),
      fmt_ratio(js["predict_vs_embree"]).c_str(), threads,
      fmt_ratio(js.value("traversal_vs_embree_mt", json())).c_str(),
      fmt_ratio(js.value("anyhit_vs_embree_mt", json())).c_str(),
      fmt_ratio(js.value("predict_scaling", json())).c_str(),
      js.contains("cosim_rays_per_s") ? js["cosim_rays_per_s"]["median"].get<double>() : 0.0,
      rss.at("ours"), rss.at("embree"), rss.at("predict"),
      rss.count("cosim") ? rss.at("cosim") : 0.0);
  if (flat.contains("rtl_skipped"))
    std::printf("%-13s %s\n", "", flat["rtl_skipped"].get<std::string>().c_str());
  if (js.contains("sim_rays_per_s") && js.contains("sim_rtl_rays_per_s"))
    std::printf(
        "%-13s simulate AO 256x256 on mobile: %s rays/s (no predictor %s), frame %s s (CPU %s s) "
        "| --rtl: %s rays/s, frame %s s (CPU %s s), %llu mismatches\n",
        "", fmt_ratio(js["sim_rays_per_s"], "%.0f").c_str(),
        fmt_ratio(js["sim_baseline_rays_per_s"], "%.0f").c_str(),
        fmt_ratio(js["sim_frame_s"]).c_str(), fmt_ratio(js["sim_frame_cpu_s"]).c_str(),
        fmt_ratio(js["sim_rtl_rays_per_s"], "%.0f").c_str(),
        fmt_ratio(js["sim_rtl_frame_s"]).c_str(), fmt_ratio(js["sim_rtl_frame_cpu_s"]).c_str(),
        (unsigned long long)flat["simulate_rtl"]["rtl_mismatches"].get<uint64_t>());
  std::fflush(stdout);
}

json geomean_report(const Figures& for_geomean, const Figures& rss_geomean, size_t scenes) {
  json gm;
  for (auto& [k, v] : for_geomean) gm[k] = geomean(v);
  for (auto& [k, v] : rss_geomean) gm["peak_rss_mb"][k] = geomean(v);
  std::printf("geometric mean over %zu scenes (ratios: ours / Embree, above 1 = ours faster):\n",
              scenes);
  for (auto it = gm.begin(); it != gm.end(); ++it)
    if (it->is_number()) std::printf("  %-34s %.3f\n", it.key().c_str(), it->get<double>());
  return gm;
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
    char c[112], lo[32], hi[32], med[32];  // c holds "med (lo-hi)" whole
    std::snprintf(med, sizeof med, f, sm[key]["median"].get<double>());
    std::snprintf(lo, sizeof lo, f, sm[key]["min"].get<double>());
    std::snprintf(hi, sizeof hi, f, sm[key]["max"].get<double>());
    std::snprintf(c, sizeof c, "%s (%s-%s)", med, lo, hi);
    return c;
  };
  std::snprintf(
      b, sizeof b,
      "| scene | triangles | rays | build | primary | any-hit | predictor | primary, %u thr. "
      "| any-hit, %u thr. | predictor scaling, %u thr. | co-sim rays/s | co-sim cycles/s "
      "| simulated rays/s | simulated rays/s, `--rtl` | AO frame s | AO frame s, `--rtl` "
      "| peak RSS MB ours / Embree / predictor / co-sim |\n",
      th, th, th);
  md += b;
  md += "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (auto it = out["scenes"].begin(); it != out["scenes"].end(); ++it) {
    const json& sc = *it;
    const json& sm = sc["summary"];
    const json& rss = sc["peak_rss_mb"];
    const uint64_t rays = sc["rays"]["primary"].get<uint64_t>() +
                          sc["rays"]["shadow"].get<uint64_t>() + sc["rays"]["ao"].get<uint64_t>();
    std::snprintf(b, sizeof b,
                  "| %s | %llu | %llu | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s "
                  "| %s | %.0f / %.0f / %.0f / %.0f |\n",
                  it.key().c_str(), (unsigned long long)sc["triangles"].get<uint64_t>(),
                  (unsigned long long)rays, cell(sm, "build_vs_embree").c_str(),
                  cell(sm, "traversal_vs_embree").c_str(), cell(sm, "anyhit_vs_embree").c_str(),
                  cell(sm, "predict_vs_embree").c_str(), cell(sm, "traversal_vs_embree_mt").c_str(),
                  cell(sm, "anyhit_vs_embree_mt").c_str(), cell(sm, "predict_scaling").c_str(),
                  cell(sm, "cosim_rays_per_s", "%.0f").c_str(),
                  cell(sm, "cosim_cycles_per_s", "%.0f").c_str(),
                  cell(sm, "sim_rays_per_s", "%.0f").c_str(),
                  cell(sm, "sim_rtl_rays_per_s", "%.0f").c_str(), cell(sm, "sim_frame_s").c_str(),
                  cell(sm, "sim_rtl_frame_s").c_str(), rss.value("ours", 0.0),
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
  std::snprintf(
      b, sizeof b,
      "| **geometric mean** | | | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s "
      "| %s | |\n",
      gv("build_vs_embree").c_str(), gv("traversal_vs_embree").c_str(),
      gv("anyhit_vs_embree").c_str(), gv("predict_vs_embree").c_str(),
      gv("traversal_vs_embree_mt").c_str(), gv("anyhit_vs_embree_mt").c_str(),
      gv("predict_scaling").c_str(), gv("cosim_rays_per_s", "%.0f").c_str(),
      gv("cosim_cycles_per_s", "%.0f").c_str(), gv("sim_rays_per_s", "%.0f").c_str(),
      gv("sim_rtl_rays_per_s", "%.0f").c_str(), gv("sim_frame_s").c_str(),
      gv("sim_rtl_frame_s").c_str());
  md += b;
  // Scenes without the co-simulation and the simulator's runs, and why.
  for (auto it = out["scenes"].begin(); it != out["scenes"].end(); ++it)
    if (it->contains("rtl_skipped"))
      md += "\n" + it.key() + ": " + (*it)["rtl_skipped"].get<std::string>() + ".\n";
  std::snprintf(
      b, sizeof b,
      "\nAgainst Embree without FTZ/DAZ (geometric means): primary %s, any-hit %s, "
      "predictor %s. Predictor: one thread's CPU time over %u threads': %s. Co-simulation "
      "at full rate (every handshake ready, one-cycle engine): %s rays/s.\n",
      gv("traversal_vs_embree_mxcsr_default").c_str(), gv("anyhit_vs_embree_mxcsr_default").c_str(),
      gv("predict_vs_embree_mxcsr_default").c_str(), th, gv("predict_mt_cpu_efficiency").c_str(),
      gv("cosim_full_rate_rays_per_s", "%.0f").c_str());
  md += b;
  if (g.contains("sim_rays_per_s") && g.contains("sim_rtl_rays_per_s")) {
    std::string args;  // hrpp simulate's options after the scene
    if (out["settings"].contains("simulate"))
      for (const json& x : out["settings"]["simulate"])
        args.append(args.empty() ? "" : " ").append(x.get<std::string>());
    std::snprintf(
        b, sizeof b,
        "\n`hrpp simulate` (one core), a 256x256 AO frame as MICRO 2021 on `mobile` with the "
        "RTL's primary predictor (`%s`; geometric means): the predictor's run simulates %s rays/s "
        "(the run with no predictor %s), the whole command takes %s s (%s s of CPU); with "
        "`--rtl` (the Verilated RTL in every unit, compared with the cycle model on every cycle: "
        "0 mismatches on every scene) %s rays/s (no predictor %s), %s s (%s s of CPU).\n",
        args.c_str(), gv("sim_rays_per_s", "%.0f").c_str(),
        gv("sim_baseline_rays_per_s", "%.0f").c_str(), gv("sim_frame_s").c_str(),
        gv("sim_frame_cpu_s").c_str(), gv("sim_rtl_rays_per_s", "%.0f").c_str(),
        gv("sim_rtl_baseline_rays_per_s", "%.0f").c_str(), gv("sim_rtl_frame_s").c_str(),
        gv("sim_rtl_frame_cpu_s").c_str());
    md += b;
  }
  if (out.contains("memory_vs_rays")) {
    md += "\nMemory against workload size (`hrpp predict`, the RTL's `primary` table on 8 cores): ";
    for (const json& m : out["memory_vs_rays"]) {
      std::snprintf(b, sizeof b, "%s%s, %llu rays: %.0f MB",
                    m == out["memory_vs_rays"][0] ? "" : "; ", m["res"].get<std::string>().c_str(),
                    (unsigned long long)m["rays"].get<uint64_t>(), m["peak_rss_mb"].get<double>());
      md += b;
    }
    md += ".\n";
  }
  if (out.contains("big_scene")) {
    md +=
        "\n| procedural scene | triangles | build s | primary rays/s (1 thread) | peak RSS MB |\n"
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

int write_report(const std::string& path, const json& out) {
  const std::string md_path = (fs::path(path).replace_extension(".md")).string();
  try {
    hrpp::write_file_atomic(path, out.dump(2) + "\n");
    hrpp::write_file_atomic(md_path, markdown(out));
  } catch (const hrpp::AtomicFileError& e) {
    std::fprintf(stderr, "hrpp_bench: %s\n", e.what());
    return 2;
  }
  std::printf("wrote %s and %s\n", path.c_str(), md_path.c_str());
  return 0;
}

}  // namespace hrpp::bench
