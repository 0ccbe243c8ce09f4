// tb_hrpp --latency (ctest tb.latency.<config>): the pipeline latencies measured at the ports of
// the DUT (the Verilated model of a configuration) and of the cycle model (tb/latency.h), against
// the declared ones (rtl/config/hrpp_configs.json).
#pragma once

#include "hrpp/hardware/rtl_config.h"
#include "hrpp/predictor/predictor.h"

namespace hrpp::tb {

/// Prints the declared and the measured latencies, then PASS or FAIL; returns the exit code.
int check_latencies(const RtlConfig& rc, PredictMode mode);

}  // namespace hrpp::tb
