// hrpp sweep: the Python driver (model/tools/sweep.py) in the project's venv; its options are
// sweep.py's (`hrpp sweep --help`).
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "subcommands.h"

namespace hrpp::cli {
namespace {

/// Replaces this process with sweep.py, given hrpp's path and the arguments after `sweep`.
int cmd_sweep(const std::vector<std::string>& remaining) {
  std::vector<std::string> args = {HRPP_PYTHON, HRPP_SOURCE_DIR "/model/tools/sweep.py", "--hrpp",
                                   "/proc/self/exe"};
  for (const std::string& e : remaining) args.push_back(e);
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n > 0) args[3] = std::string(self, size_t(n));
  std::vector<char*> argv2;
  for (std::string& s : args) argv2.push_back(s.data());
  argv2.push_back(nullptr);
  execv(argv2[0], argv2.data());
  std::fprintf(stderr, "hrpp sweep: cannot run %s: %s (run `make setup`)\n", HRPP_PYTHON,
               std::strerror(errno));
  return 2;
}

}  // namespace

Subcommand add_sweep(CLI::App& app) {
  auto* sw = app.add_subcommand("sweep",
                                "Sweep predictor parameters over scenes: CSV, Pareto "
                                "fronts, plots; time from the cost model or, with --timing "
                                "simulate, from hrpp simulate (model/tools/sweep.py --help)");
  sw->allow_extras();
  sw->prefix_command();
  sw->set_help_flag();
  return {sw, [sw] { return cmd_sweep(sw->remaining()); }};
}

}  // namespace hrpp::cli
