// tb_hrpp: the RTL parity testbench (tb/README.md). The golden model generates real ray streams
// and plays the traversal engine; every cycle every DUT output is compared with the cycle model.
//
//   tb_hrpp --scene SCENE|--stream FILE|--latency [--rays N]
//           [--config small|default|large|mobile|mutant|oct|...]
//           [--mode anyhit|closest-exact|closest-spec] [--seed S] [--trace FILE.fst|.vcd]
//           [--reset-every N] [--stall-gap G --stall-max M] [--stress KIND] [+verilator+...]
//
// The coordinator: the options (tb_options.h), the configuration (tb_config.h; the Verilated
// models tb_dut.h), the rays (tb_rays.h), the runs (tb_run.h; --latency: tb_latency_check.h) and
// the report (tb_report.h).
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>

#include "hrpp/hardware/rtl_config.h"
#include "hrpp/util/atomic_file.h"
#include "stress.h"
#include "tb_config.h"
#include "tb_latency_check.h"
#include "tb_options.h"
#include "tb_rays.h"
#include "tb_report.h"
#include "tb_run.h"

namespace hrpp::tb {
namespace {

int main_impl(int argc, char** argv) {
  TbOptions o;
  if (const std::optional<int> exit_code = parse_options(argc, argv, &o)) return *exit_code;
  if (o.latency && rtl_config(o.config).lanes != 1) {
    std::printf("tb_hrpp --latency measures one-lane configurations; %s has %d lanes\n",
                o.config.c_str(), rtl_config(o.config).lanes);
    return 2;
  }
  if (o.latency) return check_latencies(rtl_config(o.config), o.eo.mode);

  if (o.skip_missing && !o.scene_path.empty() && !std::filesystem::exists(o.scene_path)) {
    std::printf("SKIP: %s is absent\n", o.scene_path.c_str());
    return 77;
  }
  const RtlConfig spec = rtl_config(o.config);  // rtl/config/hrpp_configs.json
  TbRays rays;
  if (const int rc = load_rays(o, &rays)) return rc;
  CycleConfig cc;
  if (const int rc = configure_for_scene(spec, o.eo.mode, rays.scene, rays.bvh, &cc)) return rc;
  o.eo.id_bits = cc.id_bits;
  StressKind stress_kind{};
  if (!o.stress.empty())
    if (const int rc = make_stress_rays(o, spec, cc, &stress_kind, &rays)) return rc;
  print_header(spec, cc, o, rays);

  const auto t_sim = std::chrono::steady_clock::now();
  const std::clock_t cpu_sim = std::clock();
  if (cc.lanes > 1 && !o.trace.empty()) {
    std::printf("tb_hrpp: --trace records one-lane configurations only (%s has %d lanes)\n",
                o.config.c_str(), cc.lanes);
    return 2;
  }
  const Run r = cc.lanes > 1 ? run_lockstep_lanes(o.config, cc, rays.bvh, rays.rays, o.eo, o.ro)
                             : run_lockstep(o.config, cc, rays.bvh, rays.rays, o.eo, o.ro, o.trace);
  print_parity(r, t_sim, cpu_sim);
  if (cc.lanes > 1)
    std::printf(
        "lanes: %d; lookups %llu, lookup-queue heads waiting for their bank %llu "
        "lane-cycles (longest queue %llu), update-queue heads waiting for another "
        "lane's %llu lane-cycles\n",
        cc.lanes, (unsigned long long)r.lanes.lookups, (unsigned long long)r.lanes.lookup_waits,
        (unsigned long long)r.lanes.max_lookup_queue, (unsigned long long)r.lanes.update_waits);
  if (const int rc = report_lockstep(r, o, spec, stress_kind, rays.rays.size())) return rc;

  // The same closed loop with the cycle model alone must give the same statistics.
  const Run m = cc.lanes > 1 ? run_model_lanes(cc, rays.bvh, rays.rays, o.eo, o.ro)
                             : run_model(cc, rays.bvh, rays.rays, o.eo, o.ro);
  const PredictStats untimed = run_untimed(cc, rays.bvh, rays.rays, o.go_up, o.eo.mode);
  // The clear: a set per cycle in each bank (a bank per lane).
  return report_statistics(r, m, untimed, o, cc.table.sets / uint32_t(cc.lanes));
}

}  // namespace
}  // namespace hrpp::tb

int main(int argc, char** argv) {
  // SIGINT / SIGTERM: the waveform being written is removed (tb_run.cc), as hrpp does.
  hrpp::remove_unfinished_outputs_on_interrupt("tb_hrpp");
  try {
    return hrpp::tb::main_impl(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tb_hrpp: %s\n", e.what());
    return 2;
  }
}
