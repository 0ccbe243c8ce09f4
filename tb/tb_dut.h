// The Verilated models of tb_hrpp (one per RTL configuration, Vhrpp_<config>, tb/CMakeLists.txt):
// driving their inputs, reading their outputs, and picking the model of a configuration by name.
// Header-only: the templates are instantiated for every model (tb_hrpp_netlist builds them
// against stub headers that make every Vhrpp_<config> name the netlist's model).
#pragma once

#include <verilated.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include "Vhrpp_default.h"
#include "Vhrpp_large.h"
#include "Vhrpp_mutant.h"
#include "Vhrpp_small.h"
#include "hrpp/hardware/cycle_model.h"

namespace hrpp::tb {

// Reads `w` bits at `lsb` of a Verilated signal (integral or VlWide).
template <typename T>
uint32_t bits_of(const T& v, int lsb, int w) {
  return static_cast<uint32_t>((static_cast<uint64_t>(v) >> lsb) & ((uint64_t{1} << w) - 1));
}
template <std::size_t N>
uint32_t bits_of(const VlWide<N>& v, int lsb, int w) {
  uint64_t lo = v[lsb / 32], hi = lsb / 32 + 1 < int(N) ? v[lsb / 32 + 1] : 0;
  return static_cast<uint32_t>((((hi << 32) | lo) >> (lsb % 32)) & ((uint64_t{1} << w) - 1));
}

template <typename M>
void apply(M* dut, const DutIn& in) {
  dut->ray_valid_i = in.ray_valid;
  dut->ray_id_i = in.ray_id;
  dut->ray_kind_i = in.ray_kind;
  for (int i = 0; i < 3; ++i) {
    dut->ray_org_i[i] = in.org[i];
    dut->ray_dir_i[i] = in.dir[i];
  }
  dut->pred_ready_i = in.pred_ready;
  dut->pw_valid_i = in.pw_valid;
  dut->pw_id_i = in.pw_id;
  dut->pw_hit_i = in.pw_hit;
  dut->pw_node_i = in.pw_node;
  dut->outcome_valid_i = in.outcome_valid;
  dut->outcome_id_i = in.outcome_id;
  dut->outcome_hit_i = in.outcome_hit;
  dut->outcome_node_i = in.outcome_node;
  dut->skip_ready_i = in.skip_ready;
}

template <typename M>
DutOut read(const M* dut, uint32_t k, int node_bits) {
  DutOut o;
  o.ray_ready = dut->ray_ready_o;
  o.pred_valid = dut->pred_valid_o;
  o.pred_id = dut->pred_id_o;
  o.pred_invalid = dut->pred_invalid_o;
  o.pred_count = dut->pred_count_o;
  for (uint32_t i = 0; i < k; ++i)
    o.pred_nodes[i] = bits_of(dut->pred_nodes_o, int(i) * node_bits, node_bits);
  o.pw_ready = dut->pw_ready_o;
  o.outcome_ready = dut->outcome_ready_o;
  o.skip_valid = dut->skip_valid_o;
  o.skip_id = dut->skip_id_o;
  o.skip_action = static_cast<Action>(dut->skip_action_o);
  return o;
}

// The start of every DUT run: the configuration inputs driven, two clock cycles with rst_ni low
// (dump() after each evaluation, for a waveform), then the reset released at clock low.
template <typename M, typename Dump>
void reset_dut(M* dut, const CycleConfig& cc, Dump&& dump) {
  dut->cfg_mode_i = static_cast<uint8_t>(cc.mode);
  dut->cfg_cell_exp_i = static_cast<uint16_t>(cc.hash.origin_cell_exp) & 0x1FF;
  apply(dut, DutIn{});
  dut->rst_ni = 0;
  for (int i = 0; i < 4; ++i) {
    dut->clk_i = i & 1;
    dut->eval();
    dump();
  }
  dut->clk_i = 0;
  dut->rst_ni = 1;
  dut->eval();
}

// Calls f.template operator()<M>() with M the Verilated model of configuration `name`.
template <typename F>
auto with_model(const std::string& name, F&& f) {
  if (name == "small") return f.template operator()<Vhrpp_small>();
  if (name == "large") return f.template operator()<Vhrpp_large>();
  if (name == "mutant") return f.template operator()<Vhrpp_mutant>();
  if (name == "default") return f.template operator()<Vhrpp_default>();
  throw std::invalid_argument("tb_hrpp has no Verilated model of configuration " + name);
}

}  // namespace hrpp::tb
