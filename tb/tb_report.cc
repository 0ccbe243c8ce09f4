#include "tb_report.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace hrpp::tb {
namespace {

void print_stats(const char* who, const PredictStats& s) {
  std::printf(
      "  %-22s rays %llu, predictions %llu, verified %llu, skipped walks %llu, "
      "interior tests %llu / baseline %llu (skipped %.2f%%), wrong %llu, exact-mismatch %llu\n",
      who, (unsigned long long)s.rays, (unsigned long long)(s.true_positive + s.false_positive),
      (unsigned long long)s.true_positive, (unsigned long long)s.skipped_walks,
      (unsigned long long)s.hrpp.interior_tests, (unsigned long long)s.baseline.interior_tests,
      100 * s.skipped_interior_fraction(), (unsigned long long)s.wrong_results,
      (unsigned long long)s.exact_mismatches);
}

bool same_stats(const PredictStats& a, const PredictStats& b) {
  return a.rays == b.rays && a.baseline == b.baseline && a.hrpp == b.hrpp &&
         a.predicted == b.predicted && a.wasted == b.wasted && a.true_positive == b.true_positive &&
         a.false_positive == b.false_positive && a.false_negative == b.false_negative &&
         a.true_negative == b.true_negative && a.skipped_walks == b.skipped_walks &&
         a.wrong_results == b.wrong_results && a.exact_mismatches == b.exact_mismatches;
}

}  // namespace

void print_header(const RtlConfig& spec, const CycleConfig& cc, const TbOptions& o,
                  const TbRays& rays) {
  const uint64_t invalid = rays.invalid;
  const std::string& stream_path = o.stream_path;
  std::printf(
      "tb_hrpp: config %s (%s hash, %u sets x %u ways x %u nodes, %d-bit tags, %d-bit ids), "
      "mode %s, %zu rays of %s%s, seed %llu\n",
      spec.name.c_str(), hash_variant_name(cc.hash.variant), spec.table.sets, spec.table.ways,
      spec.table.nodes_per_entry, spec.table.tag_bits, spec.id_width, o.mode.c_str(),
      rays.rays.size(), !stream_path.empty() ? stream_path.c_str() : rays.scene_file.c_str(),
      invalid ? (" (" + std::to_string(invalid) + " invalid rays not issued)").c_str() : "",
      (unsigned long long)o.seed);
  std::fflush(stdout);  // before the run, also when piped
}

void print_parity(const Run& r, std::chrono::steady_clock::time_point t_sim, std::clock_t cpu_sim) {
  const uint64_t finished = r.stats.rays;
  std::printf("parity: %llu rays, %llu cycles, %llu mismatches\n", (unsigned long long)finished,
              (unsigned long long)r.cycles, (unsigned long long)r.mismatches);
  // The lockstep run alone (engine walks, DUT, cycle model, comparison of every output on every
  // cycle); hrpp_bench reads this line.
  const double sim_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_sim).count();
  const double cpu_s = double(std::clock() - cpu_sim) / CLOCKS_PER_SEC;
  std::printf(
      "timing: lockstep run %.3f s (CPU %.3f s): %.0f rays/s, %.0f cycles/s of CPU time "
      "with parity checking\n",
      sim_s, cpu_s, finished / std::max(cpu_s, 1e-9), r.cycles / std::max(cpu_s, 1e-9));
}

