// hrpp exactness: every ray kind of the studies' workloads through our walk and through Embree,
// as closest-hit and any-hit queries; disagreements resolved by the referee, walk misses counted
// (hrpp/reference/exactness.h, docs/bvh.md "Exactness check").
#include "hrpp/reference/exactness.h"

#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "common.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"
#include "hrpp/util/progress.h"
#include "subcommands.h"

namespace hrpp::cli {
namespace {

struct ExactnessArgs {
  std::string scene, json_path, misses_path, replay_path, res, kinds = "all", bvh = "sah";
  uint64_t min_rays = 10'000'000, seed = 1, max_samples = 0;
  int spp = 0;
  size_t max_examples = 16, max_printed = 20;
  std::string config = kEmbreeReferenceConfig;
};

/// --kinds: "all" or a comma-separated list of study kinds.
bool parse_kinds(const std::string& spec, std::array<bool, kNumStudyKinds>* on) {
  on->fill(spec == "all");
  if (spec == "all") return true;
  size_t p = 0;
  while (p <= spec.size()) {
    const size_t c = std::min(spec.find(',', p), spec.size());
    StudyKind k;
    if (!parse_study_kind(spec.substr(p, c - p), &k)) {
      std::fprintf(stderr,
                   "hrpp exactness: --kinds: unknown kind '%s' (all, or a comma-separated list "
                   "of primary, shadow, ao, ao-short, reflection, refraction, diffuse)\n",
                   spec.substr(p, c - p).c_str());
      return false;
    }
    (*on)[static_cast<int>(k)] = true;
    p = c + 1;
  }
  return true;
}

/// The rays of a walk-miss file (WalkMiss::line, one per line; '#' starts a comment).
bool read_replay(const std::string& path, std::vector<std::pair<Ray, StudyKind>>* rays) {
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "hrpp exactness: --replay %s: cannot read it\n", path.c_str());
    return false;
  }
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line[0] == '#') continue;
    WalkMiss m;
    if (!WalkMiss::parse(line, &m)) {
      std::fprintf(stderr,
                   "hrpp exactness: --replay %s:%d: not a walk-miss line (KIND QUERY org X Y Z "
                   "dir X Y Z tnear T tfar T ...)\n",
                   path.c_str(), n);
      return false;
    }
    rays->push_back({m.ray, m.kind});
  }
  return true;
}

