// Ray-stream files (docs/ray_stream.md): round trip, byte-identical determinism, every malformed
// file named with its record number, and the command-line errors of trace / predict / render.
#include "hrpp/workload/ray_stream.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "test_util.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;

std::string own(const std::string& name) {
  return std::string(HRPP_SOURCE_DIR) + "/scenes/" + name;
}

std::vector<char> read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<char>(std::istreambuf_iterator<char>(f), {});
}
void write_bytes(const std::string& path, const std::vector<char>& b) {
  std::ofstream(path, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
}

/// Writes a scene's workload to PATH; returns the records.
std::vector<RayRecord> write_stream(const Scene& s, const WorkloadOptions& wo,
                                    const std::string& path) {
  Bvh bvh = build_bvh(s.triangles);
  StreamHeader h;
  h.scene_fingerprint = scene_fingerprint(s);
  h.options = workload_json(s, wo).dump();
  RayStreamWriter w(path, h);
  std::vector<RayRecord> out;
  generate_rays(s, bvh, wo, [&](const RayRecord& r, const Hit*) {
    w.write(r);
    out.push_back(r);
  });
  w.close();
  return out;
}

bool same_record(const RayRecord& a, const RayRecord& b) {
  return std::memcmp(&a.ray, &b.ray, sizeof(Ray)) == 0 && a.kind == b.kind && a.pixel == b.pixel &&
         a.sample == b.sample && a.id == b.id && a.parent == b.parent &&
         a.spawn_prim == b.spawn_prim && a.depth == b.depth;
}

/// The message of the StreamError that reading all of PATH throws ("" when none).
std::string read_error(const std::string& path, uint64_t* records = nullptr) {
  try {
    RayStreamReader r(path);
    RayRecord rec;
    while (r.next(&rec)) {
    }
    if (records) *records = r.records_read();
  } catch (const StreamError& e) {
    return e.what();
  }
  return "";
}

class Stream : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir(::testing::UnitTest::GetInstance()->current_test_info()->name());
    scene_ = load_scene(own("glass_spheres.glb"));
    wo_.width = 24;
    wo_.height = 16;
    ASSERT_EQ(apply_effects("auto,ao,diffuse", scene_, &wo_), "");
    path_ = dir_ + "/a.rays";
    rays_ = write_stream(scene_, wo_, path_);
    bytes_ = read_bytes(path_);
    header_len_ = 0;
    std::memcpy(&header_len_, &bytes_[12], 4);
  }
  std::string dir_, path_;
  Scene scene_;
  WorkloadOptions wo_;
  std::vector<RayRecord> rays_;
  std::vector<char> bytes_;
  uint32_t header_len_;
};

TEST_F(Stream, RoundTripGivesIdenticalRays) {
  RayStreamReader r(path_);
  EXPECT_EQ(r.header().version, 1u);
  EXPECT_EQ(r.header().scene_fingerprint, scene_fingerprint(scene_));
  EXPECT_EQ(r.header().ray_count, rays_.size());
  EXPECT_EQ(nlohmann::json::parse(r.header().options), workload_json(scene_, wo_));
  RayRecord rec;
  size_t i = 0;
  while (r.next(&rec)) {
    ASSERT_LT(i, rays_.size());
    ASSERT_TRUE(same_record(rec, rays_[i])) << "record " << i;
    ++i;
  }
  EXPECT_EQ(i, rays_.size());
  EXPECT_EQ(r.records_read(), rays_.size());
  EXPECT_GT(rays_.size(), 1000u);
  // Layout: header padded to 64 bytes, then 64 bytes per record.
  EXPECT_EQ(header_len_ % 64, 0u);
  EXPECT_EQ(bytes_.size(), header_len_ + 64 * rays_.size());
  EXPECT_EQ(std::string(bytes_.data(), 8), "HRPPRAYS");
  EXPECT_FALSE(fs::exists(path_ + ".tmp"));
}

TEST_F(Stream, SameOptionsGiveByteIdenticalStreams) {
  write_stream(scene_, wo_, dir_ + "/b.rays");
  EXPECT_TRUE(read_bytes(dir_ + "/b.rays") == bytes_);
  for (RayOrder o : {RayOrder::kTiled, RayOrder::kMorton}) {
    WorkloadOptions wo = wo_;
    wo.order = o;
    write_stream(scene_, wo, dir_ + "/c.rays");
    write_stream(scene_, wo, dir_ + "/d.rays");
    EXPECT_TRUE(read_bytes(dir_ + "/c.rays") == read_bytes(dir_ + "/d.rays"));
    EXPECT_FALSE(read_bytes(dir_ + "/c.rays") == bytes_) << "the order is part of the stream";
  }
  WorkloadOptions other = wo_;
  other.seed = 2;
  write_stream(scene_, other, dir_ + "/e.rays");
  EXPECT_FALSE(read_bytes(dir_ + "/e.rays") == bytes_);
}

