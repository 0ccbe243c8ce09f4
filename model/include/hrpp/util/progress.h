// Progress of a long run on standard error (issue 20): nothing for the first couple of seconds,
// then on a terminal one line updated in place (and cleared at the end), when piped one line
// every few seconds; each line gives the share done, the rate and the estimated time left.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

namespace hrpp {

class Progress {
 public:
  using Clock = std::chrono::steady_clock;
  struct Options {
    double delay = 2.0;          // seconds since the run's start before the first line
    double tty_interval = 0.25;  // seconds between updates of the line on a terminal
    double pipe_interval = 5.0;  // seconds between lines when piped
  };
  /// LABEL names the run or its phase ("render: predictor"), UNIT what is counted ("camera
  /// samples"), TOTAL how many there are. RUN_START is when the whole run started (the delay
  /// counts from it, the rate from now). TTY: update one line in place (isatty of OUT).
  Progress(std::FILE* out, std::string label, std::string unit, uint64_t total,
           Clock::time_point run_start, bool tty, Options o)
      : out_(out),
        label_(std::move(label)),
        unit_(std::move(unit)),
        total_(total),
        run_start_(run_start),
        start_(Clock::now()),
        tty_(tty),
        opt_(o) {}
  Progress(std::FILE* out, std::string label, std::string unit, uint64_t total,
           Clock::time_point run_start = Clock::now())
      : Progress(out, std::move(label), std::move(unit), total, run_start, isatty(fileno(out)),
                 Options{}) {}
  ~Progress() { finish(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// DONE of the total are done: prints a line when it is time to.
  void update(uint64_t done) {
    const Clock::time_point now = Clock::now();
    update(done, seconds(run_start_, now), seconds(start_, now));
  }
  /// The same at a given time: SINCE_RUN seconds since the run's start, ELAPSED since this
  /// progress's start (for tests).
  void update(uint64_t done, double since_run, double elapsed) {
    if (since_run < opt_.delay) return;
    if (printed_ && elapsed - last_ < (tty_ ? opt_.tty_interval : opt_.pipe_interval)) return;
    last_ = elapsed;
    printed_ = true;
    const std::string l = line(done, elapsed);
    if (tty_)
      std::fprintf(out_, "\r%s\033[K", l.c_str());
    else
      std::fprintf(out_, "%s\n", l.c_str());
    std::fflush(out_);
  }
  /// On a terminal, clears the line (what follows starts on a clean line).
  void finish() {
    if (tty_ && printed_) {
      std::fprintf(out_, "\r\033[K");
      std::fflush(out_);
    }
    printed_ = false;
  }
  /// "LABEL: 42.0% of 262144 UNIT, 1.23 M UNIT/s, 3 s left"
  std::string line(uint64_t done, double elapsed) const {
    char b[160];
    const double rate = elapsed > 0 ? done / elapsed : 0;
    std::string left = "time left unknown";
    if (rate > 0 && done <= total_) {
      const long s = std::lround(std::ceil((total_ - done) / rate));
      char t[48];
      if (s < 100)
        std::snprintf(t, sizeof t, "%ld s left", s);
      else if (s < 3600)
        std::snprintf(t, sizeof t, "%ld min %02ld s left", s / 60, s % 60);
      else
        std::snprintf(t, sizeof t, "%ld h %02ld min left", s / 3600, s % 3600 / 60);
      left = t;
    }
    std::snprintf(b, sizeof b, "%5.1f%% of %" PRIu64 " %s, ", total_ ? 100.0 * done / total_ : 0.0,
                  total_, unit_.c_str());
    char r[64];
    if (rate >= 1e5)
      std::snprintf(r, sizeof r, "%.2f M %s/s, ", rate / 1e6, unit_.c_str());
    else
      std::snprintf(r, sizeof r, "%.0f %s/s, ", rate, unit_.c_str());
    return label_ + ": " + b + r + left;
  }

 private:
  static double seconds(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  }
  std::FILE* out_;
  std::string label_, unit_;
  uint64_t total_;
  Clock::time_point run_start_, start_;
  bool tty_;
  Options opt_;
  bool printed_ = false;
  double last_ = 0;
};

}  // namespace hrpp
