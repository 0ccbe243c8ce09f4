// hrpp: the project's command-line tool. `hrpp --help` and `hrpp SUBCOMMAND --help` list options.
//
// Exit codes: 0 success; 1 a check failed (e.g. check-embree found mismatches); 2 bad input
// (bad option, unreadable or malformed scene).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "hrpp/bvh.h"
#include "hrpp/crosscheck.h"
#include "hrpp/predictor.h"
#include "hrpp/scene.h"
#include "hrpp/workload.h"

#include <bit>
#include <chrono>

namespace {

using namespace hrpp;

void print_vec(const char* label, const Vec3& v) {
  std::printf("%s(%g, %g, %g)\n", label, v.x, v.y, v.z);
}

bool write_json_file(const std::string& path, const nlohmann::json& j) {
  // Written to a temporary name and renamed, so a killed run never leaves a partial file.
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) {
      std::fprintf(stderr, "hrpp: cannot write %s\n", tmp.c_str());
      return false;
    }
    out << j.dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "hrpp: error writing %s\n", tmp.c_str());
      return false;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::fprintf(stderr, "hrpp: cannot rename %s to %s\n", tmp.c_str(), path.c_str());
    return false;
  }
  return true;
}

nlohmann::json bvh_json(const Bvh& bvh) {
  const BvhStats& s = bvh.stats;
  return {{"nodes", s.nodes},
          {"interior", s.interior},
          {"leaves", s.leaves},
          {"max_depth", s.max_depth},
          {"mean_leaf_depth", s.mean_leaf_depth},
          {"leaf_size_histogram", s.leaf_size_histogram},
          {"sah_cost", s.sah_cost},
          {"build_seconds", s.build_seconds},
          {"max_leaf_size", bvh.options.max_leaf_size},
          {"memory_bytes", bvh.memory_bytes()}};
}

int cmd_info(const std::string& path, uint32_t leaf_size, const std::string& json_path) {
  Scene s = load_scene(path);
  BvhBuildOptions bo;
  bo.max_leaf_size = leaf_size;
  Bvh bvh = build_bvh(s.triangles, bo);
  std::printf("scene      %s\n", s.path.c_str());
  std::printf("triangles  %zu (%u degenerate: kept, never hit)\n", s.triangles.size(),
              s.degenerate_triangles);
  std::printf("meshes     %zu\n", s.meshes.size());
  print_vec("bounds     min ", s.bounds.lo);
  print_vec("           max ", s.bounds.hi);
  const Camera& c = s.camera;
  std::printf("camera     %s\n", c.source.c_str());
  print_vec("           eye ", c.eye);
  print_vec("           target ", c.target);
  print_vec("           up ", c.up);
  std::printf("           fov_y %.4g deg, aspect %.4g, image %dx%d\n", c.fov_y_deg, c.aspect,
              c.width, c.height);
  std::printf("lights     %zu punctual, %zu emissive triangles\n", s.lights.size(),
              s.emissive_triangles().size());
  for (const Light& l : s.lights) {
    std::printf("           %-12s %-11s intensity %g colour (%g, %g, %g)", l.name.c_str(),
                light_type_name(l.type), l.intensity, l.color.x, l.color.y, l.color.z);
    if (l.type == Light::Type::kDirectional)
      std::printf(" direction (%g, %g, %g)\n", l.direction.x, l.direction.y, l.direction.z);
    else
      std::printf(" position (%g, %g, %g)\n", l.position.x, l.position.y, l.position.z);
  }
  std::printf("materials  %zu\n", s.materials.size());
  std::vector<uint32_t> tri_count(s.materials.size(), 0);
  for (uint32_t m : s.tri_material) tri_count[m]++;
  for (size_t i = 0; i < s.materials.size(); ++i) {
    const Material& m = s.materials[i];
    std::printf("           %-18s base (%.3g, %.3g, %.3g) metallic %.3g roughness %.3g", m.name.c_str(),
                m.base_color.r, m.base_color.g, m.base_color.b, m.metallic, m.roughness);
    if (m.is_emissive())
      std::printf(" emission (%.4g, %.4g, %.4g)", m.emission().x, m.emission().y, m.emission().z);
    if (m.transmission > 0) std::printf(" transmission %.3g ior %.3g", m.transmission, m.ior);
    std::printf(" %s, %u triangles\n", m.double_sided ? "double-sided" : "one-sided", tri_count[i]);
  }
  const BvhStats& st = bvh.stats;
  std::printf("bvh        binned SAH, %u bins, max leaf %u: %u nodes (%u interior, %u leaves), "
              "depth max %u mean-leaf %.1f, SAH cost %.2f, %.1f MB, built in %.3f s\n",
              bvh.options.bins, bvh.options.max_leaf_size, st.nodes, st.interior, st.leaves,
              st.max_depth, st.mean_leaf_depth, st.sah_cost, bvh.memory_bytes() / 1e6,
              st.build_seconds);
  std::printf("           leaf sizes:");
  for (size_t k = 1; k < st.leaf_size_histogram.size(); ++k)
    std::printf(" %zu:%u", k, st.leaf_size_histogram[k]);
  std::printf("\n");
  if (!json_path.empty()) {
    nlohmann::json j = {{"scene", s.path},
                        {"triangles", s.triangles.size()},
                        {"degenerate_triangles", s.degenerate_triangles},
                        {"bounds", {{"min", {s.bounds.lo.x, s.bounds.lo.y, s.bounds.lo.z}},
                                    {"max", {s.bounds.hi.x, s.bounds.hi.y, s.bounds.hi.z}}}},
                        {"camera", c.source},
                        {"lights", s.lights.size()},
                        {"emissive_triangles", s.emissive_triangles().size()},
                        {"materials", s.materials.size()},
                        {"bvh", bvh_json(bvh)}};
    if (!write_json_file(json_path, j)) return 2;
  }
  return 0;
}

