#include "hrpp/sim/gpu_config.h"

#include <bit>
#include <cmath>
#include <fstream>
#include <set>

namespace hrpp::sim {
namespace {

// Reads the keys of one JSON object, each once, and rejects the ones it did not read.
class Reader {
 public:
  Reader(const nlohmann::json& j, std::string where) : j_(j), where_(std::move(where)) {
    if (!j.is_object()) fail("is not a JSON object");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw GpuConfigError(where_ + " " + what);
  }
  bool has(const char* key) const { return j_.contains(key); }
  const nlohmann::json& at(const char* key) {
    seen_.insert(key);
    if (!j_.contains(key)) fail("has no \"" + std::string(key) + "\"");
    return j_.at(key);
  }
  double number(const char* key, bool allow_zero) {
    const nlohmann::json& v = at(key);
    if (!v.is_number()) fail("\"" + std::string(key) + "\" must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < 0 || (!allow_zero && d == 0))
      fail("\"" + std::string(key) + "\" must be " + (allow_zero ? ">= 0" : "> 0") + ", got " +
           v.dump());
    return d;
  }
  uint32_t integer(const char* key, bool allow_zero = false) {
    const nlohmann::json& v = at(key);
    if (!v.is_number_integer() || v.get<int64_t>() < (allow_zero ? 0 : 1) ||
        v.get<int64_t>() > int64_t(1) << 31)
      fail("\"" + std::string(key) + "\" must be an integer " + (allow_zero ? ">= 0" : ">= 1") +
           ", got " + v.dump());
    return v.get<uint32_t>();
  }
  bool flag(const char* key) {
    const nlohmann::json& v = at(key);
    if (!v.is_boolean()) fail("\"" + std::string(key) + "\" must be true or false");
    return v.get<bool>();
  }
  std::string text(const char* key) {
    const nlohmann::json& v = at(key);
    if (!v.is_string()) fail("\"" + std::string(key) + "\" must be a string");
    return v.get<std::string>();
  }
  void done() const {
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!seen_.count(it.key())) fail("has an unknown key \"" + it.key() + "\"");
  }

