// Named predictor presets: the RTL's configurations (rtl-NAME) and the published anchors
// (micro21, study2019), defined once here for `hrpp predict`, `hrpp render` and the simulator.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "hrpp/predictor/predictor.h"

namespace hrpp {

/// What a preset sets. The hash and the table always; go-up, mode and the ray kinds only where
/// the preset says (an rtl-NAME preset leaves them to the caller, as the RTL's configuration
/// does not fix them). origin_cell_exp, the bounds, index and tag widths come later from the
/// scene (resolve_for_scene).
struct PredictorPreset {
  std::string name;
  std::string description;
  HashConfig hash;
  TableConfig table;
  int tag_bits = -1;  // stored tag bits for resolve_for_scene (< 0: the full tag)
  std::optional<uint32_t> go_up;
  std::optional<PredictMode> mode;
  std::optional<bool> any_hit_only;
};

/// Every preset's name: "rtl-NAME" for each RTL configuration, then "micro21" and "study2019".
std::vector<std::string> preset_names();

/// The named preset; throws std::invalid_argument naming the known presets for an unknown name.
PredictorPreset predictor_preset(const std::string& name);

/// `base` with everything the preset sets replaced (the tag width goes to ResolveOptions).
PredictorConfig apply_preset(const PredictorPreset& p, PredictorConfig base = {});

}  // namespace hrpp
