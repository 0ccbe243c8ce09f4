// tb_hrpp's configuration: an RTL configuration (rtl_config(name), rtl/config/hrpp_configs.json)
// resolved for the scene into the cycle model's configuration. The Verilated model of each
// configuration: tb/tb_dut.h.
#pragma once

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/hardware/rtl_config.h"
#include "hrpp/predictor/predictor.h"
#include "hrpp/scene/scene.h"
#include "hrpp/trace/bvh.h"

namespace hrpp::tb {

/// The cycle model of `spec` in `mode` for the scene (its cell exponent; the RTL's node-id and
/// tag widths checked against the BVH). Returns 0, or 2 after printing why it does not fit.
int configure_for_scene(const RtlConfig& spec, PredictMode mode, const Scene& scene, const Bvh& bvh,
                        CycleConfig* cc);

}  // namespace hrpp::tb
