// hrpp: the project's command-line tool. `hrpp --help` and `hrpp SUBCOMMAND --help` list options.
// Each subcommand lives in its own file (subcommands.h); this file parses the command line, runs
// the chosen subcommand and turns errors into exit codes.
//
// Exit codes: 0 success; 1 a check failed (e.g. check-embree found mismatches); 2 bad input
// (bad option, unreadable or malformed scene or ray stream, unwritable output); 130 / 143
// interrupted by SIGINT / SIGTERM (unfinished outputs removed).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <vector>

#include "common.h"
#include "hrpp/report/render.h"
#include "hrpp/scene/scene.h"
#include "hrpp/util/atomic_file.h"
#include "hrpp/util/cli.h"
#include "hrpp/workload/ray_stream.h"
#include "subcommands.h"

int main(int argc, char** argv) {
  using namespace hrpp;
  using namespace hrpp::cli;
  set_command_line(argc, argv);  // for the JSON reports' "tool" object
  CLI::App app{"HRPP: hash-based ray path prediction - golden model tool"};
  app.require_subcommand(1);
  add_version_flag(app, "hrpp");
  // In this order in `hrpp --help`.
  const std::vector<Subcommand> subcommands = {
      add_info(app),  add_check_embree(app), add_exactness(app), add_predict(app),   add_sweep(app),
      add_trace(app), add_render(app),       add_simulate(app),  add_dir_codes(app),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return usage_exit(app, e);  // 0 after --help or --version, 2 for a usage error
  }
  // SIGINT / SIGTERM: unfinished outputs removed, one line, exit 130 / 143 (`hrpp sweep` execs
  // Python: its handlers are reset to the default).
  remove_unfinished_outputs_on_interrupt("hrpp");
  try {
    for (const Subcommand& s : subcommands)
      if (*s.app) return s.run();
  } catch (const SceneError& e) {
    std::fprintf(stderr, "hrpp: %s\n", e.what());
    return 2;
  } catch (const StreamError& e) {
    std::fprintf(stderr, "hrpp: %s\n", e.what());
    return 2;
  } catch (const RenderError& e) {
    std::fprintf(stderr, "hrpp: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrpp: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