int cmd_check_embree(const std::string& path, uint64_t rays, const std::string& kind,
                     uint64_t seed, const std::string& config, const std::string& json_path) {
  Scene s = load_scene(path);
  Bvh bvh = build_bvh(s.triangles);
  CrossCheckOptions opt;
  opt.rays = rays;
  opt.seed = seed;
  opt.embree_config = config;
  if (kind != "all") {
    RayKind k;
    parse_ray_kind(kind, &k);  // validated by CLI11
    opt.kinds = {k};
  }
  CrossCheckResult r = cross_check(s, bvh, opt);
  std::printf("check-embree %s: %s\n", s.path.c_str(), r.embree.c_str());
  std::printf("  %dx%d camera samples, %.2f s\n", r.width, r.height, r.seconds);
  std::printf("  %-8s %9s %8s %9s %13s %8s %7s %6s %6s %6s\n", "kind", "rays", "invalid",
              "hits", "hit-agreement", "hit-mis", "grazes", "t-mis", "p-mis", "ties");
  auto row = [](const char* name, const CrossCheckCounts& c) {
    std::printf("  %-8s %9llu %8llu %9llu %13.7f %8llu %7llu %6llu %6llu %6llu\n", name,
                (unsigned long long)c.rays, (unsigned long long)c.invalid_rays,
                (unsigned long long)c.hits, c.hit_agreement(),
                (unsigned long long)c.hit_mismatches, (unsigned long long)c.grazes,
                (unsigned long long)c.t_mismatches, (unsigned long long)c.prim_mismatches,
                (unsigned long long)c.ties);
  };
  for (int k = 0; k < kNumRayKinds; ++k)
    if (r.by_kind[k].rays) row(std::string(ray_kind_name(RayKind(k))).c_str(), r.by_kind[k]);
  row("all", r.total);
  for (const auto& e : r.examples) std::printf("  %s\n", e.c_str());
  std::printf("  %s\n", r.passed() ? "PASS: our traversal agrees with Embree"
                                   : "FAIL: disagreements beyond genuine ties and grazes");
  if (!json_path.empty() && !write_json_file(json_path, r.to_json())) return 2;
  return r.passed() ? 0 : 1;
}


