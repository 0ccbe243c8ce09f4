#include "tb_latency_check.h"

#include <cstdio>
#include <memory>
#include <string>

#include "latency.h"
#include "tb_dut.h"

namespace hrpp::tb {
namespace {

// The latencies of the DUT, measured at its ports (tb/latency.h).
template <typename M>
Latencies measure_dut_latencies(const CycleConfig& cc, std::string* error) {
  auto ctx = std::make_unique<VerilatedContext>();
  auto dut = std::make_unique<M>(ctx.get());
  reset_dut(dut.get(), cc, [] {});
  const CycleFn cycle = [&](const DutIn& in) {
    apply(dut.get(), in);
    dut->clk_i = 0;
    dut->eval();
    const DutOut o = read(dut.get(), cc.table.nodes_per_entry, cc.table.node_bits);
    dut->clk_i = 1;
    dut->eval();
    return o;
  };
  Latencies l;
  *error = measure_latencies(cycle, cc.id_bits, cc.table.sets, &l, cc.table.conf_bits > 0);
  if (error->empty() && ctx->gotFinish()) *error = "the simulation finished early (an assertion?)";
  dut->final();
  return l;
}

}  // namespace

// tb_hrpp --latency: the DUT's and the cycle model's latencies against the declared ones.
int check_latencies(const RtlConfig& rc, PredictMode mode) {
  const CycleConfig cc = rc.cycle(mode);
  std::string dut_error, model_error;
  const Latencies dut =
      with_model(rc.name, [&]<typename M>() { return measure_dut_latencies<M>(cc, &dut_error); });
  CycleModel cm(cc);
  const CycleFn model_cycle = [&](const DutIn& in) {
    const DutOut o = cm.outputs();
    cm.tick(in);
    return o;
  };
  Latencies model;
  model_error =
      measure_latencies(model_cycle, cc.id_bits, cc.table.sets, &model, cc.table.conf_bits > 0);
  const Latencies declared = declared_latencies(rc);
  std::printf(
      "latency: config %s (cycles: ray accepted to pred_valid_o, predicted-walk result "
      "accepted to skip_valid_o, final outcome accepted to the first ray seeing its "
      "write)\n",
      rc.name.c_str());
  auto line = [](const char* who, const Latencies& l) {
    std::printf("  %-12s prediction %d, decision %d, update landing %d\n", who, l.prediction,
                l.decision, l.landing);
  };
  line("declared", declared);
  line("DUT", dut);
  line("cycle model", model);
  std::string e = !dut_error.empty()     ? "DUT: " + dut_error
                  : !model_error.empty() ? "cycle model: " + model_error
                                         : "";
  if (e.empty()) {
    if (std::string d = compare_latencies(dut, declared); !d.empty())
      e = "DUT: " + d;
    else if (std::string m = compare_latencies(model, declared); !m.empty())
      e = "cycle model: " + m;
  }
  if (!e.empty()) {
    std::printf("FAIL: %s (rtl/config/hrpp_configs.json)\n", e.c_str());
    return 1;
  }
  std::printf("PASS\n");
  return 0;
}

}  // namespace hrpp::tb
