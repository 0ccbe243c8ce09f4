// Ray-stream files, byte for byte as docs/ray_stream.md specifies: little-endian whatever the
// host, a header, then one 64-byte record per ray.
#include "hrpp/workload/ray_stream.h"

#include <sys/stat.h>

#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>

namespace hrpp {
namespace {

constexpr char kMagic[8] = {'H', 'R', 'P', 'P', 'R', 'A', 'Y', 'S'};
constexpr uint32_t kVersion = 1;
constexpr size_t kFixedHeader = 36;  // magic .. options length
constexpr size_t kRecord = 64;
constexpr size_t kAlign = 64;  // records start at a multiple of 64 bytes
constexpr long kCountOffset = 24;

void put32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
void put64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
void putf(uint8_t* p, float v) { put32(p, std::bit_cast<uint32_t>(v)); }
uint32_t get32(const uint8_t* p) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= uint32_t{p[i]} << (8 * i);
  return v;
}
uint64_t get64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= uint64_t{p[i]} << (8 * i);
  return v;
}
float getf(const uint8_t* p) { return std::bit_cast<float>(get32(p)); }

/// The first field that makes a record unreadable, or nullptr.
const char* bad_field(const Ray& r) {
  static const char* names[2][3] = {{"org.x", "org.y", "org.z"}, {"dir.x", "dir.y", "dir.z"}};
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(r.org[a])) return names[0][a];
    if (!std::isfinite(r.dir[a])) return names[1][a];
  }
  if (!std::isfinite(r.tnear)) return "tnear";
  if (std::isnan(r.tfar)) return "tfar";
  return nullptr;
}

std::string errno_text() { return std::strerror(errno); }

}  // namespace

uint64_t scene_fingerprint(const Scene& scene) {
  uint64_t h = 0xCBF29CE484222325ull;  // FNV-1a 64
  auto eat = [&h](uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) {
      h ^= (v >> (8 * i)) & 0xFF;
      h *= 0x100000001B3ull;
    }
  };
  eat(scene.triangles.size(), 8);
  for (const Triangle& t : scene.triangles)
    for (const Vec3* v : {&t.v0, &t.v1, &t.v2})
      for (int a = 0; a < 3; ++a) eat(std::bit_cast<uint32_t>((*v)[a]), 4);
  return h;
}

// ---- writer -----------------------------------------------------------------------------------

RayStreamWriter::RayStreamWriter(const std::string& path, const StreamHeader& header)
    : path_(path) {
  if (header.version != kVersion)
    throw StreamError(path + ": this writer writes ray-stream version " + std::to_string(kVersion) +
                      ", not " + std::to_string(header.version));
  const size_t header_len = (kFixedHeader + header.options.size() + kAlign - 1) / kAlign * kAlign;
  std::vector<uint8_t> h(header_len, 0);
  std::memcpy(h.data(), kMagic, 8);
  put32(&h[8], kVersion);
  put32(&h[12], static_cast<uint32_t>(header_len));
  put64(&h[16], header.scene_fingerprint);
  put64(&h[24], 0);  // ray count, written by close()
  put32(&h[32], static_cast<uint32_t>(header.options.size()));
  std::memcpy(&h[kFixedHeader], header.options.data(), header.options.size());
  count_offset_ = kCountOffset;
  try {
    file_.emplace(path);
    file_->write(h.data(), h.size());
  } catch (const AtomicFileError& e) {
    file_.reset();
    throw StreamError(e.what());
  }
}

RayStreamWriter::~RayStreamWriter() = default;  // without close(): file_ removes the temporary

void RayStreamWriter::write(const RayRecord& r) {
  if (!file_) throw StreamError(path_ + ": write after close");
  if (const char* field = bad_field(r.ray))
    throw StreamError(path_ + ": record " + std::to_string(count_) + ": NaN or infinite field (" +
                      field + "); not written");
  std::array<uint8_t, kRecord> b{};
  for (int a = 0; a < 3; ++a) {
    putf(&b[4 * a], r.ray.org[a]);
    putf(&b[12 + 4 * a], r.ray.dir[a]);
  }
  putf(&b[24], r.ray.tnear);
  putf(&b[28], r.ray.tfar);
  b[32] = static_cast<uint8_t>(r.kind);
  b[33] = r.depth;
  // 34, 35: reserved, zero
  put32(&b[36], r.pixel);
  put32(&b[40], r.sample);
  put32(&b[44], r.spawn_prim);
  put64(&b[48], r.id);
  put64(&b[56], r.parent);
  if (std::fwrite(b.data(), 1, b.size(), file_->stream()) != b.size())
    throw StreamError(file_->tmp_path() + ": write error at record " + std::to_string(count_) +
                      ": " + errno_text());
  ++count_;
}

