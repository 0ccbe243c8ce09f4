#include "latency.h"

#include <bit>
#include <vector>

#include "hrpp/rtl_config_data.h"

namespace hrpp::tb {

Latencies declared_latencies(const RtlConfig& rc) {
  return {rc.prediction_latency(), rc.decision_latency(), rc.update_landing()};
}

namespace {

// A valid ray (finite components), the same key every time.
DutIn probe_ray(uint32_t id) {
  DutIn in;
  in.ray_valid = true;
  in.ray_id = id;
  in.ray_kind = 0;  // primary: a closest-hit query
  in.org = {std::bit_cast<uint32_t>(0.5f), std::bit_cast<uint32_t>(0.25f),
            std::bit_cast<uint32_t>(0.75f)};
  in.dir = {std::bit_cast<uint32_t>(0.f), std::bit_cast<uint32_t>(0.6f),
            std::bit_cast<uint32_t>(0.8f)};
  return in;
}

}  // namespace

std::string measure_latencies(const CycleFn& cycle, int id_bits, uint32_t sets, Latencies* out,
                              bool confidence) {
  *out = Latencies{};
  constexpr uint32_t kNode = 5;
  const uint64_t limit = sets + 1000;
  uint64_t now = 0;
  DutOut o;
  // The table's reset clear.
  for (o = cycle(DutIn{}); !o.ray_ready; o = cycle(DutIn{}))
    if (++now > limit) return "ray_ready_o never rose after reset";
  if (confidence) {
    // The node written once first (its way's confidence bit 0: no prediction yet) by a ray of
    // the last id: its prediction, predicted-walk result (no hit) and final outcome (a hit), each
    // taken when offered; then enough idle cycles for the write to land.
    const uint32_t id = (1u << id_bits) - 1;
    DutIn in = probe_ray(id);
    in.pred_ready = in.skip_ready = true;
    bool sent_pw = false, sent_outcome = false;
    for (uint64_t n = 0; n < limit && !sent_outcome; ++n) {
      const bool pred_seen = o.pred_valid && o.pred_id == id;
      if (pred_seen && o.pred_count != 0) return "a prediction before the node was written";
      if (pred_seen) {
        in.pw_valid = true;
        in.pw_id = id;
      }
      if (sent_pw) {
        in.outcome_valid = true;
        in.outcome_id = id;
        in.outcome_hit = true;
        in.outcome_node = kNode;
      }
      const DutIn now_in = in;
      o = cycle(now_in);
      if (now_in.ray_valid && o.ray_ready) in.ray_valid = false;
      if (now_in.pw_valid && o.pw_ready) {
        in.pw_valid = false;
        sent_pw = true;
      }
      if (now_in.outcome_valid && o.outcome_ready) sent_outcome = true;
    }
    if (!sent_outcome) return "the first write of the probe's node was not taken";
    for (int i = 0; i < 64; ++i) o = cycle(DutIn{.pred_ready = true, .skip_ready = true});
  }
  // Ray 0: acceptance to its prediction (the output is not taken until seen).
  now = 0;
  o = cycle(probe_ray(0));  // accepted: ray_ready_o was high
  for (int t = 1;; ++t) {
    DutIn in;
    in.pred_ready = true;
    o = cycle(in);
    if (o.pred_valid) {
      if (o.pred_id != 0 || o.pred_count != 0) return "unexpected prediction for ray 0";
      out->prediction = t;
      break;
    }
    if (t > 1000) return "no prediction for ray 0";
  }
  // Its predicted-walk result, without a hit (no table write): acceptance to the decision.
  DutIn pw;
  pw.pw_valid = true;
  pw.pw_id = 0;
  for (o = cycle(pw); !o.pw_ready; o = cycle(pw))
    if (++now > limit) return "pw_ready_o stayed low";
  for (int t = 1;; ++t) {
    DutIn in;
    in.skip_ready = true;
    o = cycle(in);
    if (o.skip_valid) {
      if (o.skip_id != 0 || o.skip_action != Action::kFull) return "unexpected skip decision";
      out->decision = t;
      break;
    }
    if (t > 1000) return "no skip decision for ray 0";
  }
  // Its final outcome with a hit (a table write), accepted in cycle u; in cycles u, u+1, ... a
  // ray of the same key (ids 1, 2, ...) is accepted: the first whose prediction holds the node.
  DutIn up;
  up.outcome_valid = true;
  up.outcome_id = 0;
  up.outcome_hit = true;
  up.outcome_node = kNode;
  up.pred_ready = true;
  const uint32_t ids = 1u << id_bits;
  uint32_t next_id = 1;
  std::vector<int> offset(ids, -1);  // id -> cycles after the outcome's acceptance
  int t = -1;  // the cycle's distance from the outcome's acceptance (-1: not accepted yet)
  for (uint64_t n = 0; n < limit; ++n) {
    DutIn in = t < 0 ? up : DutIn{};
    in.pred_ready = true;
    in.skip_ready = true;
    const bool offer = t >= 0 && next_id < ids;
    if (offer) {
      const DutIn r = probe_ray(next_id);
      in.ray_valid = true;
      in.ray_id = r.ray_id;
      in.org = r.org;
      in.dir = r.dir;
    }
    o = cycle(in);
    if (o.pred_valid && o.pred_id != 0 && o.pred_count > 0) {
      if (o.pred_nodes[0] != kNode)
        return "the outcome's write landed with node " + std::to_string(o.pred_nodes[0]) +
               ", not " + std::to_string(kNode);
      out->landing = offset[o.pred_id];
      return {};
    }
    if (t < 0) {
      if (o.outcome_ready) t = 1;  // the next cycle is one after the acceptance
      continue;
    }
    if (offer && o.ray_ready) offset[next_id++] = t;
    ++t;
  }
  return "no ray saw the final outcome's table write";
}

std::string compare_latencies(const Latencies& m, const Latencies& d) {
  std::string e;
  auto one = [&](const char* what, int mv, int dv) {
    if (mv != dv)
      e += std::string(e.empty() ? "" : "; ") + what + ": measured " + std::to_string(mv) +
           " cycles, declared " + std::to_string(dv);
  };
  one("ray accepted to pred_valid_o", m.prediction, d.prediction);
  one("predicted-walk result accepted to skip_valid_o", m.decision, d.decision);
  one("final outcome accepted to the first ray that sees its write", m.landing, d.landing);
  return e;
}

}  // namespace hrpp::tb
