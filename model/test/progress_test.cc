// Progress lines on standard error (hrpp/util/progress.h): nothing before the delay, one line
// per interval when piped, one line updated in place on a terminal, cleared at the end.
#include "hrpp/util/progress.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace hrpp {
namespace {

/// What P wrote to F so far.
std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  for (int c; (c = std::fgetc(f)) != EOF;) s += char(c);
  return s;
}

TEST(Progress, PipedOneLinePerIntervalAfterTheDelay) {
  std::FILE* f = std::tmpfile();
  ASSERT_TRUE(f);
  {
    Progress p(f, "render: predictor", "camera samples", 1000, Progress::Clock::now(), false,
               {.delay = 2, .tty_interval = 0.25, .pipe_interval = 5});
    p.update(100, 1.0, 1.0);  // before the delay: nothing
    EXPECT_EQ(contents(f), "");
    p.update(250, 2.5, 2.5);
    p.update(300, 3.0, 3.0);  // within the interval: nothing more
    p.update(900, 7.5, 7.5);
  }
  const std::string s = contents(f);
  EXPECT_EQ(s,
            "render: predictor:  25.0% of 1000 camera samples, 100 camera samples/s, 8 s left\n"
            "render: predictor:  90.0% of 1000 camera samples, 120 camera samples/s, 1 s left\n");
  std::fclose(f);
}

TEST(Progress, TerminalLineUpdatedInPlaceAndCleared) {
  std::FILE* f = std::tmpfile();
  ASSERT_TRUE(f);
  Progress p(f, "x", "pixels", 4000000, Progress::Clock::now(), true, {});
  p.update(1000000, 2.0, 0.5);
  p.update(1100000, 2.1, 0.6);  // within 0.25 s: not redrawn
  p.update(2000000, 2.5, 1.0);
  p.finish();
  EXPECT_EQ(contents(f),
            "\rx:  25.0% of 4000000 pixels, 2.00 M pixels/s, 2 s left\033[K"
            "\rx:  50.0% of 4000000 pixels, 2.00 M pixels/s, 1 s left\033[K\r\033[K");
  EXPECT_EQ(p.line(10, 1.0), "x:   0.0% of 4000000 pixels, 10 pixels/s, 111 h 06 min left");
  EXPECT_EQ(p.line(3000000, 1000.0), "x:  75.0% of 4000000 pixels, 3000 pixels/s, 5 min 34 s left");
  EXPECT_EQ(p.line(0, 0.0), "x:   0.0% of 4000000 pixels, 0 pixels/s, time left unknown");
  std::fclose(f);
}

}  // namespace
}  // namespace hrpp