int report_lockstep(const Run& r, const TbOptions& o, const RtlConfig& spec, StressKind stress_kind,
                    size_t nrays) {
  const RunOptions& ro = o.ro;
  const EngineOptions& eo = o.eo;
  const std::string& stress = o.stress;
  if (r.mismatches || !r.ok) return 1;
  if (ro.reset_every)
    std::printf(
        "resets: %llu (%llu cycles in reset), %llu hit rays in flight: %llu rays dropped "
        "and offered again\n",
        (unsigned long long)r.resets, (unsigned long long)r.reset_cycles,
        (unsigned long long)r.resets_with_rays, (unsigned long long)r.dropped);
  if (eo.stall_gap) {
    std::printf("stalls (count, cycles, longest, cycles a handshake was held back):");
    for (int p = 0; p < kNumStallPorts; ++p)
      std::printf("%s %s %llu, %llu, %llu, %llu", p ? ";" : "", stall_port_name(p),
                  (unsigned long long)r.stalls[p].stalls, (unsigned long long)r.stalls[p].cycles,
                  (unsigned long long)r.stalls[p].longest, (unsigned long long)r.stalls[p].blocked);
    std::printf("\n");
  }
  std::printf(
      "table: %llu updates, %llu requests merged, %llu evictions, %llu cycles of "
      "same-set interlock, %llu of %u entries valid at the end\n",
      (unsigned long long)r.table.updates, (unsigned long long)r.table.merged,
      (unsigned long long)r.table.evictions, (unsigned long long)r.table.interlock_cycles,
      (unsigned long long)r.table_used, spec.table.sets * spec.table.ways);
  // Every ray of the stream got exactly one final result, resets or not.
  if (!r.exactly_once.empty()) {
    std::printf("FAIL: not every ray got exactly one final result: %s\n", r.exactly_once.c_str());
    return 1;
  }
  std::printf("exactly once: each of the %zu rays got one final result\n", nrays);
  // The stress the options ask for really happened.
  if (ro.reset_every && (r.resets == 0 || r.dropped == 0)) {
    std::printf("FAIL: --reset-every %llu: %llu resets, %llu rays in flight hit\n",
                (unsigned long long)ro.reset_every, (unsigned long long)r.resets,
                (unsigned long long)r.dropped);
    return 1;
  }
  for (int p = 0; eo.stall_gap && p < kNumStallPorts; ++p)
    if (r.stalls[p].blocked == 0) {
      std::printf("FAIL: the random stalls never held back a handshake on %s\n",
                  stall_port_name(p));
      return 1;
    }
  if (!stress.empty()) {
    std::string e;
    const uint64_t entries = uint64_t{spec.table.sets} * spec.table.ways;
    if (stress_kind == StressKind::kSetBurst &&
        (r.table.interlock_cycles == 0 || r.table.evictions == 0))
      e = "no same-set interlock or no eviction";
    if (stress_kind == StressKind::kOneKey &&
        (r.table.updates == 0 || r.table.evictions != 0 || r.table_used > 1))
      e = "one key must give updates, no eviction and at most one valid entry";
    if (stress_kind == StressKind::kEvict &&
        (r.table.evictions < entries || (r.resets == 0 && r.table_used != entries)))
      e = "fewer evictions than table entries, or the table not full at the end";
    if (!e.empty()) {
      std::printf("FAIL: the %s run did not stress the table as claimed: %s\n", stress.c_str(),
                  e.c_str());
      return 1;
    }
  }
  return 0;
}

int report_statistics(const Run& r, const Run& m, const PredictStats& untimed, const TbOptions& o,
                      uint64_t clear_cycles) {
  const uint64_t finished = r.stats.rays;
  std::printf("statistics:\n");
  print_stats("DUT run", r.stats);
  print_stats("cycle model alone", m.stats);
  print_stats("untimed model", untimed);
  // The rate from the end of the table's reset clear after power-up (clear_cycles, one set per
  // cycle, no ray taken), and over the whole run.
  const uint64_t steady_cycles = r.cycles > clear_cycles ? r.cycles - clear_cycles : 1;
  const double throughput = double(finished) / double(steady_cycles);
  std::printf(
      "  throughput: %.3f rays per cycle after the reset clear (%.3f over all %llu cycles, the "
      "clear's %llu included); pipeline latency costs %.2f points of skipped interior tests "
      "against the untimed model\n",
      throughput, double(finished) / std::max<uint64_t>(1, r.cycles), (unsigned long long)r.cycles,
      (unsigned long long)clear_cycles,
      100 * (untimed.skipped_interior_fraction() - r.stats.skipped_interior_fraction()));
  if (!m.ok || !same_stats(r.stats, m.stats) || m.cycles != r.cycles || m.resets != r.resets ||
      m.dropped != r.dropped || !m.exactly_once.empty()) {
    std::printf(
        "FAIL: the cycle model alone gives different statistics or cycle count (%llu cycles)\n",
        (unsigned long long)m.cycles);
    return 1;
  }
  std::printf("  rays in flight: at most %llu at once (accepted, final result not yet reported)\n",
              (unsigned long long)r.max_in_flight);
  if (throughput < o.min_throughput) {
    std::printf("FAIL: %.3f rays per cycle, below the required %.3f\n", throughput,
                o.min_throughput);
    return 1;
  }
  if (r.max_in_flight < o.min_in_flight) {
    std::printf("FAIL: at most %llu rays in flight, below the required %llu\n",
                (unsigned long long)r.max_in_flight, (unsigned long long)o.min_in_flight);
    return 1;
  }
  if (r.stats.exact_mismatches) {
    std::printf("FAIL: %llu rays answered differently from the baseline in an exact mode\n",
                (unsigned long long)r.stats.exact_mismatches);
    return 1;
  }
  std::printf("PASS\n");
  return 0;
}

}  // namespace hrpp::tb
