#include "hrpp/predictor/predictor.h"

#include <bit>
#include <chrono>

#include "hrpp/predictor/engine_side.h"

namespace hrpp {

const char* predict_mode_name(PredictMode m) {
  switch (m) {
    case PredictMode::kAnyHit:
      return "anyhit";
    case PredictMode::kClosestExact:
      return "closest-exact";
    case PredictMode::kClosestSpec:
      return "closest-spec";
  }
  return "?";
}

bool parse_predict_mode(const std::string& s, PredictMode* out) {
  for (PredictMode m :
       {PredictMode::kAnyHit, PredictMode::kClosestExact, PredictMode::kClosestSpec})
    if (s == predict_mode_name(m)) {
      *out = m;
      return true;
    }
  return false;
}

std::string resolve_for_scene(const Scene& scene, const Bvh& bvh, HashConfig* hash,
                              TableConfig* table, const ResolveOptions& opt) {
  HashConfig& h = *hash;
  TableConfig& t = *table;
  h.index_bits = t.unbounded ? 0 : std::countr_zero(t.sets);
  h.origin_cell_exp = cell_exp_for(scene.bounds, h.origin_bits);
  // micro21's origin grid spans the BVH root's box, as their simulator's world bounds (the union
  // of the root's two child boxes); the scene's bounds for an empty BVH.
  const Aabb world = bvh.nodes.empty() ? scene.bounds : bvh.nodes[0].box();
  for (int a = 0; a < 3; ++a) {
    h.bounds_lo[a] = world.lo[a];
    h.bounds_hi[a] = world.hi[a];
  }
  const size_t nodes = bvh.nodes.size();
  if (opt.node_bits > 0 && opt.node_bits < 64 && nodes > (uint64_t{1} << opt.node_bits))
    return "the BVH has " + std::to_string(nodes) + " nodes; " + std::to_string(opt.node_bits) +
           "-bit node ids name at most " + std::to_string(uint64_t{1} << opt.node_bits);
  t.node_bits = opt.node_bits > 0 ? opt.node_bits : node_bits_for(nodes);
  t.key_bits = h.key_bits();
  t.tag_bits = t.unbounded ? 0 : h.tag_bits();
  if (opt.tag_bits >= 0 && !t.unbounded) {
    if (opt.tag_bits > h.tag_bits())
      return std::string(opt.tag_bits_name) + " " + std::to_string(opt.tag_bits) +
             " exceeds the full tag width " + std::to_string(h.tag_bits()) + " (key " +
             std::to_string(h.key_bits()) + " bits, index " + std::to_string(h.index_bits) +
             " bits)";
    t.tag_bits = opt.tag_bits;
  }
  for (const std::string& err : {h.validate(), t.validate()})
    if (!err.empty()) return err;
  return {};
}

PredictStats& PredictStats::operator+=(const PredictStats& o) {
  rays += o.rays;
  invalid_rays += o.invalid_rays;
  baseline += o.baseline;
  hrpp += o.hrpp;
  predicted += o.predicted;
  wasted += o.wasted;
  true_positive += o.true_positive;
  false_positive += o.false_positive;
  false_negative += o.false_negative;
  true_negative += o.true_negative;
  skipped_walks += o.skipped_walks;
  wrong_results += o.wrong_results;
  baseline_wrong_results += o.baseline_wrong_results;
  exact_mismatches += o.exact_mismatches;
  baseline_hits += o.baseline_hits;
  table_updates += o.table_updates;
  table_demotes += o.table_demotes;
  suppressed_lookups += o.suppressed_lookups;
  unoffered_rays += o.unoffered_rays;
  baseline_ns += o.baseline_ns;
  hrpp_ns += o.hrpp_ns;
  return *this;
}

double PredictStats::skipped_interior_fraction() const {
  return baseline.interior_tests
             ? 1.0 - double(hrpp.interior_tests) / double(baseline.interior_tests)
             : 0.0;
}
double PredictStats::precision() const {
  const uint64_t d = true_positive + false_positive;
  return d ? double(true_positive) / d : 0.0;
}
double PredictStats::recall() const {
  const uint64_t d = true_positive + false_negative;
  return d ? double(true_positive) / d : 0.0;
}

static nlohmann::json counters_json(const Counters& c) {
  return {{"interior_tests", c.interior_tests},
          {"box_tests", c.box_tests},
          {"leaf_visits", c.leaf_visits},
          {"tri_tests", c.tri_tests}};
}

nlohmann::json PredictStats::to_json() const {
  auto frac = [](uint64_t a, uint64_t b) { return b ? 1.0 - double(a) / double(b) : 0.0; };
  return {{"rays", rays},
          {"invalid_rays", invalid_rays},
          {"baseline", counters_json(baseline)},
          {"hrpp", counters_json(hrpp)},
          {"predicted_walks", counters_json(predicted)},
          {"wasted_walks", counters_json(wasted)},
          {"skipped_interior_fraction", skipped_interior_fraction()},
          {"skipped_tri_fraction", frac(hrpp.tri_tests, baseline.tri_tests)},
          {"skipped_walks", skipped_walks},
          {"precision", precision()},
          {"recall", recall()},
          {"true_positive", true_positive},
          {"false_positive", false_positive},
          {"false_negative", false_negative},
          {"true_negative", true_negative},
          {"wrong_results", wrong_results},
          {"baseline_wrong_results", baseline_wrong_results},
          {"exact_mismatches", exact_mismatches},
          {"baseline_hits", baseline_hits},
          {"table_updates", table_updates},
          {"table_demotes", table_demotes},
          {"suppressed_lookups", suppressed_lookups},
          {"unoffered_rays", unoffered_rays},
          {"baseline_ns", baseline_ns},
          {"hrpp_ns", hrpp_ns}};
}

bool in_subtree(const Bvh& bvh, uint32_t node, uint32_t leaf) {
  for (uint32_t n = leaf; n != kNoNode; n = bvh.parent[n])
    if (n == node) return true;
  return false;
}

bool same_answer(const Bvh& bvh, const Ray& r, const Hit& a, const Hit& b) {
  if (a.hit() != b.hit()) return false;
  if (!a.hit()) return true;
  if (a.t != b.t) return false;
  if (a.prim == b.prim) return true;
  // An exact tie: the baseline's primitive is hit at exactly the same t.
  const RayPre pre(r);
  for (uint32_t i = 0; i < bvh.prim_ids.size(); ++i)
    if (bvh.prim_ids[i] == b.prim) {
      float t, u, v;
      return intersect_triangle(pre, bvh.tris[i], r.tnear, next_float_up(r.tfar), &t, &u, &v) &&
             t == a.t;
    }
  return false;
}

Predictor::Predictor(const Bvh& bvh, const PredictorConfig& cfg)
    : bvh_(bvh), cfg_(cfg), table_(cfg.table) {}

RayResult Predictor::process(const RayRecord& rec) {
  RayResult res;
  // Statistics go straight into the ray kind's record (total() sums the kinds when asked).
  PredictStats& s = by_kind_[static_cast<int>(rec.kind)];
  const uint64_t ray_no = issued_++;
  // Writes of rays issued update_delay or more rays ago have landed.
  while (!pending_.empty() && pending_.front().due <= ray_no) {
    const PendingUpdate& u = pending_.front();
    if (u.demote)
      table_.demote(u.index, u.tag, u.key);
    else
      table_.update(u.index, u.tag, u.key, u.node);
    pending_.pop_front();
  }
  using Clock = std::chrono::steady_clock;
  const bool timed = cfg_.measure_time;
  auto ns_since = [](Clock::time_point t0) {
    return uint64_t(
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count());
  };
  const Ray& ray = rec.ray;
  if (validate_ray(ray) != RayError::kNone) {  // never hashed
    res.invalid = true;
    s.rays += 1;
    s.invalid_rays += 1;
    return res;
  }
  EngineRay er;
  set_query(rec.kind, cfg_.mode, &er);
  if (cfg_.any_hit_only && !er.any) {
    // Not offered to the predictor: the plain walk from the root answers (a full walk), and
    // nothing is looked up or written.
    Clock::time_point t1;
    if (timed) t1 = Clock::now();
    walk_from_root(bvh_, ray, Action::kFull, &er);
    finish(bvh_, Action::kFull, &er);
    if (timed) {
      const uint64_t ns = ns_since(t1);
      s.baseline_ns += ns;
      s.hrpp_ns += ns;  // HRPP runs the same walk, nothing else
    }
    s.unoffered_rays += 1;
    classify(bvh_, ray, er, cfg_.mode, &s);
    res.baseline = er.baseline;
    res.answer = er.answer;
    res.base_counters = er.base;
    res.hrpp_counters = er.hrpp;
    return res;
  }

  // Lookup and predicted subtree walks, most recently used node first; the walks from the root
  // come after them, so that in closest-exact mode the baseline walk can carry the shortened
  // walk along (walk_from_root). Neither depends on the other, so the order changes no result;
  // with timing on, every walk runs on its own and is timed as before.
  Clock::time_point t0;
  if (timed) t0 = Clock::now();
  res.key = hash_ray(ray, cfg_.hash);
  const Prediction p = table_.lookup(res.key.index, res.key.tag, res.key.key);
  res.suppressed = p.suppressed;
  s.suppressed_lookups += p.suppressed;
  walk_predicted(bvh_, ray, p.nodes.data(), p.count, &er);
  const uint64_t lookup_ns = timed ? ns_since(t0) : 0;
  const Action action = decide(er, cfg_.mode);

  // The walks from the root: the baseline walk (with the shortened walk, when there is one).
  uint64_t base_ns = 0, hrpp_ns = 0;
  if (timed) {
    t0 = Clock::now();
    baseline_walk(bvh_, ray, &er);
    base_ns = ns_since(t0);
    t0 = Clock::now();  // the rest of HRPP's time, after lookup_ns
    if (action == Action::kShrink) shrunk_walk(bvh_, ray, &er);
    if (action == Action::kFull) hrpp_ns = base_ns;  // HRPP runs the same walk, not twice
  } else {
    walk_from_root(bvh_, ray, action, &er);
  }
  finish(bvh_, action, &er);

  // Update: refresh a verified node, else insert the hit's node.
  res.update_node = update_node(bvh_, er, cfg_.go_up);
  if (res.update_node != kNoNode) {
    s.table_updates += 1;
    if (cfg_.update_delay == 0)
      table_.update(res.key.index, res.key.tag, res.key.key, res.update_node);
    else
      pending_.push_back({ray_no + 1 + cfg_.update_delay, res.key.index, res.key.tag, res.key.key,
                          res.update_node});
  } else if (demotes(cfg_.table, er.predicted, er.verified, res.update_node)) {
    // Confidence: the prediction failed and the ray writes nothing: its entry counts down.
    res.demoted = true;
    s.table_demotes += 1;
    if (cfg_.update_delay == 0)
      table_.demote(res.key.index, res.key.tag, res.key.key);
    else
      pending_.push_back(
          {ray_no + 1 + cfg_.update_delay, res.key.index, res.key.tag, res.key.key, kNoNode, true});
  }
  if (timed) {
    s.hrpp_ns += hrpp_ns + lookup_ns + ns_since(t0);
    s.baseline_ns += base_ns;
  }

  classify(bvh_, ray, er, cfg_.mode, &s);
  res.predicted = er.predicted;
  res.verified = er.verified;
  res.baseline = er.baseline;
  res.answer = er.answer;
  res.base_counters = er.base;
  res.hrpp_counters = er.hrpp;
  return res;
}

const PredictStats& Predictor::total() const {
  total_ = PredictStats{};
  for (const PredictStats& k : by_kind_) total_ += k;
  return total_;
}

nlohmann::json Predictor::to_json() const {
  nlohmann::json j = total().to_json();
  const HashConfig& h = cfg_.hash;
  const TableConfig& t = cfg_.table;
  j["config"] = {
      {"hash", hash_variant_name(h.variant)},
      {"precision_bits", h.precision},  // the faithful hash's P; "precision" is TP / (TP + FP)
      {"exp_bits", h.exp_bits},
      {"origin_bits", h.origin_bits},
      {"origin_cell_exp", h.origin_cell_exp},
      {"dir_bits", h.dir_bits},
      {"dir_code", dir_code_name(h.dir_code)},
      {"combine", combine_mode_name(h.combine)},
      {"key_bits", h.key_bits()},
      {"table", t.unbounded ? "unbounded" : std::to_string(t.sets) + "x" + std::to_string(t.ways)},
      {"sets", t.unbounded ? 0 : t.sets},
      {"ways", t.unbounded ? 0 : t.ways},
      {"nodes_per_entry", t.nodes_per_entry},
      {"confidence_bits", t.conf_bits},
      {"confidence_threshold", t.conf_bits > 0 ? t.conf_threshold : 0},
      {"node_bits", t.node_bits},
      {"tag_bits", t.unbounded ? 0 : t.tag_bits},
      {"full_tag_bits", t.unbounded ? 0 : h.tag_bits()},
      {"entry_bits", t.entry_bits()},
      {"go_up", cfg_.go_up},
      {"mode", predict_mode_name(cfg_.mode)},
      {"predict_kinds", cfg_.any_hit_only ? "any-hit" : "all"}};
  j["table_entries"] = table_.entries_used();
  j["table_bytes"] = table_.bytes();  // an unbounded table: the bytes of the entries used
  j["table_unbounded"] = t.unbounded;
  nlohmann::json bk = nlohmann::json::object();
  for (int k = 0; k < kNumRayKinds; ++k)
    if (by_kind_[k].rays)
      bk[std::string(ray_kind_name(static_cast<RayKind>(k)))] = by_kind_[k].to_json();
  j["by_kind"] = bk;
  return j;
}

}  // namespace hrpp
