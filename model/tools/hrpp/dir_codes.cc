// hrpp dir-codes: how many of a hash's direction codes unit directions use, and how evenly
// (docs/hash.md, "Direction codes used"): for each direction code asked for (improved grid or oct
// with b bits, micro21 with T theta bits), N directions uniformly distributed on the unit sphere
// (a fixed seed) plus every axis-aligned and diagonal direction are hashed; the report gives the
// codes available (2^field bits), the codes that occur, and the directions per occurring code
// (min, max and max / min: 1 would be equal solid angles).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common.h"
#include "hrpp/predictor/hash.h"
#include "hrpp/util/rng.h"
#include "subcommands.h"

namespace hrpp::cli {
namespace {

/// One direction code: "grid:B", "oct:B" or "micro21:T".
struct CodeSpec {
  std::string kind;  // grid | oct | micro21
  int bits = 0;
  std::string name() const { return kind + ":" + std::to_string(bits); }
  int field_bits() const {
    return kind == "grid" ? 3 * bits : kind == "oct" ? 2 * bits : 2 * bits + 1;
  }
  uint32_t code(const std::array<float, 3>& d) const {
    const std::array<uint32_t, 3> b = {std::bit_cast<uint32_t>(d[0]), std::bit_cast<uint32_t>(d[1]),
                                       std::bit_cast<uint32_t>(d[2])};
    if (kind == "oct") return oct_dir_field(b, bits);
    if (kind == "micro21") return micro21_dir_field(d, bits);
    // The improved hash's direction field z | y | x (docs/hash.md, step 3).
    return (grid_dir_field(b[2], bits) << (2 * bits)) | (grid_dir_field(b[1], bits) << bits) |
           grid_dir_field(b[0], bits);
  }
};

/// Parses "grid:B" (B = 1..6 here: 2^18 codes at most), "oct:B" (1..8) or "micro21:T" (1..8).
std::string parse_spec(const std::string& s, CodeSpec* c) {
  const size_t colon = s.find(':');
  const std::string kind = s.substr(0, colon);
  if (colon == std::string::npos || (kind != "grid" && kind != "oct" && kind != "micro21"))
    return "--code " + s + ": expected grid:B, oct:B or micro21:T (e.g. oct:3)";
  int b = 0;
  try {
    size_t used = 0;
    b = std::stoi(s.substr(colon + 1), &used);
    if (used != s.size() - colon - 1) b = 0;
  } catch (const std::exception&) {
    b = 0;
  }
  const int most = kind == "grid" ? 6 : 8;
  if (b < 1 || b > most)
    return "--code " + s + ": the bits must be a whole number 1.." + std::to_string(most);
  c->kind = kind;
  c->bits = b;
  return {};
}

/// Direction i of the uniform sample: z = 1 - 2u, phi = 2 pi u' (Archimedes: uniform in solid
/// angle), rounded to float.
std::array<float, 3> uniform_dir(uint64_t seed, uint64_t i) {
  const double z = 1.0 - 2.0 * uniform01(seed, i, 0), phi = 2 * M_PI * uniform01(seed, i, 1);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)};
}

/// The 26 axis-aligned, face-diagonal and body-diagonal unit directions.
std::vector<std::array<float, 3>> special_dirs() {
  std::vector<std::array<float, 3>> v;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        const int n = x * x + y * y + z * z;
        if (n == 0) continue;
        const float s = 1.0f / std::sqrt(float(n));
        v.push_back({float(x) * s, float(y) * s, float(z) * s});
      }
  return v;
}

struct DirCodesArgs {
  std::vector<std::string> codes = {"grid:2", "grid:3", "oct:2", "oct:3", "oct:4", "micro21:3"};
  uint64_t samples = 1000000, seed = 1;
  std::string json_path;
};

int cmd_dir_codes(const DirCodesArgs& a) {
  std::vector<CodeSpec> specs;
  for (const std::string& s : a.codes) {
    CodeSpec c;
    if (const std::string e = parse_spec(s, &c); !e.empty()) {
      std::fprintf(stderr, "hrpp dir-codes: %s\n", e.c_str());
      return 2;
    }
    specs.push_back(c);
  }
  if (!a.json_path.empty() &&
      !check_output_path("dir-codes", "--json", a.json_path, OutputKind::kJson))
    return 2;
  const std::vector<std::array<float, 3>> extra = special_dirs();
  std::printf("%llu uniform unit directions (seed %llu) + %zu axis-aligned and diagonal ones\n",
              static_cast<unsigned long long>(a.samples), static_cast<unsigned long long>(a.seed),
              extra.size());
  std::printf("%-10s %5s %9s %9s %7s %12s %12s %9s\n", "code", "bits", "available", "occur", "used",
              "min/code", "max/code", "max/min");
  nlohmann::json rows = nlohmann::json::array();
  for (const CodeSpec& c : specs) {
    std::vector<uint64_t> count(size_t{1} << c.field_bits(), 0);
    for (uint64_t i = 0; i < a.samples; ++i) ++count[c.code(uniform_dir(a.seed, i))];
    for (const auto& d : extra) ++count[c.code(d)];
    uint64_t occur = 0, lo = UINT64_MAX, hi = 0;
    for (uint64_t n : count)
      if (n) {
        ++occur;
        lo = std::min(lo, n);
        hi = std::max(hi, n);
      }
    const double ratio = double(hi) / double(lo);
    std::printf("%-10s %5d %9zu %9llu %6.1f%% %12llu %12llu %9.2f\n", c.name().c_str(),
                c.field_bits(), count.size(), static_cast<unsigned long long>(occur),
                100.0 * double(occur) / double(count.size()), static_cast<unsigned long long>(lo),
                static_cast<unsigned long long>(hi), ratio);
    rows.push_back({{"code", c.kind},
                    {"bits", c.bits},
                    {"field_bits", c.field_bits()},
                    {"available", count.size()},
                    {"occur", occur},
                    {"min_per_code", lo},
                    {"max_per_code", hi},
                    {"max_over_min", ratio}});
  }
  if (!a.json_path.empty()) {
    const nlohmann::json j = {{"samples", a.samples},
                              {"seed", a.seed},
                              {"special_directions", extra.size()},
                              {"codes", rows},
                              {"tool", tool_json()}};
    if (!write_json_file(a.json_path, j)) return 2;
  }
  return 0;
}

}  // namespace

Subcommand add_dir_codes(CLI::App& app) {
  auto a = std::make_shared<DirCodesArgs>();
  auto* sc = app.add_subcommand(
      "dir-codes",
      "Direction codes used out of codes available, per hash: uniform unit directions (and the "
      "axis-aligned and diagonal ones) through each direction code");
  sc->add_option("--code", a->codes,
                 "direction codes to analyse, each grid:B (improved hash, B bits per component), "
                 "oct:B (improved, octahedral, B bits per coordinate) or micro21:T (T theta bits); "
                 "B 1..6 (grid) or 1..8 (oct), T 1..8")
      ->capture_default_str();
  sc->add_option("--samples", a->samples, "uniform unit directions")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 32))
      ->capture_default_str();
  sc->add_option("--seed", a->seed, "seed of the uniform directions")->capture_default_str();
  sc->add_option("--json", a->json_path,
                 "also write the table as JSON to this file ('-': to standard output, the text "
                 "then to standard error)");
  return {sc, [a] { return cmd_dir_codes(*a); }};
}

}  // namespace hrpp::cli
