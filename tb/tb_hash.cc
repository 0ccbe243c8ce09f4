// tb_hash: the RTL hash unit (rtl/hrpp_hash.sv) against the C++ hash (model/src/predictor/hash.cc)
// on every special class of HARD_CASES H1-H8 and dense random vectors, for thirteen parameter sets
// (four with the octahedral direction code, which also gets every direction made of three special
// values, random unit directions and exact bin boundaries) and many origin cell exponents. Prints
// "hash: N vectors x 13 configurations, M mismatches".
//
//   tb_hash [COUNT]   COUNT random vectors per configuration (default 2000000); --help, --version
#include <verilated.h>

#include <CLI/CLI.hpp>
#include <bit>
#include <cmath>
#include <cstdio>
#include <deque>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "Vtb_hash_top.h"
#include "hrpp/predictor/hash.h"
#include "hrpp/rtl_config_data.h"
#include "hrpp/util/cli.h"

using namespace hrpp;

namespace {

HashConfig make(HashVariant v, int p, int e, int go, int gd, CombineMode c,
                DirCode d = DirCode::kGrid) {
  HashConfig h;
  h.dir_code = d;
  h.variant = v;
  h.precision = p;
  h.exp_bits = e;
  h.origin_bits = go;
  h.dir_bits = gd;
  h.combine = c;
  h.index_bits = 0;
  return h;
}

// Keep in sync with tb_hash_top.sv.
constexpr int kNumConfigs = 13;
const HashConfig kConfigs[kNumConfigs] = {
    make(HashVariant::kFaithful, 6, 3, 5, 3, CombineMode::kXor),
    make(HashVariant::kFaithful, 2, 2, 5, 3, CombineMode::kConcat),
    make(HashVariant::kFaithful, 10, 8, 5, 3, CombineMode::kXor),
    make(HashVariant::kFaithful, 1, 0, 5, 3, CombineMode::kConcat),
    make(HashVariant::kImproved, 6, 3, 5, 3, CombineMode::kConcat),
    make(HashVariant::kImproved, 6, 3, 16, 16, CombineMode::kXor),
    make(HashVariant::kImproved, 6, 3, 1, 1, CombineMode::kConcat),
    make(HashVariant::kImproved, 6, 3, 10, 8, CombineMode::kXor),
    make(HashVariant::kImproved, 6, 3, 3, 3, CombineMode::kConcat, DirCode::kOct),
    make(HashVariant::kImproved, 6, 3, 5, 1, CombineMode::kXor, DirCode::kOct),
    make(HashVariant::kImproved, 6, 3, 16, 8, CombineMode::kConcat, DirCode::kOct),
    make(HashVariant::kImproved, 6, 3, 1, 4, CombineMode::kXor, DirCode::kOct),
    make(HashVariant::kImproved, 6, 3, 3, 2, CombineMode::kConcat),  // the default configuration
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"HRPP hash unit (rtl/hrpp_hash.sv) against the C++ hash, thirteen parameter sets"};
  cli::add_version_flag(app, "tb_hash");
  uint64_t n_random = 2000000;
  app.add_option("count", n_random, "random vectors per configuration (the special values too)")
      ->check(CLI::Range(uint64_t{0}, uint64_t{1} << 40));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli::usage_exit(app, e);  // 0 after --help or --version, 2 for a usage error
  }
  auto ctx = std::make_unique<VerilatedContext>();
  auto dut = std::make_unique<Vtb_hash_top>(ctx.get());
  // Every special class of H1-H8 and the values around them.
  const std::vector<uint32_t> special = {0x00000000,
                                         0x80000000,
                                         0x00000001,
                                         0x007FFFFF,
                                         0x80000001,
                                         0x807FFFFF,
                                         0x00800000,
                                         0x80800000,
                                         0x3F800000,
                                         0x3F7FFFFF,
                                         0xBF800000,
                                         0xBF7FFFFF,
                                         0x7F7FFFFF,
                                         0xFF7FFFFF,
                                         0x7F800000,
                                         0xFF800000,
                                         0x7FC00000,
                                         0xFFC00000,
                                         0x7F800001,
                                         0x7FC12345,
                                         0xFFFFFFFF,
                                         std::bit_cast<uint32_t>(1e30f),
                                         std::bit_cast<uint32_t>(-1e30f),
                                         std::bit_cast<uint32_t>(0.5f),
                                         std::bit_cast<uint32_t>(-0.5f),
                                         0x3F000000,
                                         0x3EFFFFFF};
  const int cell_exps[] = {-149, -60, -20, -7, -3, 0, 3, 12, 40, 127};
  std::mt19937_64 rng(12345);
  uint64_t vectors = 0, mismatches = 0;
  // The unit is pipelined (HashLatency stages): a vector applied before a clock edge reaches the
  // output after HashLatency - 1 more edges, so each edge's output is compared with the vector
  // applied that many edges earlier.
  constexpr size_t kHashLatency = rtl::kHashStages;  // rtl/config/hrpp_configs.json
  dut->rst_ni = 0;
  dut->clk_i = 0;
  dut->eval();
  dut->rst_ni = 1;
  dut->eval();
  std::deque<std::pair<std::array<uint32_t, 6>, int>> previous;
  auto compare = [&](const std::array<uint32_t, 6>& b, int k) {
    bool invalid = false;
    for (uint32_t v : b) invalid |= ((v >> 23) & 0xFF) == 0xFF;
    for (int c = 0; c < kNumConfigs; ++c) {
      HashConfig cfg = kConfigs[c];
      cfg.origin_cell_exp = k;
      const uint64_t exp = hash_key(b, cfg);
      const uint64_t act = (uint64_t(dut->key_o[2 * c + 1]) << 32) | dut->key_o[2 * c];
      const bool act_inv = (dut->invalid_o >> c) & 1;
      if (exp != act || invalid != act_inv) {
        if (mismatches++ < 10)
          std::printf(
              "MISMATCH config %d, cell exp %d, bits %08x %08x %08x %08x %08x %08x: "
              "expected key %llx invalid %d, actual %llx invalid %d\n",
              c, k, b[0], b[1], b[2], b[3], b[4], b[5], (unsigned long long)exp, invalid,
              (unsigned long long)act, act_inv);
      }
    }
    ++vectors;
  };
  auto check = [&](const std::array<uint32_t, 6>& b, int k) {
    for (int i = 0; i < 3; ++i) {
      dut->org_i[i] = b[i];
      dut->dir_i[i] = b[3 + i];
    }
    dut->cell_exp_i = static_cast<uint16_t>(k) & 0x1FF;
    dut->clk_i = 0;
    dut->eval();
    dut->clk_i = 1;
    dut->eval();
    if (previous.size() == kHashLatency - 1) {
      compare(previous.front().first, previous.front().second);
      previous.pop_front();
    }
    previous.emplace_back(b, k);
  };
  // Every special value in every component position, for every cell exponent.
  for (int k : cell_exps)
    for (int pos = 0; pos < 6; ++pos)
      for (uint32_t s : special) {
        std::array<uint32_t, 6> b;
        for (auto& x : b) x = static_cast<uint32_t>(rng());
        b[pos] = s;
        check(b, k);
      }
  // The octahedral code: every direction made of three special values (random origins), and
  // exact bin boundaries (dyadic components: (1, 1, 0) / 2, (1, 1, -2) / 4, ...).
  for (uint32_t x : special)
    for (uint32_t y : special)
      for (uint32_t z : special)
        check({static_cast<uint32_t>(rng()), static_cast<uint32_t>(rng()),
               static_cast<uint32_t>(rng()), x, y, z},
              cell_exps[(x ^ y ^ z) % std::size(cell_exps)]);
  const float dyadic[] = {0.f,    -0.f,    0.125f, -0.125f, 0.25f,  -0.25f,
                          0.375f, -0.375f, 0.5f,   -0.5f,   0.625f, -0.625f,
                          0.75f,  -0.75f,  1.f,    -1.f,    0.875f, -0.875f};
  for (float x : dyadic)
    for (float y : dyadic)
      for (float z : dyadic)
        check({0, 0, 0, std::bit_cast<uint32_t>(x), std::bit_cast<uint32_t>(y),
               std::bit_cast<uint32_t>(z)},
              0);
  // Random unit directions (normalised Gaussian vectors).
  std::normal_distribution<float> gauss;
  for (uint64_t i = 0; i < n_random / 4; ++i) {
    float d[3], n2 = 0;
    for (float& c : d) {
      c = gauss(rng);
      n2 += c * c;
    }
    const float inv = 1.f / std::sqrt(n2);
    check({static_cast<uint32_t>(rng()), static_cast<uint32_t>(rng()), static_cast<uint32_t>(rng()),
           std::bit_cast<uint32_t>(d[0] * inv), std::bit_cast<uint32_t>(d[1] * inv),
           std::bit_cast<uint32_t>(d[2] * inv)},
          cell_exps[i % std::size(cell_exps)]);
  }
  // Dense random: uniform bit patterns, and realistic floats (origins in a scene, unit dirs).
  std::uniform_int_distribution<int> kd(0, std::size(cell_exps) - 1);
  std::uniform_real_distribution<float> pos(-100.f, 100.f), unit(-1.f, 1.f);
  for (uint64_t i = 0; i < n_random; ++i) {
    std::array<uint32_t, 6> b;
    if (i % 2) {
      for (auto& x : b) x = static_cast<uint32_t>(rng());
    } else {
      for (int j = 0; j < 3; ++j) b[j] = std::bit_cast<uint32_t>(pos(rng));
      for (int j = 3; j < 6; ++j) b[j] = std::bit_cast<uint32_t>(unit(rng));
    }
    check(b, cell_exps[kd(rng)]);
  }
  check({0, 0, 0, 0, 0, 0}, 0);  // flushes the last vector
  std::printf("hash: %llu vectors x %d configurations, %llu mismatches\n",
              (unsigned long long)vectors, kNumConfigs, (unsigned long long)mismatches);
  dut->final();
  return mismatches ? 1 : 0;
}
