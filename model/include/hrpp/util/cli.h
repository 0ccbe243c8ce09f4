// What every binary of the project (hrpp, tb_hrpp, tb_hash, hrpp_bench) does the same way on its
// command line (CLI11): --version, usage errors (exit 2, with "did you mean --seed?" for a
// misspelt option or subcommand) and outputs checked before the work starts.
//
//   CLI::App app{...};
//   hrpp::cli::add_version_flag(app, "tb_hrpp");
//   try { app.parse(argc, argv); }
//   catch (const CLI::ParseError& e) { return hrpp::cli::usage_exit(app, e); }
#pragma once

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "hrpp/util/version.h"

namespace hrpp::cli {

/// Exit code of a usage error (a bad option or argument), for every binary.
inline constexpr int kUsageError = 2;

/// The optimal-string-alignment distance: insertions, deletions, substitutions and swaps of two
/// neighbouring characters each cost 1 ("--sede" is 1 from "--seed").
inline size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min(
          {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

/// The candidate closest to `typed` (a misspelling: at most 1 edit for up to 3 characters after
/// the dashes, 2 up to 8, 3 beyond), or "" when none is that close.
inline std::string closest(const std::string& typed, const std::vector<std::string>& candidates) {
  const size_t len = typed.size() - std::min(typed.find_first_not_of('-'), typed.size());
  const size_t limit = len <= 3 ? 1 : len <= 8 ? 2 : 3;
  std::string best;
  size_t best_d = limit + 1;
  for (const std::string& c : candidates) {
    const size_t d = edit_distance(typed, c);
    if (d > 0 && d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

/// The option names ("--seed", "-h") an argument of this command line could have meant: the
/// app's, its option groups' and those of the subcommands given (recursively); and the names of
/// the app's subcommands when none was given.
inline void option_names(const CLI::App& app, std::vector<std::string>* names) {
  for (const CLI::Option* o : app.get_options()) {
    for (const std::string& n : o->get_lnames()) names->push_back("--" + n);
    for (const std::string& n : o->get_snames()) names->push_back("-" + n);
  }
  bool any_parsed = false;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    if (!sub->get_name().empty() && sub->count() > 0) any_parsed = true;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (sub->get_name().empty() || sub->count() > 0)
      option_names(*sub, names);
    else if (!any_parsed)
      names->push_back(sub->get_name());
  }
}

/// The arguments CLI11 could not place (their "--name" part, without "=value").
inline void unplaced_arguments(const CLI::App& app, std::vector<std::string>* args) {
  for (std::string a : app.remaining(true)) {
    if (const size_t eq = a.find('='); a.rfind("--", 0) == 0 && eq != std::string::npos)
      a.resize(eq);
    args->push_back(a);
  }
}

/// Turns a parse error into the exit code: --help and --version print and give 0; every usage
/// error prints CLI11's message, a "did you mean ...?" line for each misspelt option or subcommand,
/// and gives kUsageError (2). Call on the top-level app.
inline int usage_exit(const CLI::App& app, const CLI::ParseError& e) {
  if (e.get_exit_code() == 0) return app.exit(e);
  std::string msg = CLI::FailureMessage::simple(&app, e);
  std::vector<std::string> names, args;
  option_names(app, &names);
  unplaced_arguments(app, &args);
  std::string hints;
  for (const std::string& a : args) {
    if (std::find(names.begin(), names.end(), a) != names.end()) continue;
    if (const std::string c = closest(a, names); !c.empty())
      hints += "unknown " + std::string(a[0] == '-' ? "option " : "argument ") + a +
               ": did you mean " + c + "?\n";
  }
  const size_t first_line = msg.find('\n');
  msg.insert(first_line == std::string::npos ? msg.size() : first_line + 1, hints);
  std::cerr << msg << std::flush;
  return kUsageError;
}

/// --version: prints "TOOL VERSION (commit COMMIT)" (hrpp/util/version.h) and exits 0.
inline void add_version_flag(CLI::App& app, const std::string& tool) {
  app.set_version_flag("--version", version_line(tool),
                       "print the version and the git commit built from, and exit");
}

/// Why PATH cannot be written as a file, or "" when it can: its folder exists and is writable, and
/// PATH is not a folder nor an existing file that cannot be written. Checked before the work
/// starts, so a run never ends without its output.
inline std::string output_file_problem(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) return "the file name is empty";
  std::error_code ec;
  if (fs::is_directory(path, ec)) return "'" + path + "' is a folder, not a file";
  const fs::path parent =
      fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::exists(parent, ec)) return "the folder '" + parent.string() + "' does not exist";
  if (!fs::is_directory(parent, ec)) return "'" + parent.string() + "' is not a folder";
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    return "the folder '" + parent.string() + "' is not writable: " + std::strerror(errno);
  if (fs::exists(path, ec) && ::access(path.c_str(), W_OK) != 0)
    return "'" + path + "' exists and cannot be written: " + std::strerror(errno);
  return "";
}

}  // namespace hrpp::cli
