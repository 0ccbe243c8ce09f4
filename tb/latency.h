// The pipeline latencies measured at the ports (tb_hrpp --latency; ctest tb.latency.<config>):
// on an otherwise idle pipeline, one ray, its predicted-walk result and its final outcome, then
// rays of the same key until one sees the outcome's table write. Compared with the declared
// latencies (rtl/config/hrpp_configs.json, hrpp/rtl_config_data.h).
#pragma once

#include <functional>
#include <string>

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/hardware/rtl_config.h"

namespace hrpp::tb {

struct Latencies {
  int prediction = -1;  // ray accepted -> pred_valid_o
  int decision = -1;    // predicted-walk result accepted -> skip_valid_o
  int landing = -1;     // final outcome accepted -> the first ray accepted whose lookup sees it
};

/// The declared ones of a configuration (one cycle more of decision and update landing with the
/// key store in block RAM: RtlConfig::decision_latency() ...).
Latencies declared_latencies(const RtlConfig& rc);

/// One clock cycle of a DUT out of reset: drives `in` with the clock low, returns the outputs
/// of that cycle, then the rising edge.
using CycleFn = std::function<DutOut(const DutIn&)>;

/// Measures the latencies through `cycle` (ray ids below 2^id_bits; node ids below 2^node_bits).
/// Returns "" or what went wrong (no answer within the time limit, a wrong node written).
/// `confidence` (a confidence bit per way): the probe's node is written once before the
/// measurement, so that the measured write (a confirmation) is the one that makes it predict.
std::string measure_latencies(const CycleFn& cycle, int id_bits, uint32_t sets, Latencies* out,
                              bool confidence = false);

/// "" when `measured` equals `declared`, else which latencies differ.
std::string compare_latencies(const Latencies& measured, const Latencies& declared);

}  // namespace hrpp::tb