void print_report(const ExactnessResult& r, const ExactnessArgs& a, const Bvh& bvh) {
  std::printf("exactness %s: %zu triangles; %s\n", r.scene.c_str(), r.triangles, r.embree.c_str());
  std::printf("%s", bvh_line(bvh).c_str());
  for (const FrameInfo& f : r.frames)
    std::printf("  frame: seed %llu, %dx%d, %d spp, effects %s: %llu camera samples\n",
                (unsigned long long)f.seed, f.width, f.height, f.spp, f.effects.c_str(),
                (unsigned long long)f.camera_samples);
  if (r.replayed)
    std::printf("  replayed: %llu rays of %s\n", (unsigned long long)r.replayed,
                a.replay_path.c_str());
  std::printf("  %-10s %-7s %10s %10s %10s %7s %7s %8s %6s %6s %6s %6s %8s %6s %6s\n", "kind",
              "query", "rays", "compared", "hits", "hit-dis", "prim-dis", "t-dis", "ours", "embree",
              "ties", "grazes", "rounding", "brute", "misses");
  auto row = [](const char* name, const KindCounts& k) {
    for (int q = 0; q < 2; ++q) {
      const QueryCounts& c = k.query[q];
      const std::string rays = q ? "" : std::to_string(k.rays);
      std::printf(
          "  %-10s %-7s %10s %10llu %10llu %7llu %7llu %8llu %6llu %6llu %6llu %6llu %8llu %6llu "
          "%6llu\n",
          q ? "" : name, std::string(query_name(Query(q))).c_str(), rays.c_str(),
          (unsigned long long)c.compared, (unsigned long long)c.hits,
          (unsigned long long)c.hit_disagree, (unsigned long long)c.prim_disagree,
          (unsigned long long)c.t_disagree, (unsigned long long)c.ours_right,
          (unsigned long long)c.embree_right, (unsigned long long)c.ties,
          (unsigned long long)c.grazes, (unsigned long long)c.rounding,
          (unsigned long long)c.brute_forced, (unsigned long long)c.walk_misses);
    }
  };
  for (int k = 0; k < kNumStudyKinds; ++k)
    if (r.asked[k]) row(std::string(study_kind_name(StudyKind(k))).c_str(), r.by_kind[k]);
  row("all", r.total());
  std::printf(
      "  (hit-dis / prim-dis / t-dis: disagreements with Embree on hit or miss, on the primitive, "
      "on t alone; ours / embree / ties / grazes / rounding: how the referee resolved them; brute: "
      "rays brute-forced; misses: walk misses, our walk farther than our own triangle test "
      "allows)\n");
  for (int k = 0; k < kNumStudyKinds; ++k)
    if (r.asked[k] && !r.note[k].empty())
      std::printf("  %s: %s\n", std::string(study_kind_name(StudyKind(k))).c_str(),
                  r.note[k].c_str());
  const size_t shown = std::min(r.walk_misses.size(), a.max_printed);
  for (size_t i = 0; i < shown; ++i)
    std::printf("  walk miss: %s\n", r.walk_misses[i].line().c_str());
  if (shown < r.walk_misses.size())
    std::printf("  ... %zu more walk misses (all in --json / --misses)\n",
                r.walk_misses.size() - shown);
  for (const std::string& e : r.examples) std::printf("  %s\n", e.c_str());
  if (r.seconds > 0) std::printf("  %.1f s\n", r.seconds);
  if (r.passed()) {
    std::printf("  PASS: no walk miss; every disagreement with Embree a tie or a graze\n");
  } else {
    std::printf("  FAIL: %s\n", r.failure().c_str());
    std::fprintf(stderr, "hrpp exactness: FAIL: %s\n", r.failure().c_str());
  }
}

int cmd_exactness(const ExactnessArgs& a) {
  if (!a.json_path.empty() &&
      !check_output_path("exactness", "--json", a.json_path, OutputKind::kJson))
    return 2;
  if (!a.misses_path.empty() &&
      !check_output_path("exactness", "--misses", a.misses_path, OutputKind::kFile))
    return 2;
  ExactnessOptions opt;
  if (!parse_kinds(a.kinds, &opt.kinds)) return 2;
  if (!a.res.empty()) {
    uint32_t w, h;
    if (!parse_wxh(a.res, &w, &h)) {
      std::fprintf(stderr,
                   "hrpp exactness: --res must be WIDTHxHEIGHT (e.g. 1024x1024), got '%s'\n",
                   a.res.c_str());
      return 2;
    }
    opt.width = int(w);
    opt.height = int(h);
  }
  std::vector<std::pair<Ray, StudyKind>> replay;
  if (!a.replay_path.empty() && !read_replay(a.replay_path, &replay)) return 2;
  opt.min_rays = a.min_rays;
  opt.seed = a.seed;
  opt.spp = a.spp;
  opt.max_samples = a.max_samples;
  opt.embree_config = a.config;
  opt.max_examples = a.max_examples;

  Scene s = load_scene(a.scene);
  Bvh bvh = build_bvh(s.triangles, bvh_build_options(a.bvh));
  // Walk misses go to --misses as they are found: a long run that is stopped keeps them.
  std::FILE* misses = nullptr;
  if (!a.misses_path.empty()) {
    misses = std::fopen(a.misses_path.c_str(), "w");
    if (!misses) {
      std::fprintf(stderr, "hrpp exactness: --misses %s: cannot write it\n", a.misses_path.c_str());
      return 2;
    }
    std::fprintf(misses,
                 "# hrpp exactness %s: walk misses, one per line (--replay reads them): KIND QUERY "
                 "org X Y Z dir X Y Z tnear T tfar T ours PRIM T closer PRIM T referee T_OURS "
                 "T_CLOSER confirmed|unconfirmed (the ray's floats and the hits' t in hex; "
                 "referee: the double-precision t of our triangle and of the closer one)\n",
                 s.path.c_str());
    std::fflush(misses);
  }
  std::unique_ptr<Progress> progress;
  opt.progress = [&](uint64_t done, uint64_t total) {
    if (!progress)
      progress = std::make_unique<Progress>(stderr, "exactness " + s.name, "rays", total);
    progress->update(done);
  };
  opt.on_walk_miss = [&](const WalkMiss& m) {
    if (progress) progress->finish();
    std::fprintf(stderr, "hrpp exactness: walk miss: %s\n", m.line().c_str());
    if (misses) {
      std::fprintf(misses, "%s\n", m.line().c_str());
      std::fflush(misses);
    }
  };

  ExactnessResult r;
  if (!replay.empty()) {
    EmbreeScene embree(s.triangles, opt.embree_config, /*robust=*/true);
    check_rays(s, bvh, embree, replay, opt, &r);
  }
  if (opt.min_rays > 0) {
    ExactnessResult g = check_exactness(s, bvh, opt);
    for (int k = 0; k < kNumStudyKinds; ++k) {
      g.by_kind[k] += r.by_kind[k];
      g.asked[k] = g.asked[k] || r.asked[k];
    }
    g.walk_misses.insert(g.walk_misses.begin(), r.walk_misses.begin(), r.walk_misses.end());
    g.examples.insert(g.examples.begin(), r.examples.begin(), r.examples.end());
    g.replayed = r.replayed;
    r = std::move(g);
  } else {
    r.scene = s.path;
    r.triangles = s.triangles.size();
    r.embree = EmbreeScene(s.triangles, opt.embree_config, true).description();
  }
  progress.reset();
  if (misses) std::fclose(misses);
  print_report(r, a, bvh);
  if (!a.json_path.empty()) {
    nlohmann::json j = {{"tool", tool_json()}};
    j.update(r.to_json());
    j["bvh"] = bvh_json(bvh);
    if (!write_json_file(a.json_path, j)) return 2;
  }
  return r.passed() ? 0 : 1;
}

}  // namespace

