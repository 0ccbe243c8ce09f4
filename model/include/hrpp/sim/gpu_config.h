// A GPU configuration for the RT-unit model (docs/timing_model.md): RT units and their ray
// buffers, the caches, DRAM and the test pipelines, as read from a data file (model/gpu/*.json,
// every number's source in the file's "sources" and in docs/timing_model.md).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace hrpp::sim {

struct PipeConfig {
  uint32_t latency = 0;    // cycles from issue to result
  uint32_t per_cycle = 0;  // tests issued per cycle and RT unit (0: unbounded)
};

struct CacheConfig {
  uint64_t bytes = 0;
  uint32_t ways = 0, line_bytes = 0;
  uint32_t hit_latency = 0;         // cycles from the request to the data (L2: after the L1's miss)
  uint32_t mshrs = 0;               // misses outstanding at once (requests to a missing line merge)
  double bytes_per_cycle = 0;       // L2 only: bandwidth to the L1s (0: unbounded)
  uint32_t requests_per_cycle = 0;  // L1 only: line requests a unit sends per cycle (0: unbounded)
  /// A sectored cache (optional key; 0: not sectored): a line holds line_bytes / sector_bytes
  /// sectors, a request reads one sector, and a miss fetches only the sector it needs (the line
  /// is allocated, evicting its set's least recently used line, when absent).
  uint32_t sector_bytes = 0;
  uint32_t sets() const { return uint32_t(bytes / line_bytes / ways); }
  /// The bytes a request reads and a miss fetches: the sector, or the line.
  uint32_t block_bytes() const { return sector_bytes ? sector_bytes : line_bytes; }
};

struct DramConfig {
  uint32_t latency = 0;        // cycles after the L2's miss
  double bytes_per_cycle = 0;  // 0: unbounded
};

/// How the RT unit reads the BVH (optional "rt_unit" object; each key optional, the defaults are
/// the project's own unit: docs/timing_model.md, "MICRO 2021's timing").
struct RtUnitConfig {
  /// 0: a fetch reads its whole record (a node pair, a leaf's triangles). N: every record fetch is
  /// one request for the N-byte aligned block holding the record's first byte.
  uint32_t request_bytes = 0;
  /// false: a leaf's triangles are one fetch and one issue of their tests. true: one fetch and
  /// one test per triangle record, one after the other.
  bool triangle_records = false;
  uint32_t triangle_bytes = 0;  // a triangle record's bytes in memory (0: ours, 36)
  uint32_t leaf_end_bytes = 0;  // bytes after each leaf's triangles (a terminator record)
  uint32_t launch_latency = 0;  // cycles added to every run (a kernel launch)
  bool is_default() const {
    return !request_bytes && !triangle_records && !triangle_bytes && !leaf_end_bytes &&
           !launch_latency;
  }
};

struct GpuConfig {
  std::string name, description;
  double clock_mhz = 0;
  uint32_t units = 0;           // RT units (one per SM)
  uint32_t warps_per_unit = 0;  // the ray buffer: warps a unit holds at once
  uint32_t warp_size = 0;
  CacheConfig l1, l2;  // l1: per unit; l2: shared
  DramConfig dram;
  PipeConfig box;       // node tests: one test = both child boxes of a node
  PipeConfig triangle;  // triangle tests
  RtUnitConfig rt;
  nlohmann::json sources = nlohmann::json::object();

  /// "" when usable, else what is wrong.
  std::string validate() const;
  nlohmann::json to_json() const;
};

struct GpuConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Reads a configuration; throws GpuConfigError naming `origin` and the offending key (unknown
/// keys included, so that a misspelt key is never silently ignored).
GpuConfig gpu_config_from_json(const nlohmann::json& j, const std::string& origin);
/// Reads a configuration file.
GpuConfig load_gpu_config(const std::string& path);

}  // namespace hrpp::sim