TEST_F(Stream, WrongMagic) {
  auto b = bytes_;
  b[3] = 'X';
  write_bytes(dir_ + "/m.rays", b);
  EXPECT_EQ(read_error(dir_ + "/m.rays"), dir_ + "/m.rays: not a ray stream (bad magic)");
  write_bytes(dir_ + "/glb.rays", read_bytes(own("cornell_box.glb")));
  EXPECT_NE(read_error(dir_ + "/glb.rays").find("bad magic"), std::string::npos);
}

TEST_F(Stream, WrongVersion) {
  auto b = bytes_;
  b[8] = 2;
  write_bytes(dir_ + "/v.rays", b);
  EXPECT_EQ(read_error(dir_ + "/v.rays"),
            dir_ + "/v.rays: ray-stream version 2 is not supported (this reader reads version 1)");
}

TEST_F(Stream, TruncatedHeaderAndRecords) {
  write_bytes(dir_ + "/h.rays", std::vector<char>(bytes_.begin(), bytes_.begin() + 20));
  EXPECT_NE(read_error(dir_ + "/h.rays").find("truncated header"), std::string::npos);
  write_bytes(dir_ + "/h2.rays", std::vector<char>(bytes_.begin(), bytes_.begin() + 50));
  EXPECT_NE(read_error(dir_ + "/h2.rays").find("truncated header"), std::string::npos);
  // Cut in the middle of record 100.
  write_bytes(dir_ + "/t.rays",
              std::vector<char>(bytes_.begin(), bytes_.begin() + header_len_ + 64 * 100 + 17));
  EXPECT_EQ(read_error(dir_ + "/t.rays"), dir_ + "/t.rays: truncated at record 100 (expected " +
                                              std::to_string(rays_.size()) + " records)");
  // Cut exactly after record 99.
  write_bytes(dir_ + "/t2.rays",
              std::vector<char>(bytes_.begin(), bytes_.begin() + header_len_ + 64 * 100));
  EXPECT_NE(read_error(dir_ + "/t2.rays").find("truncated at record 100"), std::string::npos);
  // No records at all.
  write_bytes(dir_ + "/t3.rays", std::vector<char>(bytes_.begin(), bytes_.begin() + header_len_));
  EXPECT_NE(read_error(dir_ + "/t3.rays").find("truncated at record 0"), std::string::npos);
}

TEST_F(Stream, RayCountMustMatchTheFileLength) {
  auto b = bytes_;
  b.insert(b.end(), 64, 0);  // one record more than the header says
  write_bytes(dir_ + "/x.rays", b);
  EXPECT_NE(read_error(dir_ + "/x.rays")
                .find("64 bytes after the " + std::to_string(rays_.size()) +
                      " records the header announces"),
            std::string::npos);
  b = bytes_;
  b.push_back(0);
  write_bytes(dir_ + "/y.rays", b);
  EXPECT_NE(read_error(dir_ + "/y.rays").find("1 bytes after"), std::string::npos);
}

TEST_F(Stream, NaNOrInfiniteRecordIsAnErrorWithItsNumber) {
  const float nan = std::nanf(""), inf = INFINITY;
  struct Case {
    int offset;  // within the record
    float value;
    const char* field;
  };
  for (const Case& c : {Case{0, nan, "org.x"}, Case{20, inf, "dir.z"}, Case{24, inf, "tnear"},
                        Case{28, nan, "tfar"}, Case{8, -inf, "org.z"}}) {
    auto b = bytes_;
    std::memcpy(&b[header_len_ + 64 * 7 + c.offset], &c.value, 4);
    write_bytes(dir_ + "/n.rays", b);
    uint64_t read = 0;
    EXPECT_EQ(read_error(dir_ + "/n.rays", &read),
              dir_ + "/n.rays: record 7: NaN or infinite field (" + c.field + ")");
  }
  // tfar = +inf is a valid ray (an unbounded closest-hit ray).
  auto b = bytes_;
  std::memcpy(&b[header_len_ + 64 * 7 + 28], &inf, 4);
  write_bytes(dir_ + "/ok.rays", b);
  uint64_t read = 0;
  EXPECT_EQ(read_error(dir_ + "/ok.rays", &read), "");
  EXPECT_EQ(read, rays_.size());
}

TEST_F(Stream, BadKindAndReservedBytes) {
  auto b = bytes_;
  b[header_len_ + 64 * 3 + 32] = 9;
  write_bytes(dir_ + "/k.rays", b);
  EXPECT_EQ(read_error(dir_ + "/k.rays"), dir_ + "/k.rays: record 3: unknown ray kind 9");
  b = bytes_;
  b[header_len_ + 64 * 4 + 35] = 1;
  write_bytes(dir_ + "/r.rays", b);
  EXPECT_EQ(read_error(dir_ + "/r.rays"),
            dir_ + "/r.rays: record 4: reserved bytes 34-35 are not zero");
}

