// hrpp CLI: the subcommands, one file each (info.cc, check_embree.cc, exactness.cc, predict.cc,
// trace.cc, render.cc, sweep.cc, simulate.cc, dir_codes.cc). Each add_X registers its subcommand
// and options on the app; main.cc runs the one the command line chose after parsing.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace hrpp::cli {

struct Subcommand {
  CLI::App* app = nullptr;   // the registered subcommand: true once the command line chose it
  std::function<int()> run;  // runs it with the parsed options; returns the exit code
};

Subcommand add_info(CLI::App& app);
Subcommand add_check_embree(CLI::App& app);
Subcommand add_exactness(CLI::App& app);
Subcommand add_predict(CLI::App& app);
Subcommand add_sweep(CLI::App& app);
Subcommand add_trace(CLI::App& app);
Subcommand add_render(CLI::App& app);
Subcommand add_simulate(CLI::App& app);
Subcommand add_dir_codes(CLI::App& app);

}  // namespace hrpp::cli
