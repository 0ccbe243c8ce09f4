#include "hrpp/predictor/presets.h"

#include <stdexcept>

#include "hrpp/hardware/rtl_config.h"

namespace hrpp {

std::vector<std::string> preset_names() {
  std::vector<std::string> names;
  for (const std::string& n : rtl_config_names()) names.push_back("rtl-" + n);
  names.emplace_back("micro21");
  names.emplace_back("study2019");
  return names;
}

PredictorPreset predictor_preset(const std::string& name) {
  PredictorPreset p;
  p.name = name;
  if (name.rfind("rtl-", 0) == 0 && name.size() > 4) {
    const RtlConfig rc = rtl_config(name.substr(4));  // throws for an unknown configuration
    p.description = "the RTL configuration '" + rc.name + "' (rtl/config/hrpp_configs.json)";
    p.hash = rc.hash;
    p.table = rc.table;
    p.tag_bits = rc.table.tag_bits;
    if (rc.any_hit_only) p.any_hit_only = true;  // else left to the caller, as before
    return p;
  }
  if (name == "micro21") {
    // MICRO 2021 (Liu et al.), as configs/tested-cfgs/MOBILE/gpgpusim.config of
    // ubc-aamodt-group/ray-intersection-predictor sets it: grid-spherical hash (5 grid bits, 3
    // sphere bits), 1024 entries 4-way set-associative LRU, 1 node per entry, go-up level 3,
    // full-hash tags; the predictor sees any-hit rays only (docs/hash.md, "micro21").
    p.description =
        "MICRO 2021's predictor: grid-spherical hash, 256x4 table, K=1, go-up 3, "
        "any-hit rays only";
    p.hash.variant = HashVariant::kMicro21;
    p.hash.origin_bits = 5;
    p.hash.dir_bits = 3;
    p.hash.combine = CombineMode::kXor;
    p.table.unbounded = false;
    p.table.sets = 256;
    p.table.ways = 4;
    p.table.nodes_per_entry = 1;
    p.tag_bits = -1;
    p.go_up = 3;
    p.mode = PredictMode::kClosestExact;  // closest-hit rays are not predicted: no effect
    p.any_hit_only = true;
    return p;
  }
  if (name == "study2019") {
    // The 2019 limit study's setting as docs/results.md reproduces its Table 1: faithful hash
    // (P = 6, E = 3, origin XOR direction), an unbounded table with 2 node ids per entry, go-up 0.
    p.description =
        "the 2019 study's limit setting: faithful hash P=6 E=3 xor, unbounded table, "
        "K=2, go-up 0";
    p.hash.variant = HashVariant::kFaithful;
    p.hash.precision = 6;
    p.hash.exp_bits = 3;
    p.hash.combine = CombineMode::kXor;
    p.table.unbounded = true;
    p.table.nodes_per_entry = 2;
    p.tag_bits = -1;
    p.go_up = 0;
    p.any_hit_only = false;
    return p;
  }
  std::string known;
  for (const std::string& n : preset_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown predictor preset '" + name + "' (known: " + known + ")");
}

PredictorConfig apply_preset(const PredictorPreset& p, PredictorConfig base) {
  base.hash = p.hash;
  base.table = p.table;
  if (p.go_up) base.go_up = *p.go_up;
  if (p.mode) base.mode = *p.mode;
  if (p.any_hit_only) base.any_hit_only = *p.any_hit_only;
  return base;
}

}  // namespace hrpp
