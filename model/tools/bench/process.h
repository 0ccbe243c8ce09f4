// hrpp_bench: child processes, their captured stdout and their peak RSS (wait4's ru_maxrss).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace hrpp::bench {

struct Proc {
  std::string out;
  int status = -1;
  double max_rss_mb = 0;
  double seconds = 0;      // wall clock
  double cpu_seconds = 0;  // user + system CPU time (wait4's ru_utime + ru_stime)
};

// Runs argv in a child process; its stdout is captured, its stderr passes through.
Proc run_process(const std::vector<std::string>& argv);

// This executable's path (the measurements run it again with --child).
std::string self_exe();

// Runs this executable with --child WHAT ARGS...: one measurement, parsed from its JSON stdout;
// its peak RSS in MB into *rss. Throws when it fails.
nlohmann::json run_child(const std::string& what, const std::vector<std::string>& args,
                         double* rss);

}  // namespace hrpp::bench
