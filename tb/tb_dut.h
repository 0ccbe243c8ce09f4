// The Verilated models of tb_hrpp (one per RTL configuration, Vhrpp_<config>, tb/CMakeLists.txt):
// driving their inputs, reading their outputs, and picking the model of a configuration by name.
// Header-only: the templates are instantiated for every model (tb_hrpp_netlist builds them
// against stub headers that make every Vhrpp_<config> name the netlist's model).
#pragma once

#include <verilated.h>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "Vhrpp_default.h"
#include "Vhrpp_large.h"
#include "Vhrpp_mobile.h"
#include "Vhrpp_mutant.h"
#include "Vhrpp_oct.h"
#include "Vhrpp_primary.h"
#include "Vhrpp_primary_x2.h"
#include "Vhrpp_primary_x4.h"
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

// Writes `w` (<= 32) bits at `lsb` of a Verilated signal (integral or VlWide).
template <typename T>
void set_bits(T& v, int lsb, int w, uint32_t x) {
  const uint64_t mask = ((uint64_t{1} << w) - 1) << lsb;
  v = static_cast<T>((static_cast<uint64_t>(v) & ~mask) | ((uint64_t{x} << lsb) & mask));
}
template <std::size_t N>
void set_bits(VlWide<N>& v, int lsb, int w, uint32_t x) {
  if (lsb % 32 == 0 && w == 32) {
    v[lsb / 32] = x;
    return;
  }
  for (int i = 0; i < w; ++i) {
    const int b = lsb + i;
    v[b / 32] = (v[b / 32] & ~(1u << (b % 32))) | (((x >> i) & 1u) << (b % 32));
  }
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

// The multi-lane models (hrpp_lanes through hrpp_tb_top, rtl/hrpp_lanes.sv): every port is an
// array of lanes, packed, lane 0 in the low bits. Lane `lane`'s inputs and outputs.
struct LaneWidths {
  int id_bits, node_bits;
  uint32_t k;  // node ids per entry
};
template <typename M>
void apply_lane(M* dut, const DutIn& in, int lane, const LaneWidths& w) {
  set_bits(dut->ray_valid_i, lane, 1, in.ray_valid);
  set_bits(dut->ray_id_i, lane * w.id_bits, w.id_bits, in.ray_id);
  set_bits(dut->ray_kind_i, lane * 3, 3, in.ray_kind);
  for (int i = 0; i < 3; ++i) {
    set_bits(dut->ray_org_i, (lane * 3 + i) * 32, 32, in.org[i]);
    set_bits(dut->ray_dir_i, (lane * 3 + i) * 32, 32, in.dir[i]);
  }
  set_bits(dut->pred_ready_i, lane, 1, in.pred_ready);
  set_bits(dut->pw_valid_i, lane, 1, in.pw_valid);
  set_bits(dut->pw_id_i, lane * w.id_bits, w.id_bits, in.pw_id);
  set_bits(dut->pw_hit_i, lane, 1, in.pw_hit);
  set_bits(dut->pw_node_i, lane * w.node_bits, w.node_bits, in.pw_node);
  set_bits(dut->outcome_valid_i, lane, 1, in.outcome_valid);
  set_bits(dut->outcome_id_i, lane * w.id_bits, w.id_bits, in.outcome_id);
  set_bits(dut->outcome_hit_i, lane, 1, in.outcome_hit);
  set_bits(dut->outcome_node_i, lane * w.node_bits, w.node_bits, in.outcome_node);
  set_bits(dut->skip_ready_i, lane, 1, in.skip_ready);
}

template <typename M>
DutOut read_lane(const M* dut, int lane, const LaneWidths& w) {
  const int count_bits = std::bit_width(w.k);  // $clog2(K + 1)
  DutOut o;
  o.ray_ready = bits_of(dut->ray_ready_o, lane, 1);
  o.pred_valid = bits_of(dut->pred_valid_o, lane, 1);
  o.pred_id = bits_of(dut->pred_id_o, lane * w.id_bits, w.id_bits);
  o.pred_invalid = bits_of(dut->pred_invalid_o, lane, 1);
  o.pred_count = bits_of(dut->pred_count_o, lane * count_bits, count_bits);
  for (uint32_t i = 0; i < w.k; ++i)
    o.pred_nodes[i] =
        bits_of(dut->pred_nodes_o, (lane * int(w.k) + int(i)) * w.node_bits, w.node_bits);
  o.pw_ready = bits_of(dut->pw_ready_o, lane, 1);
  o.outcome_ready = bits_of(dut->outcome_ready_o, lane, 1);
  o.skip_valid = bits_of(dut->skip_valid_o, lane, 1);
  o.skip_id = bits_of(dut->skip_id_o, lane * w.id_bits, w.id_bits);
  o.skip_action = static_cast<Action>(bits_of(dut->skip_action_o, lane * 2, 2));
  return o;
}

// Compares every output of the cycle model (exp) and the DUT (act); payloads are compared while
// their valid is set (a FIFO's head is undefined while it is empty). Returns a description of the
// first difference, or "". tb_hrpp's lockstep run and hrpp simulate --rtl (rtl_port.cc) use it.
inline std::string compare_outputs(const DutOut& exp, const DutOut& act, uint32_t k) {
  char buf[256];
  auto diff = [&](const char* sig, uint64_t e, uint64_t a, uint32_t id) {
    std::snprintf(buf, sizeof buf, "signal %s: expected 0x%llx, actual 0x%llx (ray id %u)", sig,
                  (unsigned long long)e, (unsigned long long)a, id);
    return std::string(buf);
  };
  if (exp.ray_ready != act.ray_ready) return diff("ray_ready_o", exp.ray_ready, act.ray_ready, 0);
  if (exp.pw_ready != act.pw_ready) return diff("pw_ready_o", exp.pw_ready, act.pw_ready, 0);
  if (exp.outcome_ready != act.outcome_ready)
    return diff("outcome_ready_o", exp.outcome_ready, act.outcome_ready, 0);
  if (exp.pred_valid != act.pred_valid)
    return diff("pred_valid_o", exp.pred_valid, act.pred_valid, exp.pred_id);
  if (exp.pred_valid) {
    if (exp.pred_id != act.pred_id) return diff("pred_id_o", exp.pred_id, act.pred_id, exp.pred_id);
    if (exp.pred_invalid != act.pred_invalid)
      return diff("pred_invalid_o", exp.pred_invalid, act.pred_invalid, exp.pred_id);
    if (exp.pred_count != act.pred_count)
      return diff("pred_count_o", exp.pred_count, act.pred_count, exp.pred_id);
    for (uint32_t i = 0; i < k; ++i)
      if (exp.pred_nodes[i] != act.pred_nodes[i])
        return diff(("pred_nodes_o[" + std::to_string(i) + "]").c_str(), exp.pred_nodes[i],
                    act.pred_nodes[i], exp.pred_id);
  }
  if (exp.skip_valid != act.skip_valid)
    return diff("skip_valid_o", exp.skip_valid, act.skip_valid, exp.skip_id);
  if (exp.skip_valid) {
    if (exp.skip_id != act.skip_id) return diff("skip_id_o", exp.skip_id, act.skip_id, exp.skip_id);
    if (exp.skip_action != act.skip_action)
      return diff("skip_action_o", uint64_t(exp.skip_action), uint64_t(act.skip_action),
                  exp.skip_id);
  }
  return {};
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
  if (name == "mobile") return f.template operator()<Vhrpp_mobile>();
  if (name == "mutant") return f.template operator()<Vhrpp_mutant>();
  if (name == "primary") return f.template operator()<Vhrpp_primary>();
  if (name == "oct") return f.template operator()<Vhrpp_oct>();
  if (name == "default") return f.template operator()<Vhrpp_default>();
  throw std::invalid_argument("no one-lane Verilated model of RTL configuration " + name);
}

// The same for the multi-lane configurations (LanesCycleModel's; tb_run_lanes.cc).
template <typename F>
auto with_lanes_model(const std::string& name, F&& f) {
  if (name == "primary_x2") return f.template operator()<Vhrpp_primary_x2>();
  if (name == "primary_x4") return f.template operator()<Vhrpp_primary_x4>();
  throw std::invalid_argument("no multi-lane Verilated model of RTL configuration " + name);
}

}  // namespace hrpp::tb
