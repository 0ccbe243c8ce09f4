// Ray-stream files (docs/ray_stream.md): a header and one fixed-size record per ray, written and
// read streaming, so streams larger than memory work. Used by `hrpp trace`, `hrpp predict
// --stream` and the RTL testbench (`tb_hrpp --stream`).
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>

#include "hrpp/util/atomic_file.h"
#include "hrpp/workload/workload.h"

namespace hrpp {

/// A malformed or unreadable stream. The message names the file, and the record number when
/// the problem is in a record.
class StreamError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StreamHeader {
  uint32_t version = 1;
  uint64_t scene_fingerprint = 0;  // hash of the scene's triangles (scene_fingerprint())
  std::string options;             // the generation options, as text (JSON)
  uint64_t ray_count = 0;          // records that follow (written when the stream is closed)
};

/// 64-bit fingerprint of a scene's geometry (FNV-1a over the triangle vertex bit patterns).
uint64_t scene_fingerprint(const Scene& scene);

class RayStreamWriter {
 public:
  /// Opens PATH.tmp for writing; close() finalizes the header and renames it to PATH.
  RayStreamWriter(const std::string& path, const StreamHeader& header);
  ~RayStreamWriter();  // without close(): the temporary file is removed
  void write(const RayRecord& r);
  void close();
  uint64_t count() const { return count_; }

 private:
  std::string path_;
  std::optional<AtomicFile> file_;  // PATH.tmp until close()
  uint64_t count_ = 0;
  long count_offset_ = 0;
};

class RayStreamReader {
 public:
  explicit RayStreamReader(const std::string& path);  // reads and checks the header
  ~RayStreamReader();
  const StreamHeader& header() const { return header_; }
  /// Next record; false at the end. Throws StreamError on a truncated file or a record with a
  /// NaN or infinite origin/direction/tnear (never silently skipped).
  bool next(RayRecord* r);
  uint64_t records_read() const { return read_; }

 private:
  std::string path_;
  std::FILE* f_ = nullptr;
  StreamHeader header_;
  uint64_t read_ = 0;
};

}  // namespace hrpp
