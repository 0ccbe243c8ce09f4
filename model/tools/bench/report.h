// hrpp_bench: the report. The figures of each repetition (ratios within a repetition, ours /
// Embree), their median, min and max over the repetitions, the geometric means over the scenes,
// the lines on stdout, out/bench.json and the table of docs/results.md ("Performance"),
// out/bench.md.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace hrpp::bench {

// The measurements of one repetition on one scene, each the JSON of its process (children.h;
// cosim: tb_hrpp's parity and timing lines; simulate, simulate_rtl: hrpp simulate's AO frame with
// the cycle model and with --rtl, null without --hrpp).
struct Repetition {
  nlohmann::json ours, embree, embree_mxcsr_default, predict, cosim, cosim_full_rate, simulate,
      simulate_rtl;
};

// A figure's value in each repetition (or each scene), by name.
using Figures = std::map<std::string, std::vector<double>>;

// {"median", "min", "max", "runs"}
nlohmann::json summary(const std::vector<double>& v);
double rate(const nlohmann::json& m);
// Rays per second over several kinds (total rays / total seconds).
double rate_of(const nlohmann::json& t, std::initializer_list<const char*> kinds);
double geomean(const std::vector<double>& v);

// Appends the figures of one repetition (ratios within it, absolute rates) to *r.
void add_figures(const Repetition& m, unsigned threads, Figures* r);

// A scene's entry of the report from its figures, its peak RSS per measurement (MB, the most over
// the repetitions) and its last repetition; the headline medians and the peak RSS also go to
// *for_geomean and *rss_geomean.
nlohmann::json scene_report(const Figures& r, const std::map<std::string, double>& rss,
                            const Repetition& last, Figures* for_geomean, Figures* rss_geomean);
// The scene's line on stdout.
void print_scene_line(const std::string& name, const nlohmann::json& flat,
                      const std::map<std::string, double>& rss, unsigned threads);

// The geometric means over the scenes (the report's "geomean"), printed.
nlohmann::json geomean_report(const Figures& for_geomean, const Figures& rss_geomean,
                              size_t scenes);

// The table of docs/results.md ("Performance"), from the report.
std::string markdown(const nlohmann::json& out);

// Writes the report to path and its markdown beside it (.md); 2 when it cannot.
int write_report(const std::string& path, const nlohmann::json& out);

}  // namespace hrpp::bench
