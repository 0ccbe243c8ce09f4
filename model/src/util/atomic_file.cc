#include "hrpp/util/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>

namespace hrpp {
namespace {

std::string errno_text() { return std::strerror(errno); }

// The temporary files of the open AtomicFiles (their tmp_.c_str(), stable while open), for
// remove_open_temporaries in a signal handler: lock-free atomics only.
constexpr int kTrackedFiles = 64;
std::atomic<const char*> open_tmp[kTrackedFiles];
static_assert(std::atomic<const char*>::is_always_lock_free);

void track(const char* tmp) {
  for (std::atomic<const char*>& slot : open_tmp) {
    const char* empty = nullptr;
    if (slot.compare_exchange_strong(empty, tmp)) return;
  }
}

void untrack(const char* tmp) {
  for (std::atomic<const char*>& slot : open_tmp) {
    const char* mine = tmp;
    if (slot.compare_exchange_strong(mine, nullptr)) return;
  }
}

}  // namespace

namespace {

const char* interrupted_tool = "hrpp";

/// Async-signal-safe calls only.
extern "C" void on_interrupt(int sig) {
  remove_open_temporaries();
  const char* what = sig == SIGINT ? ": interrupted (SIGINT): unfinished outputs removed\n"
                                   : ": terminated (SIGTERM): unfinished outputs removed\n";
  for (const char* part : {interrupted_tool, what}) {
    ssize_t ignored = ::write(STDERR_FILENO, part, std::strlen(part));
    (void)ignored;
  }
  ::_exit(128 + sig);
}

}  // namespace

void remove_unfinished_outputs_on_interrupt(const char* tool) {
  interrupted_tool = tool;
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void track_unfinished_output(const char* path) noexcept { track(path); }
void untrack_unfinished_output(const char* path) noexcept { untrack(path); }

int remove_open_temporaries() noexcept {
  int removed = 0;
  for (std::atomic<const char*>& slot : open_tmp)
    if (const char* tmp = slot.exchange(nullptr); tmp && ::unlink(tmp) == 0) ++removed;
  return removed;
}

AtomicFile::AtomicFile(const std::string& path) : path_(path), tmp_(path + ".tmp") {
  track(tmp_.c_str());  // before the file exists: a signal in between finds nothing to remove
  f_ = std::fopen(tmp_.c_str(), "wb");
  if (!f_) {
    untrack(tmp_.c_str());
    throw AtomicFileError(tmp_ + ": cannot open for writing: " + errno_text());
  }
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::discard() {
  if (!f_) return;
  std::fclose(f_);
  f_ = nullptr;
  std::remove(tmp_.c_str());
  untrack(tmp_.c_str());
}

void AtomicFile::fail(const std::string& why) {
  discard();
  throw AtomicFileError(tmp_ + ": write error: " + why);
}

void AtomicFile::write(const void* data, size_t size) {
  if (!f_) throw AtomicFileError(path_ + ": write after commit");
  if (std::fwrite(data, 1, size, f_) != size) fail(errno_text());
}

void AtomicFile::commit() {
  if (!f_) throw AtomicFileError(path_ + ": committed twice");
  // The last buffer is written by fflush / fclose: their errors count too.
  bool ok = std::fflush(f_) == 0;
  std::string e = ok ? std::string() : errno_text();
  ok = std::fclose(f_) == 0 && ok;
  f_ = nullptr;
  if (!ok) {
    if (e.empty()) e = errno_text();
    std::remove(tmp_.c_str());
    untrack(tmp_.c_str());
    throw AtomicFileError(tmp_ + ": write error: " + e);
  }
  const bool renamed = std::rename(tmp_.c_str(), path_.c_str()) == 0;
  if (!renamed) e = errno_text();
  if (!renamed) std::remove(tmp_.c_str());
  untrack(tmp_.c_str());  // after the rename: a signal before it removes the temporary file
  if (!renamed) throw AtomicFileError(path_ + ": cannot rename " + tmp_ + " to it: " + e);
}

void write_file_atomic(const std::string& path, std::string_view bytes) {
  AtomicFile f(path);
  f.write(bytes);
  f.commit();
}

}  // namespace hrpp