 private:
  const nlohmann::json& j_;
  std::string where_;
  std::set<std::string> seen_;
};

CacheConfig read_cache(const nlohmann::json& j, const std::string& where, bool l2) {
  Reader r(j, where);
  CacheConfig c;
  c.bytes = r.integer("bytes");
  c.ways = r.integer("ways");
  c.line_bytes = r.integer("line_bytes");
  c.hit_latency = r.integer("hit_latency", true);
  c.mshrs = r.integer("mshrs");
  if (l2) c.bytes_per_cycle = r.number("bytes_per_cycle", true);
  if (!l2) c.requests_per_cycle = r.integer("requests_per_cycle", true);
  if (r.has("sector_bytes")) c.sector_bytes = r.integer("sector_bytes");
  r.done();
  return c;
}

PipeConfig read_pipe(const nlohmann::json& j, const std::string& where) {
  Reader r(j, where);
  PipeConfig p;
  p.latency = r.integer("latency", true);
  p.per_cycle = r.integer("per_cycle", true);
  r.done();
  return p;
}

std::string check_cache(const CacheConfig& c, const char* name) {
  const std::string n(name);
  if (!std::has_single_bit(c.line_bytes) || c.line_bytes < 16)
    return n + ".line_bytes must be a power of two >= 16";
  if (c.ways == 0 || c.bytes % (uint64_t(c.line_bytes) * c.ways) != 0 || c.sets() == 0)
    return n + ".bytes must be a multiple of line_bytes x ways";
  if (!std::has_single_bit(c.sets()))
    return n + ": bytes / line_bytes / ways = " + std::to_string(c.sets()) +
           " sets, not a power of two";
  if (c.mshrs == 0) return n + ".mshrs must be >= 1";
  if (c.sector_bytes &&
      (!std::has_single_bit(c.sector_bytes) || c.sector_bytes < 4 || c.sector_bytes > c.line_bytes))
    return n + ".sector_bytes must be a power of two from 4 to line_bytes";
  return {};
}

}  // namespace

std::string GpuConfig::validate() const {
  if (units == 0 || warps_per_unit == 0 || warp_size == 0)
    return "units, warps_per_unit and warp_size must be >= 1";
  if (units > 4096 || warps_per_unit > 4096 || warp_size > 1024)
    return "units (<= 4096), warps_per_unit (<= 4096) or warp_size (<= 1024) out of range";
  for (const auto& [c, n] : {std::pair{&l1, "l1"}, std::pair{&l2, "l2"}})
    if (std::string e = check_cache(*c, n); !e.empty()) return e;
  if (l2.line_bytes < l1.line_bytes) return "l2.line_bytes must be >= l1.line_bytes";
  if (l2.block_bytes() < l1.block_bytes())
    return "the L2's block (sector or line) must be at least the L1's";
  if (rt.request_bytes &&
      (!std::has_single_bit(rt.request_bytes) || rt.request_bytes > l1.block_bytes()))
    return "rt_unit.request_bytes must be a power of two no larger than the L1's block";
  return {};
}

nlohmann::json GpuConfig::to_json() const {
  auto cache = [](const CacheConfig& c, bool l2) {
    nlohmann::json j = {{"bytes", c.bytes},
                        {"ways", c.ways},
                        {"line_bytes", c.line_bytes},
                        {"hit_latency", c.hit_latency},
                        {"mshrs", c.mshrs}};
    if (l2) j["bytes_per_cycle"] = c.bytes_per_cycle;
    if (!l2) j["requests_per_cycle"] = c.requests_per_cycle;
    if (c.sector_bytes) j["sector_bytes"] = c.sector_bytes;
    return j;
  };
  auto pipe = [](const PipeConfig& p) {
    return nlohmann::json{{"latency", p.latency}, {"per_cycle", p.per_cycle}};
  };
  nlohmann::json j = {
      {"name", name},
      {"description", description},
      {"clock_mhz", clock_mhz},
      {"units", units},
      {"warps_per_unit", warps_per_unit},
      {"warp_size", warp_size},
      {"l1", cache(l1, false)},
      {"l2", cache(l2, true)},
      {"dram", {{"latency", dram.latency}, {"bytes_per_cycle", dram.bytes_per_cycle}}},
      {"box", pipe(box)},
      {"triangle", pipe(triangle)},
      {"sources", sources}};
  if (!rt.is_default())
    j["rt_unit"] = {{"request_bytes", rt.request_bytes},
                    {"triangle_records", rt.triangle_records},
                    {"triangle_bytes", rt.triangle_bytes},
                    {"leaf_end_bytes", rt.leaf_end_bytes},
                    {"launch_latency", rt.launch_latency}};
  return j;
}

GpuConfig gpu_config_from_json(const nlohmann::json& j, const std::string& origin) {
  Reader r(j, origin + ":");
  GpuConfig g;
  g.name = r.text("name");
  g.description = r.text("description");
  g.clock_mhz = r.number("clock_mhz", false);
  g.units = r.integer("units");
  g.warps_per_unit = r.integer("warps_per_unit");
  g.warp_size = r.integer("warp_size");
  g.l1 = read_cache(r.at("l1"), origin + ": l1", false);
  g.l2 = read_cache(r.at("l2"), origin + ": l2", true);
  {
    Reader d(r.at("dram"), origin + ": dram");
    g.dram.latency = d.integer("latency", true);
    g.dram.bytes_per_cycle = d.number("bytes_per_cycle", true);
    d.done();
  }
  g.box = read_pipe(r.at("box"), origin + ": box");
  g.triangle = read_pipe(r.at("triangle"), origin + ": triangle");
  if (r.has("rt_unit")) {
    Reader u(r.at("rt_unit"), origin + ": rt_unit");
    if (u.has("request_bytes")) g.rt.request_bytes = u.integer("request_bytes");
    if (u.has("triangle_records")) g.rt.triangle_records = u.flag("triangle_records");
    if (u.has("triangle_bytes")) g.rt.triangle_bytes = u.integer("triangle_bytes");
    if (u.has("leaf_end_bytes")) g.rt.leaf_end_bytes = u.integer("leaf_end_bytes", true);
    if (u.has("launch_latency")) g.rt.launch_latency = u.integer("launch_latency", true);
    u.done();
  }
  g.sources = r.at("sources");
  if (!g.sources.is_object()) r.fail("\"sources\" must be an object");
  r.done();
  if (const std::string e = g.validate(); !e.empty()) throw GpuConfigError(origin + ": " + e);
  return g;
}

GpuConfig load_gpu_config(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw GpuConfigError("cannot read the GPU configuration " + path);
  nlohmann::json j = nlohmann::json::parse(f, nullptr, false);
  if (j.is_discarded()) throw GpuConfigError(path + " is not valid JSON");
  return gpu_config_from_json(j, path);
}

}  // namespace hrpp::sim
