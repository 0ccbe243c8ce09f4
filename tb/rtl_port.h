// The RTL in the loop of `hrpp simulate --rtl` (docs/timing_model.md): a Verilated hrpp_top of one
// configuration (tb/CMakeLists.txt, library hrpp_rtl) at the ports of a simulated RT unit's
// predictor, in lockstep with the cycle model of the same configuration. The DUT's outputs drive
// the simulator; every cycle they are compared with the cycle model's (tb_dut.h,
// compare_outputs, as tb_hrpp does).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/sim/unit_predictor.h"

namespace hrpp::tb {

/// Called once per port model, at its first mismatching cycle, with "cycle N: signal ...".
using MismatchSink = std::function<void(const std::string&)>;

/// The RTL port model of configuration `config` (each of rtl/config/hrpp_configs.json: the
/// Verilated models built into hrpp_rtl) with the cycle configuration `cc` (the configuration's,
/// resolved for the scene). The DUT is reset as tb_hrpp resets it (tb_dut.h, reset_dut); the
/// cycle model starts with it, and both count the same cycles. outputs() returns the DUT's
/// outputs; mismatches() counts the cycles in which they differed from the cycle model's (the
/// run goes on with the DUT's); error() reports an early finish of the DUT (a failed assertion),
/// a cycle model protocol error, or the two falling out of step. Throws std::invalid_argument
/// for a configuration without a Verilated model.
std::unique_ptr<sim::PortModel> make_rtl_port_model(const std::string& config,
                                                    const CycleConfig& cc,
                                                    MismatchSink on_first_mismatch = {});

}  // namespace hrpp::tb