TEST_F(Stream, WriterNeverLeavesAHalfWrittenFile) {
  const std::string p = dir_ + "/killed.rays";
  {
    RayStreamWriter w(p, StreamHeader{});
    for (int i = 0; i < 10; ++i) w.write(rays_[i]);
    EXPECT_TRUE(fs::exists(p + ".tmp"));
    EXPECT_FALSE(fs::exists(p));
  }  // destroyed without close(): as if the run was killed
  EXPECT_FALSE(fs::exists(p));
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  // A NaN ray is refused by the writer too.
  RayStreamWriter w(p, StreamHeader{});
  RayRecord bad = rays_[0];
  bad.ray.dir.y = std::nanf("");
  EXPECT_THROW(w.write(bad), StreamError);
  EXPECT_THROW(RayStreamWriter(dir_ + "/no/such/dir/x.rays", StreamHeader{}), StreamError);
  EXPECT_NE(read_error(dir_ + "/missing.rays").find("cannot open"), std::string::npos);
}

// ---- the tool ---------------------------------------------------------------------------------

struct RunResult {
  int code;
  std::string output;
};
RunResult run(const std::string& args) {
  const std::string cmd = std::string(HRPP_TOOL) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

void expect_error(const std::string& args, const std::string& message) {
  const RunResult r = run(args);
  EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
}

TEST_F(Stream, ToolErrors) {
  const std::string scene = own("cornell_box.glb"), out = dir_ + "/o.rays";
  expect_error("trace " + scene + " --effects shadows --out " + out, "unknown effect 'shadows'");
  expect_error("trace " + scene + " --order zigzag --out " + out, "--order");
  expect_error("trace " + scene + " --res 0x5 --out " + out, "--res must be WIDTHxHEIGHT");
  expect_error("trace " + scene + " --res 64 --out " + out, "--res must be WIDTHxHEIGHT");
  expect_error("trace " + scene, "--out is required");
  expect_error("trace " + scene + " --res 8x8 --out " + dir_ + "/nodir/o.rays",
               "/nodir' does not exist");
  expect_error("render " + scene + " --res 8x8 --out " + path_, "is a file, not a folder");
  expect_error("render " + scene + " --res 8x8 --effects ao,bogus --out " + dir_ + "/r",
               "unknown effect 'bogus'");
  expect_error("predict " + scene + " --stream " + dir_ + "/none.rays", "cannot open");
  expect_error("predict " + scene + " --stream " + scene, "not a ray stream (bad magic)");
  expect_error("predict " + scene + " --stream " + path_, "was generated from another scene");
  expect_error("predict " + own("glass_spheres.glb") + " --stream " + path_ + " --spp 2",
               "excludes");
  auto b = bytes_;
  b.resize(header_len_ + 64 * 5 + 3);
  write_bytes(dir_ + "/cut.rays", b);
  expect_error("predict " + own("glass_spheres.glb") + " --stream " + dir_ + "/cut.rays",
               "truncated at record 5 (expected");
  EXPECT_FALSE(fs::exists(out));
}

// `hrpp trace` then `hrpp predict --stream` gives exactly the figures of `hrpp predict` on the
// same workload.
TEST_F(Stream, PredictFromAStreamEqualsPredictOnTheGeneratedRays) {
  const std::string scene = own("glass_spheres.glb"), rays = dir_ + "/t.rays";
  const std::string w = " --res 40x30 --spp 2 --effects auto,ao --order morton --tile 4";
  RunResult t = run("trace " + scene + w + " --out " + rays + " --json " + dir_ + "/trace.json");
  ASSERT_EQ(t.code, 0) << t.output;
  EXPECT_NE(t.output.find("refraction  on   derived: material 'glass'"), std::string::npos)
      << t.output;
  RunResult a = run("predict " + scene + w + " --json " + dir_ + "/a.json");
  RunResult b = run("predict " + scene + " --stream " + rays + " --json " + dir_ + "/b.json");
  ASSERT_EQ(a.code, 0) << a.output;
  ASSERT_EQ(b.code, 0) << b.output;
  auto ja = nlohmann::json::parse(std::ifstream(dir_ + "/a.json"));
  auto jb = nlohmann::json::parse(std::ifstream(dir_ + "/b.json"));
  auto jt = nlohmann::json::parse(std::ifstream(dir_ + "/trace.json"));
  EXPECT_EQ(ja["by_kind"], jb["by_kind"]);
  EXPECT_EQ(ja["rays"], jt["rays"]);
  for (const auto& [k, v] : jt["by_kind"].items()) EXPECT_EQ(ja["by_kind"][k]["rays"], v) << k;
  EXPECT_EQ(jb["workload"]["order"], "morton");
  EXPECT_EQ(ja["workload"]["order"], "morton");
  EXPECT_EQ(jb["workload"]["stream"], rays);
  EXPECT_TRUE(ja["by_kind"].contains("refraction"));
}

}  // namespace
}  // namespace hrpp