Subcommand add_exactness(CLI::App& app) {
  auto a = std::make_shared<ExactnessArgs>();
  auto* ex = app.add_subcommand(
      "exactness",
      "Every ray kind of the studies' workloads through our walk and Embree, as closest-hit and "
      "any-hit queries: disagreements resolved by the referee, walk misses counted (exit 1 on "
      "any)");
  ex->add_option("scene", a->scene, "glTF scene (.glb or .gltf)")->required();
  ex->add_option("--min-rays", a->min_rays,
                 "rays of every kind to check (frames are generated until each kind has them; 0: "
                 "only --replay)")
      ->capture_default_str();
  ex->add_option("--kinds", a->kinds,
                 "'all' or a comma-separated list of primary, shadow, ao (MICRO 2021: unbounded), "
                 "ao-short (5% of the scene diagonal), reflection, refraction, diffuse")
      ->capture_default_str();
  ex->add_option("--seed", a->seed, "seed of the first frame (frame f uses SEED + f)")
      ->capture_default_str();
  ex->add_option("--res", a->res,
                 "frame resolution WxH (default: about min(--min-rays, 2^20) camera samples at the "
                 "camera's aspect ratio)");
  ex->add_option("--spp", a->spp, "frame samples per pixel (default 1)")
      ->check(CLI::Range(1, 4096));
  ex->add_option("--max-samples", a->max_samples,
                 "camera samples at most (default 16 x --min-rays): kinds still short are "
                 "reported as such");
  ex->add_option("--replay", a->replay_path,
                 "also check the rays of this walk-miss file (the lines --misses writes)");
  ex->add_option("--misses", a->misses_path,
                 "write every walk miss to this file as it is found, one line each, floats in hex");
  ex->add_option("--max-examples", a->max_examples, "other failing disagreements to describe")
      ->capture_default_str();
  ex->add_option("--embree-config", a->config, "Embree device configuration string")
      ->capture_default_str();
  add_bvh_option(ex, a->bvh);
  ex->add_option("--json", a->json_path,
                 "write the results as JSON to this file ('-': to standard output, the text report "
                 "then to standard error)");
  return {ex, [a] { return cmd_exactness(*a); }};
}

}  // namespace hrpp::cli
