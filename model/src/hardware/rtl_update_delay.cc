#include "hrpp/hardware/rtl_update_delay.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <optional>

#include "hrpp/hardware/cycle_model.h"
#include "hrpp/hardware/rtl_config.h"

namespace hrpp {

// ---- the RTL's update delay, from the cycle model ----------------------------------------------

namespace {

// The RTL's `primary` configuration (rtl/config/hrpp_configs.json; the default configuration
// before issue 17's winner, kept so the cost model's figures stay those published).
CycleConfig primary_rtl_config() { return rtl_config("primary").cycle(PredictMode::kClosestExact); }

uint32_t f32(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

// Ray 0 is accepted; ray 1 (same key) is offered `gap` cycles later. True when ray 1's prediction
// holds ray 0's node.
bool second_ray_sees_write(const CycleConfig& cfg, uint32_t gap, uint32_t walk_latency) {
  CycleModel cm(cfg);
  DutIn ray;
  ray.ray_valid = true;
  ray.org = {f32(0.5f), f32(0.25f), f32(0.75f)};
  ray.dir = {f32(0.f), f32(0.6f), f32(0.8f)};
  std::optional<uint64_t> t0;
  bool sent1 = false;
  std::map<uint32_t, uint64_t> pw_due, upd_due;  // id -> cycle
  const uint64_t limit = uint64_t(gap) + walk_latency + 1000 + cfg.table.sets;
  while (cm.cycle() < limit) {
    const DutOut out = cm.outputs();
    DutIn in;
    in.pred_ready = in.skip_ready = true;
    const uint64_t now = cm.cycle();
    if (!t0 && out.ray_ready) {
      in = ray;
      in.ray_id = 0;
      in.pred_ready = in.skip_ready = true;
      t0 = now;
    } else if (t0 && !sent1 && now >= *t0 + gap && out.ray_ready) {
      in.ray_valid = true;
      in.ray_id = 1;
      in.org = ray.org;
      in.dir = ray.dir;
      sent1 = true;
    }
    if (out.pred_valid) {
      if (out.pred_id == 1) return out.pred_count > 0;
      pw_due[out.pred_id] = now + 1;  // an empty prediction: answered at once
    }
    for (auto it = pw_due.begin(); it != pw_due.end(); ++it)
      if (now >= it->second) {
        in.pw_valid = true;
        in.pw_id = it->first;
        in.pw_hit = false;
        if (out.pw_ready) pw_due.erase(it);
        break;
      }
    if (out.skip_valid && out.skip_id == 0) upd_due[0] = now + walk_latency;
    for (auto it = upd_due.begin(); it != upd_due.end(); ++it)
      if (now >= it->second) {
        in.outcome_valid = true;
        in.outcome_id = it->first;
        in.outcome_hit = true;
        in.outcome_node = 5;
        if (out.outcome_ready) upd_due.erase(it);
        break;
      }
    cm.tick(in);
  }
  return false;
}

}  // namespace

uint32_t rtl_update_delay(uint32_t walk_latency) {
  const CycleConfig cfg = primary_rtl_config();
  // The smallest gap at which the second ray sees the first one's write.
  uint32_t lo = 1, hi = 64;
  while (!second_ray_sees_write(cfg, hi, walk_latency)) hi *= 2;
  while (lo < hi) {
    const uint32_t mid = lo + (hi - lo) / 2;
    if (second_ray_sees_write(cfg, mid, walk_latency))
      hi = mid;
    else
      lo = mid + 1;
  }
  // At one ray per cycle, gap - 1 rays are looked up in between; but no more rays than there
  // are ray ids can be in flight.
  return std::min<uint32_t>(lo - 1, (1u << cfg.id_bits) - 1);
}

}  // namespace hrpp
