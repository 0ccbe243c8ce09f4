// Fuzz target: the ray-stream reader (model/src/workload/ray_stream.cc) on any bytes. Properties:
// it either reads every record the header announces or throws a StreamError whose message names the
// file; every record it returns has finite origin, direction and tnear, a known kind and zero
// reserved bytes; and what it read, written again with RayStreamWriter and read back, gives the
// same records bit for bit.
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "fuzz_util.h"
#include "hrpp/workload/ray_stream.h"

using namespace hrpp;

namespace {

std::string temp_path(const char* what) {
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/hrpp-fuzz-stream-" + std::to_string(getpid()) +
         what;
}

bool same(const RayRecord& a, const RayRecord& b) {
  auto bits = [](float f) { return std::bit_cast<uint32_t>(f); };
  for (int i = 0; i < 3; ++i)
    if (bits(a.ray.org[i]) != bits(b.ray.org[i]) || bits(a.ray.dir[i]) != bits(b.ray.dir[i]))
      return false;
  return bits(a.ray.tnear) == bits(b.ray.tnear) && bits(a.ray.tfar) == bits(b.ray.tfar) &&
         a.kind == b.kind && a.depth == b.depth && a.pixel == b.pixel && a.sample == b.sample &&
         a.spawn_prim == b.spawn_prim && a.id == b.id && a.parent == b.parent;
}

std::vector<RayRecord> read_all(const std::string& path, StreamHeader* header) {
  RayStreamReader rd(path);
  *header = rd.header();
  std::vector<RayRecord> out;
  RayRecord r;
  while (rd.next(&r)) {
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(r.ray.org[i]) || !std::isfinite(r.ray.dir[i]))
        fuzz::violated("a record with a non-finite origin or direction was returned");
    if (!std::isfinite(r.ray.tnear) || std::isnan(r.ray.tfar))
      fuzz::violated("a record with a non-finite tnear or NaN tfar was returned");
    if (static_cast<int>(r.kind) >= kNumRayKinds) fuzz::violated("unknown kind returned");
    out.push_back(r);
  }
  if (out.size() != rd.header().ray_count || rd.records_read() != out.size())
    fuzz::violated("read " + std::to_string(out.size()) + " records, header announces " +
                   std::to_string(rd.header().ray_count));
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string in_path = temp_path(".rays"), out_path = temp_path("-rewritten.rays");
  std::FILE* f = std::fopen(in_path.c_str(), "wb");
  if (!f || std::fwrite(data, 1, size, f) != size || std::fclose(f) != 0) {
    std::perror(in_path.c_str());
    std::abort();  // the machine's problem, not the input's
  }
  std::vector<RayRecord> recs;
  StreamHeader header;
  try {
    recs = read_all(in_path, &header);
  } catch (const StreamError& e) {
    if (std::string(e.what()).rfind(in_path + ": ", 0) != 0)
      fuzz::violated(std::string("StreamError message does not name the file: ") + e.what());
    return 0;
  }
  {
    RayStreamWriter w(out_path, header);
    for (const RayRecord& r : recs) w.write(r);
    w.close();
  }
  StreamHeader h2;
  const std::vector<RayRecord> again = read_all(out_path, &h2);
  if (again.size() != recs.size() || h2.options != header.options ||
      h2.scene_fingerprint != header.scene_fingerprint)
    fuzz::violated("rewritten stream differs in its header or record count");
  for (size_t i = 0; i < recs.size(); ++i)
    if (!same(recs[i], again[i])) fuzz::violated("record " + std::to_string(i) + " changed");
  std::remove(out_path.c_str());
  return 0;
}