struct PredictArgs {
  std::string scene, json_path, hash = "faithful", table = "unbounded", mode = "closest-exact";
  std::string combine = "xor", res;
  int precision = 6, exp_bits = 3, origin_bits = 5, dir_bits = 3, spp = 1;
  uint32_t go_up = 0, nodes_per_entry = 1;
  int tag_bits = -1;
  uint64_t seed = 1;
  bool shadow = true, ao = true;
  float ao_distance = 0.f;
};

/// Parses "WxH" into two positive integers.
bool parse_wxh(const std::string& s, uint32_t* a, uint32_t* b) {
  size_t x = s.find('x');
  if (x == std::string::npos || x == 0 || x + 1 >= s.size()) return false;
  try {
    size_t p1, p2;
    unsigned long va = std::stoul(s.substr(0, x), &p1), vb = std::stoul(s.substr(x + 1), &p2);
    if (p1 != x || p2 != s.size() - x - 1 || va == 0 || vb == 0 || va > (1u << 24) ||
        vb > (1u << 24))
      return false;
    *a = static_cast<uint32_t>(va);
    *b = static_cast<uint32_t>(vb);
    return true;
  } catch (...) {
    return false;
  }
}

int cmd_predict(const PredictArgs& a) {
  PredictorConfig cfg;
  HashConfig& h = cfg.hash;
  h.variant = a.hash == "faithful" ? HashVariant::kFaithful : HashVariant::kImproved;
  h.precision = a.precision;
  h.exp_bits = a.exp_bits;
  h.origin_bits = a.origin_bits;
  h.dir_bits = a.dir_bits;
  h.combine = a.combine == "xor" ? CombineMode::kXor : CombineMode::kConcat;
  parse_predict_mode(a.mode, &cfg.mode);
  cfg.go_up = a.go_up;
  TableConfig& t = cfg.table;
  t.nodes_per_entry = a.nodes_per_entry;
  if (a.table == "unbounded") {
    t.unbounded = true;
    h.index_bits = 0;
  } else if (!parse_wxh(a.table, &t.sets, &t.ways)) {
    std::fprintf(stderr, "hrpp predict: --table must be 'unbounded' or SETSxWAYS (e.g. 256x4), got '%s'\n",
                 a.table.c_str());
    return 2;
  } else {
    if (!std::has_single_bit(t.sets)) {
      std::fprintf(stderr, "hrpp predict: --table %s: the number of sets must be a power of two\n",
                   a.table.c_str());
      return 2;
    }
    h.index_bits = std::countr_zero(t.sets);
  }
  uint32_t w = 0, hh = 0;
  if (!a.res.empty() && !parse_wxh(a.res, &w, &hh)) {
    std::fprintf(stderr, "hrpp predict: --res must be WIDTHxHEIGHT (e.g. 256x256), got '%s'\n",
                 a.res.c_str());
    return 2;
  }

  Scene scene = load_scene(a.scene);
  Bvh bvh = build_bvh(scene.triangles);
  h.origin_cell_exp = cell_exp_for(scene.bounds, h.origin_bits);
  t.node_bits = node_bits_for(bvh.nodes.size());
  t.key_bits = h.key_bits();
  t.tag_bits = t.unbounded ? 0 : h.tag_bits();
  if (a.tag_bits >= 0 && !t.unbounded) {
    if (a.tag_bits > h.tag_bits()) {
      std::fprintf(stderr, "hrpp predict: --tag-bits %d exceeds the full tag width %d (key %d bits, index %d bits)\n",
                   a.tag_bits, h.tag_bits(), h.key_bits(), h.index_bits);
      return 2;
    }
    t.tag_bits = a.tag_bits;
  }
  for (const std::string& err : {h.validate(), t.validate()})
    if (!err.empty()) {
      std::fprintf(stderr, "hrpp predict: %s\n", err.c_str());
      return 2;
    }
  WorkloadOptions wo;
  wo.width = static_cast<int>(w);
  wo.height = static_cast<int>(hh);
  wo.spp = a.spp;
  wo.seed = a.seed;
  wo.shadow = a.shadow;
  wo.ao = a.ao;
  wo.ao_distance = a.ao_distance;
  if (wo.width == 0) {
    wo.width = scene.camera.width;
    wo.height = scene.camera.height;
  }
  Predictor pred(bvh, cfg);
  const uint64_t primaries = uint64_t(wo.width) * wo.height * wo.spp;
  uint64_t done = 0;
  auto t0 = std::chrono::steady_clock::now();
  auto last = t0;
  generate_rays(scene, bvh, wo, [&](const RayRecord& r, const Hit*) {
    pred.process(r);
    if (r.kind != RayKind::kPrimary || (++done & 0xFFFF)) return;
    auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::seconds(2)) return;
    last = now;
    double secs = std::chrono::duration<double>(now - t0).count();
    std::fprintf(stderr, "predict: %5.1f%% of %llu camera samples, %.2f M rays/s\n",
                 100.0 * done / primaries, (unsigned long long)primaries,
                 pred.total().rays / secs / 1e6);
  });
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  nlohmann::json j = pred.to_json();
  j["scene"] = scene.path;
  j["resolution"] = {wo.width, wo.height};
  j["spp"] = wo.spp;
  j["seed"] = wo.seed;
  j["seconds"] = secs;

  const auto& c = j["config"];
  std::printf("predict %s: %dx%d, %d spp, hash %s (%s), key %d bits, table %s (K=%u, %u-bit node ids, "
              "%llu bytes, %llu entries used), go-up %u, mode %s\n",
              scene.path.c_str(), wo.width, wo.height, wo.spp, a.hash.c_str(),
              h.variant == HashVariant::kFaithful
                  ? ("P=" + std::to_string(h.precision) + " E=" + std::to_string(h.exp_bits) + " " + a.combine).c_str()
                  : ("origin " + std::to_string(h.origin_bits) + " bits, cell 2^" +
                     std::to_string(h.origin_cell_exp) + ", dir " + std::to_string(h.dir_bits) + " bits " + a.combine).c_str(),
              h.key_bits(), c["table"].get<std::string>().c_str(), t.nodes_per_entry, t.node_bits,
              (unsigned long long)pred.table().bytes(), (unsigned long long)pred.table().entries_used(),
              cfg.go_up, a.mode.c_str());
  std::printf("  %-8s %10s %8s %9s %9s %10s %10s %10s %10s %8s\n", "kind", "rays", "skipped",
              "precision", "recall", "TP", "FP", "FN", "TN", "wrong");
  auto row = [](const char* name, const PredictStats& s) {
    std::printf("  %-8s %10llu %7.2f%% %9.4f %9.4f %10llu %10llu %10llu %10llu %8llu\n", name,
                (unsigned long long)s.rays, 100 * s.skipped_interior_fraction(), s.precision(),
                s.recall(), (unsigned long long)s.true_positive,
                (unsigned long long)s.false_positive, (unsigned long long)s.false_negative,
                (unsigned long long)s.true_negative, (unsigned long long)s.wrong_results);
  };
  for (int k = 0; k < kNumRayKinds; ++k)
    if (pred.by_kind(RayKind(k)).rays)
      row(std::string(ray_kind_name(RayKind(k))).c_str(), pred.by_kind(RayKind(k)));
  row("all", pred.total());
  std::printf("  skipped = 1 - HRPP interior-node tests (wasted predicted tests included) / baseline; %.1f s, %.2f M rays/s\n",
              secs, pred.total().rays / secs / 1e6);
  if (pred.total().exact_mismatches) {
    std::fprintf(stderr, "hrpp predict: BUG: %llu rays answered differently from the baseline in an exact mode\n",
                 (unsigned long long)pred.total().exact_mismatches);
    return 1;
  }
  if (!a.json_path.empty() && !write_json_file(a.json_path, j)) return 2;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"HRPP: hash-based ray path prediction - golden model tool"};
  app.require_subcommand(1);

  std::string scene, json_path;
  uint32_t leaf_size = 4;
  auto* info = app.add_subcommand("info", "Print a scene's triangles, bounds, camera, lights, "
                                          "materials and BVH statistics");
  info->add_option("scene", scene, "glTF scene (.glb or .gltf)")->required();
  info->add_option("--leaf-size", leaf_size, "maximum triangles per BVH leaf")
      ->check(CLI::Range(1, 64));
  info->add_option("--json", json_path, "also write the summary as JSON to this file");

  uint64_t rays = 100000, seed = 1;
  std::string kind = "all", config = kEmbreeReferenceConfig;
  auto* ce = app.add_subcommand(
      "check-embree", "Trace the same rays with our BVH and with Embree 3 and compare them");
  ce->add_option("scene", scene, "glTF scene (.glb or .gltf)")->required();
  ce->add_option("--rays", rays, "number of camera samples (shadow and AO rays come on top)")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 32));
  ce->add_option("--kind", kind, "ray kinds to compare")
      ->check(CLI::IsMember({"primary", "shadow", "ao", "all"}));
  ce->add_option("--seed", seed, "random seed of the ray generator");
  ce->add_option("--embree-config", config, "Embree device configuration string");
  ce->add_option("--json", json_path, "write the results as JSON to this file");

  PredictArgs pa;
  auto* pr = app.add_subcommand("predict", "Run the HRPP predictor over a scene's rays and report "
                                           "skipped work, precision and recall");
  pr->add_option("scene", pa.scene, "glTF scene (.glb or .gltf)")->required();
  pr->add_option("--hash", pa.hash, "hash variant")->check(CLI::IsMember({"faithful", "improved"}));
  pr->add_option("--precision", pa.precision, "faithful hash: mantissa bits per component (P)")
      ->check(CLI::Range(1, 23));
  pr->add_option("--exp-bits", pa.exp_bits, "faithful hash: top exponent bits per component (E)")
      ->check(CLI::Range(0, 8));
  pr->add_option("--origin-bits", pa.origin_bits, "improved hash: bits per origin axis")
      ->check(CLI::Range(1, 16));
  pr->add_option("--dir-bits", pa.dir_bits, "improved hash: bits per direction component")
      ->check(CLI::Range(1, 16));
  pr->add_option("--combine", pa.combine, "how origin and direction fields combine")
      ->check(CLI::IsMember({"xor", "concat"}));
  pr->add_option("--go-up", pa.go_up, "store the hit leaf's ancestor this many levels up")
      ->check(CLI::Range(0u, 64u));
  pr->add_option("--table", pa.table, "'unbounded' or SETSxWAYS, e.g. 256x4");
  pr->add_option("--tag-bits", pa.tag_bits,
                 "stored tag bits (default: the full tag, so keys never alias; fewer bits save "
                 "storage and let keys of one set alias)")
      ->check(CLI::Range(0, 64));
  pr->add_option("--nodes-per-entry", pa.nodes_per_entry, "node ids per table entry (K)")
      ->check(CLI::Range(1, kMaxNodesPerEntry));
  pr->add_option("--mode", pa.mode, "how closest-hit rays use predictions")
      ->check(CLI::IsMember({"anyhit", "closest-exact", "closest-spec"}));
  pr->add_option("--res", pa.res, "image resolution WxH (default: the camera's)");
  pr->add_option("--spp", pa.spp, "samples per pixel")->check(CLI::Range(1, 4096));
  pr->add_option("--seed", pa.seed, "random seed of the ray generator");
  pr->add_flag("!--no-shadow", pa.shadow, "do not trace shadow rays");
  pr->add_flag("!--no-ao", pa.ao, "do not trace ambient-occlusion rays");
  pr->add_option("--ao-distance", pa.ao_distance, "AO ray length (default 5% of the scene diagonal)")
      ->check(CLI::NonNegativeNumber);
  pr->add_option("--json", pa.json_path, "write the report as JSON to this file");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (*info) return cmd_info(scene, leaf_size, json_path);
    if (*ce) return cmd_check_embree(scene, rays, kind, seed, config, json_path);
    if (*pr) return cmd_predict(pa);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "hrpp: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrpp: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
