// Outputs written under a temporary name beside their target and renamed into place when
// complete, so a killed or failed run never leaves a half-written file that looks complete
// (model/test/atomic_outputs.py checks every writer of the `hrpp` tool).
#pragma once

#include <cstddef>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

namespace hrpp {

/// An output could not be written. The message names the file and gives the reason.
class AtomicFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file written to PATH.tmp and renamed to PATH by commit(). Destroyed without commit() (an
/// exception, a write error), the temporary file is removed. Every failure throws
/// AtomicFileError and removes the temporary file.
class AtomicFile {
 public:
  /// Opens PATH.tmp for writing (binary), replacing any earlier one.
  explicit AtomicFile(const std::string& path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// The open temporary file, for writers that write in place or seek back (ray streams). A
  /// writer that reports its own write errors calls fail() with the reason.
  std::FILE* stream() const { return f_; }
  void write(const void* data, size_t size);
  void write(std::string_view bytes) { write(bytes.data(), bytes.size()); }
  /// Flushes and closes the temporary file and renames it to PATH.
  void commit();
  /// Closes and removes the temporary file; throws "TMP: write error: WHY".
  [[noreturn]] void fail(const std::string& why);

  const std::string& path() const { return path_; }
  const std::string& tmp_path() const { return tmp_; }

 private:
  void discard();
  std::string path_, tmp_;
  std::FILE* f_ = nullptr;
};

/// Writes BYTES to PATH through an AtomicFile.
void write_file_atomic(const std::string& path, std::string_view bytes);

/// Removes the temporary file of every AtomicFile still open (up to 64 at once are tracked) and
/// returns how many it removed. Async-signal-safe: for a SIGINT / SIGTERM handler, so that an
/// interrupted run leaves no PATH.tmp behind.
int remove_open_temporaries() noexcept;

/// Installs the SIGINT / SIGTERM handler of the tools: removes the unfinished outputs
/// (remove_open_temporaries), prints "TOOL: interrupted (SIGINT): unfinished outputs removed"
/// (or "terminated (SIGTERM)") on standard error and exits 128 + signal. TOOL must be a string
/// literal (or outlive the process).
void remove_unfinished_outputs_on_interrupt(const char* tool);

/// Tracks (untracks) an output that is not an AtomicFile while it is being written, e.g. a
/// waveform: remove_open_temporaries removes it too. PATH must outlive the tracking.
void track_unfinished_output(const char* path) noexcept;
void untrack_unfinished_output(const char* path) noexcept;

}  // namespace hrpp