void RayStreamWriter::close() {
  if (!file_) return;
  uint8_t c[8];
  put64(c, count_);
  std::FILE* f = file_->stream();
  try {
    if (!(std::fflush(f) == 0 && std::fseek(f, count_offset_, SEEK_SET) == 0 &&
          std::fwrite(c, 1, 8, f) == 8))
      file_->fail(errno_text());
    file_->commit();
  } catch (const AtomicFileError& e) {
    file_.reset();
    throw StreamError(e.what());
  }
  file_.reset();
}

// ---- reader -----------------------------------------------------------------------------------

RayStreamReader::RayStreamReader(const std::string& path) : path_(path) {
  f_ = std::fopen(path.c_str(), "rb");
  if (!f_) throw StreamError(path + ": cannot open: " + errno_text());
  struct stat st;
  if (fstat(fileno(f_), &st) != 0 || !S_ISREG(st.st_mode)) {
    std::fclose(f_);
    f_ = nullptr;
    throw StreamError(path + ": not a regular file");
  }
  const uint64_t size = static_cast<uint64_t>(st.st_size);
  auto fail = [&](const std::string& what) {
    std::fclose(f_);
    f_ = nullptr;
    throw StreamError(path + ": " + what);
  };
  uint8_t h[kFixedHeader];
  const size_t got = std::fread(h, 1, kFixedHeader, f_);
  if (got < 8 ? std::memcmp(h, kMagic, got) != 0 : std::memcmp(h, kMagic, 8) != 0)
    fail("not a ray stream (bad magic)");
  if (got < kFixedHeader)
    fail("truncated header (" + std::to_string(got) + " bytes, the fixed part alone is " +
         std::to_string(kFixedHeader) + ")");
  header_.version = get32(&h[8]);
  if (header_.version != kVersion)
    fail("ray-stream version " + std::to_string(header_.version) +
         " is not supported (this reader reads version " + std::to_string(kVersion) + ")");
  const uint64_t header_len = get32(&h[12]);
  header_.scene_fingerprint = get64(&h[16]);
  header_.ray_count = get64(&h[24]);
  const uint64_t options_len = get32(&h[32]);
  if (header_len < kFixedHeader + options_len || header_len % kAlign != 0)
    fail("bad header length " + std::to_string(header_len) + " (options " +
         std::to_string(options_len) + " bytes; must be a multiple of 64 holding them)");
  if (size < header_len)
    fail("truncated header (" + std::to_string(size) + " of " + std::to_string(header_len) +
         " bytes)");
  header_.options.resize(options_len);
  if (options_len && std::fread(header_.options.data(), 1, options_len, f_) != options_len)
    fail("read error in the header");
  if (std::fseek(f_, static_cast<long>(header_len), SEEK_SET) != 0) fail("seek error");
  const uint64_t body = size - header_len;
  const uint64_t whole = body / kRecord;
  if (whole < header_.ray_count)
    fail("truncated at record " + std::to_string(whole) + " (expected " +
         std::to_string(header_.ray_count) + " records)");
  if (body != header_.ray_count * kRecord)
    fail(std::to_string(body - header_.ray_count * kRecord) + " bytes after the " +
         std::to_string(header_.ray_count) + " records the header announces");
}

RayStreamReader::~RayStreamReader() {
  if (f_) std::fclose(f_);
}

bool RayStreamReader::next(RayRecord* r) {
  if (!f_ || read_ >= header_.ray_count) return false;
  std::array<uint8_t, kRecord> b;
  if (std::fread(b.data(), 1, kRecord, f_) != kRecord)
    throw StreamError(path_ + ": truncated at record " + std::to_string(read_) + " (expected " +
                      std::to_string(header_.ray_count) + " records)");
  const std::string where = path_ + ": record " + std::to_string(read_) + ": ";
  RayRecord out;
  for (int a = 0; a < 3; ++a) {
    out.ray.org[a] = getf(&b[4 * a]);
    out.ray.dir[a] = getf(&b[12 + 4 * a]);
  }
  out.ray.tnear = getf(&b[24]);
  out.ray.tfar = getf(&b[28]);
  if (const char* field = bad_field(out.ray))
    throw StreamError(where + "NaN or infinite field (" + field + ")");
  if (b[32] >= kNumRayKinds) throw StreamError(where + "unknown ray kind " + std::to_string(b[32]));
  out.kind = static_cast<RayKind>(b[32]);
  out.depth = b[33];
  if (b[34] || b[35]) throw StreamError(where + "reserved bytes 34-35 are not zero");
  out.pixel = get32(&b[36]);
  out.sample = get32(&b[40]);
  out.spawn_prim = get32(&b[44]);
  out.id = get64(&b[48]);
  out.parent = get64(&b[56]);
  *r = out;
  ++read_;
  return true;
}

}  // namespace hrpp
