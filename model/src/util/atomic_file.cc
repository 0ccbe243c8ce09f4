#include "hrpp/util/atomic_file.h"

#include <cerrno>
#include <cstring>

namespace hrpp {
namespace {

std::string errno_text() { return std::strerror(errno); }

}  // namespace

AtomicFile::AtomicFile(const std::string& path) : path_(path), tmp_(path + ".tmp") {
  f_ = std::fopen(tmp_.c_str(), "wb");
  if (!f_) throw AtomicFileError(tmp_ + ": cannot open for writing: " + errno_text());
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::discard() {
  if (!f_) return;
  std::fclose(f_);
  f_ = nullptr;
  std::remove(tmp_.c_str());
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
    throw AtomicFileError(tmp_ + ": write error: " + e);
  }
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    e = errno_text();
    std::remove(tmp_.c_str());
    throw AtomicFileError(path_ + ": cannot rename " + tmp_ + " to it: " + e);
  }
}

void write_file_atomic(const std::string& path, std::string_view bytes) {
  AtomicFile f(path);
  f.write(bytes);
  f.commit();
}

}  // namespace hrpp
