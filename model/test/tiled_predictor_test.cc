// The predictor on several cores (TiledPredictor): the statistics depend on the number of cores
// (each owns its table) but never on the number of threads that run them, and one core is the
// plain Predictor ray for ray.
#include "hrpp/predictor/tiled_predictor.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>

#include "test_util.h"

namespace hrpp {
namespace {

struct Fixture {
  Scene scene;
  Bvh bvh;
  PredictorConfig cfg;
  WorkloadOptions wo;
};

Fixture make_fixture() {
  Fixture f{load_scene(std::string(HRPP_SOURCE_DIR) + "/scenes/spd_balls.glb"), {}, {}, {}};
  f.bvh = build_bvh(f.scene.triangles);
  PredictorConfig& c = f.cfg;
  c.mode = PredictMode::kClosestExact;
  c.hash.variant = HashVariant::kImproved;
  c.hash.combine = CombineMode::kConcat;
  c.hash.origin_cell_exp = cell_exp_for(f.scene.bounds, c.hash.origin_bits);
  c.table.sets = 64;
  c.table.ways = 4;
  c.table.nodes_per_entry = 2;
  c.hash.index_bits = 6;
  c.table.node_bits = node_bits_for(f.bvh.nodes.size());
  c.table.tag_bits = c.hash.tag_bits();
  c.table.key_bits = c.hash.key_bits();
  f.wo.width = 80;
  f.wo.height = 60;
  f.wo.spp = 2;
  f.wo.order = RayOrder::kMorton;
  return f;
}

nlohmann::json run(const Fixture& f, uint32_t cores, uint32_t threads, uint32_t batch = 4096) {
  TiledOptions o;
  o.cores = cores;
  o.threads = threads;
  o.width = static_cast<uint32_t>(f.wo.width);
  o.batch = batch;
  o.queue_batches = batch < 100 ? 1 : 4;  // small batches and queues: the producer blocks often
  TiledPredictor p(f.bvh, f.cfg, o);
  generate_rays(f.scene, f.bvh, f.wo, [&](const RayRecord& r, const Hit*) { p.push(r); });
  p.finish();
  return p.to_json();
}

TEST(TiledPredictor, OneCoreIsThePlainPredictor) {
  const Fixture f = make_fixture();
  Predictor plain(f.bvh, f.cfg);
  generate_rays(f.scene, f.bvh, f.wo, [&](const RayRecord& r, const Hit*) { plain.process(r); });
  ASSERT_GT(plain.total().true_positive, 0u) << "no verified prediction: the test would be vacuous";
  EXPECT_EQ(run(f, 1, 1), plain.to_json());
  EXPECT_EQ(run(f, 1, 2), plain.to_json());  // one worker thread beside the producer
}

TEST(TiledPredictor, StatisticsDoNotDependOnTheThreadCount) {
  const Fixture f = make_fixture();
  const nlohmann::json one = run(f, 4, 1);
  ASSERT_GT(one["rays"].get<uint64_t>(), 10000u);
  ASSERT_GT(one["true_positive"].get<uint64_t>(), 0u);
  EXPECT_EQ(one["cores"], 4);
  for (uint32_t threads : {2u, 3u, 4u, 8u}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    EXPECT_EQ(run(f, 4, threads), one);
  }
  EXPECT_EQ(run(f, 4, 3, /*batch=*/17), one);
  // Separate tables see fewer similar rays than one shared table: the cores matter.
  const nlohmann::json shared = run(f, 1, 1);
  EXPECT_EQ(shared["rays"], one["rays"]);
  EXPECT_NE(shared["true_positive"], one["true_positive"]);
}

TEST(TiledPredictor, CoresFollowImageTiles) {
  const Fixture f = make_fixture();
  TiledOptions o;
  o.cores = 3;
  o.width = 80;
  o.tile = 8;
  TiledPredictor p(f.bvh, f.cfg, o);
  RayRecord r;
  r.pixel = 0;
  EXPECT_EQ(p.core_of(r), 0u);
  r.pixel = 7 * 80 + 7;  // same tile
  EXPECT_EQ(p.core_of(r), 0u);
  r.pixel = 8;  // next tile to the right
  EXPECT_EQ(p.core_of(r), 1u);
  r.pixel = 8 * 80;  // first tile of the second tile row: tile 10 (10 tiles per row)
  EXPECT_EQ(p.core_of(r), 10u % 3);
}

TEST(TiledPredictor, RejectsBadOptions) {
  const Fixture f = make_fixture();
  TiledOptions o;
  o.cores = 2;  // no width
  EXPECT_THROW(TiledPredictor(f.bvh, f.cfg, o), std::invalid_argument);
  o.width = 10;
  o.threads = 0;
  EXPECT_THROW(TiledPredictor(f.bvh, f.cfg, o), std::invalid_argument);
}

// hrpp predict --cores/--threads, from a ray-stream file (the image width comes from its header).
int tool(const std::string& args, std::string* out) {
  FILE* p = popen((std::string(HRPP_TOOL) + " " + args + " 2>&1").c_str(), "r");
  char buf[4096];
  for (size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) out->append(buf, n);
  const int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream f(path);
  nlohmann::json j = nlohmann::json::parse(f);
  j.erase("seconds");
  j.erase("threads");
  j.erase("tool");  // its command line and timestamp
  j["workload"].erase("stream");
  return j;
}

TEST(TiledPredictor, ToolGivesTheSameStatisticsForAnyThreadCount) {
  const std::string dir = test::temp_dir("tiled_tool");
  const std::string scene = std::string(HRPP_SOURCE_DIR) + "/scenes/spd_balls.glb";
  std::string out;
  ASSERT_EQ(tool("trace " + scene + " --effects shadow,ao --res 192x144 --order morton --out " +
                     dir + "/s.rays",
                 &out),
            0)
      << out;
  const std::string base =
      "predict " + scene + " --stream " + dir + "/s.rays --table 64x4 --cores 4";
  ASSERT_EQ(tool(base + " --threads 1 --json " + dir + "/1.json", &out), 0) << out;
  ASSERT_EQ(tool(base + " --threads 3 --json " + dir + "/3.json", &out), 0) << out;
  const nlohmann::json one = read_json(dir + "/1.json"), three = read_json(dir + "/3.json");
  EXPECT_EQ(one["cores"], 4);
  EXPECT_GT(one["true_positive"].get<uint64_t>(), 0u);
  EXPECT_EQ(one, three);
  out.clear();
  EXPECT_EQ(tool(base + " --threads 0", &out), 2) << out;
}

}  // namespace
}  // namespace hrpp
