#include "tb_options.h"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <vector>

#include "hrpp/hardware/rtl_config.h"
#include "hrpp/util/cli.h"

namespace hrpp::tb {

std::optional<int> parse_options(int argc, char** argv, TbOptions* o) {
  CLI::App app{"HRPP RTL parity testbench: DUT against the cycle model, cycle by cycle"};
  cli::add_version_flag(app, "tb_hrpp");
  EngineOptions& eo = o->eo;
  auto* src = app.add_option_group("source");
  src->add_option("--scene", o->scene_path, "generate the rays of this glTF scene");
  src->add_option("--stream", o->stream_path, "read the rays from this ray-stream file");
  src->add_flag("--latency", o->latency,
                "measure the pipeline latencies at the ports and compare them with the declared "
                "ones (rtl/config/hrpp_configs.json)");
  src->require_option(1);
  app.add_option("--rays", o->nrays, "rays to run (at most)")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 32));
  std::vector<std::string> configs = rtl_config_names();
  for (const std::string& n : rtl_config_names()) configs.push_back("rtl-" + n);
  app.add_option("--config", o->config,
                 "RTL configuration (rtl/config/hrpp_configs.json), by its name or by its preset "
                 "name as hrpp predict/simulate take it (rtl-default is default)")
      ->check(CLI::IsMember(configs))
      ->capture_default_str();
  app.add_option("--mode", o->mode, "how closest-hit rays use predictions")
      ->check(CLI::IsMember({"anyhit", "closest-exact", "closest-spec"}));
  app.add_option("--go-up", o->go_up, "go-up level of inserted nodes")->check(CLI::Range(0u, 64u));
  app.add_option("--seed", o->seed, "seed of the engine's latencies and back-pressure");
  app.add_option("--max-latency", eo.max_latency, "largest engine latency in cycles")
      ->check(CLI::Range(1, 1000));
  app.add_option("--p-ray", eo.p_ray, "probability the engine offers a ray in a cycle")
      ->check(CLI::Range(0.01, 1.0));
  app.add_option("--min-latency", eo.min_latency, "smallest engine latency in cycles")
      ->check(CLI::Range(1, 1000));
  app.add_option("--p-ready", eo.p_pred_ready,
                 "probability the engine accepts an output in a cycle")
      ->check(CLI::Range(0.01, 1.0));
  app.add_option("--stall-every", eo.stall_every, "stall every output this often (cycles)");
  app.add_option("--stall-length", eo.stall_length, "... for this many cycles");
  app.add_option("--trace", o->trace,
                 "write a waveform to this file: FST if its name ends in .fst, VCD otherwise (its "
                 "folder must exist and be writable)");
  app.add_option("--min-throughput", o->min_throughput,
                 "fail unless at least this many rays finish per cycle (all lanes together)")
      ->check(CLI::Range(0.0, 4.0));
  app.add_option("--min-in-flight", o->min_in_flight,
                 "fail unless at some cycle at least this many rays were in flight at once");
  app.add_flag("--skip-missing", o->skip_missing,
               "exit 77 (skipped) when the scene file does not exist (for ctest)");
  RunOptions& ro = o->ro;
  app.add_option("--reset-every", ro.reset_every,
                 "assert rst_ni mid-stream about every N cycles (uniform in [N/2, 3N/2]; 0: never)")
      ->check(CLI::Range(uint64_t{0}, uint64_t{1} << 40));
  app.add_option("--reset-max-length", ro.reset_max_len, "each reset lasts 1..L cycles")
      ->check(CLI::Range(1, 1000));
  app.add_option("--stall-gap", eo.stall_gap,
                 "random stalls on every interface: one starts with probability 1/G per cycle");
  app.add_option("--stall-max", eo.stall_max, "... and lasts 1..M cycles");
  app.add_option("--engine-fault", eo.fault,
                 "test only: 1 = a reset re-offers each dropped ray twice, 2 = a ray stall loses "
                 "the ray on offer (the exactly-once check must fail)")
      ->check(CLI::Range(0, 2));
  app.add_option("--stress", o->stress,
                 "synthetic rays of the scene instead of its camera rays: set-burst (bursts of one "
                 "table set), one-key (every ray one key), evict (many keys: continuous eviction), "
                 "spread (ray i of a set s with s mod 4 = i mod 4: each lane its own bank)")
      ->check(CLI::IsMember({"set-burst", "one-key", "evict", "spread"}));
  // +verilator+... arguments go to the VerilatedContext, the rest to the options above.
  std::vector<char*> cli_args;
  for (int i = 0; i < argc; ++i) {
    if (i > 0 && argv[i][0] == '+')
      ro.plusargs.push_back(argv[i]);
    else
      cli_args.push_back(argv[i]);
  }
  try {
    app.parse(int(cli_args.size()), cli_args.data());
  } catch (const CLI::ParseError& e) {
    return cli::usage_exit(app, e);  // 0 after --help or --version, 2 for a usage error
  }
  if (o->config.starts_with("rtl-")) o->config = o->config.substr(4);  // the preset's name
  // Outputs are checked before the work starts: a run never ends without its waveform.
  if (!o->trace.empty())
    if (const std::string why = cli::output_file_problem(o->trace); !why.empty()) {
      std::fprintf(stderr, "tb_hrpp: --trace %s: %s\n", o->trace.c_str(), why.c_str());
      return cli::kUsageError;
    }
  if (ro.reset_every && ro.reset_every < 16) {
    std::fprintf(stderr, "tb_hrpp: --reset-every must be 0 or at least 16\n");
    return 2;
  }
  if (eo.stall_gap && !eo.stall_max) {
    std::fprintf(stderr, "tb_hrpp: --stall-gap needs --stall-max\n");
    return 2;
  }
  if (!o->stress.empty() && o->scene_path.empty()) {
    std::fprintf(stderr, "tb_hrpp: --stress needs --scene\n");
    return 2;
  }
  if (eo.min_latency > eo.max_latency) {
    std::fprintf(stderr, "tb_hrpp: --min-latency %d exceeds --max-latency %d\n", eo.min_latency,
                 eo.max_latency);
    return 2;
  }
  eo.p_skip_ready = eo.p_pred_ready;
  eo.seed = o->seed;
  eo.go_up = o->go_up;
  parse_predict_mode(o->mode, &eo.mode);
  return std::nullopt;
}

}  // namespace hrpp::tb
