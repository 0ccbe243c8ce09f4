#!/usr/bin/env python3
"""Tests of model/tools/sweep.py (ctest: sweep.pareto, sweep.tiny, sweep.errors, sweep.dask).

Run one class:  .venv/bin/python model/test/sweep_test.py Pareto
The tool is $HRPP_TOOL (default build/hrpp); scenes are the project's own (scenes/).
"""
import csv
import os
import pathlib
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "model" / "tools"))
import sweep  # noqa: E402

HRPP = os.environ.get("HRPP_TOOL", str(ROOT / "build" / "hrpp"))
TETRA = str(ROOT / "scenes" / "spd_tetra.glb")
CORNELL = str(ROOT / "scenes" / "cornell_box.glb")
SWEEP = [sys.executable, str(ROOT / "model" / "tools" / "sweep.py"), "--hrpp", HRPP]


def run_sweep(*args):
    return subprocess.run(SWEEP + list(args), capture_output=True, text=True)


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


class Pareto(unittest.TestCase):
    def test_hand_made_points(self):
        # (cycles, accuracy): minimise cycles, maximise accuracy.
        pts = [{"c": 100, "a": 1.0},   # 0 front: the most accurate
               {"c": 80, "a": 0.99},   # 1 front
               {"c": 90, "a": 0.98},   # 2 dominated by 1
               {"c": 60, "a": 0.90},   # 3 front: the fastest
               {"c": 60, "a": 0.80},   # 4 dominated by 3 (same time, less accurate)
               {"c": 120, "a": 1.0},   # 5 dominated by 0 (same accuracy, slower)
               {"c": 70, "a": 0.95}]   # 6 front
        self.assertEqual(sweep.pareto_front(pts, ["c"], ["a"]), [3, 6, 1, 0])

    def test_duplicates_and_single_objective(self):
        pts = [{"c": 5}, {"c": 3}, {"c": 3}, {"c": 9}]
        self.assertEqual(sweep.pareto_front(pts, ["c"]), [1, 2])  # equal points both stay
        self.assertEqual(sweep.pareto_front([], ["c"]), [])

    def test_baseline_point_joins_the_front(self):
        pts = [{"scene": "s", "kind": "all", "spp": "1", "hrpp_cycles_per_ray": 120.0,
                "baseline_cycles_per_ray": 100.0, "accuracy": 1.0},   # exact but slower
               {"scene": "s", "kind": "all", "spp": "1", "hrpp_cycles_per_ray": 80.0,
                "baseline_cycles_per_ray": 100.0, "accuracy": 0.9}]   # speculative, faster
        allp = sweep.with_baselines(pts)
        front = sweep.pareto_front(allp, ["hrpp_cycles_per_ray"], ["accuracy"])
        self.assertEqual(front, [1, 2])  # the speculative point and the baseline, not point 0
        self.assertTrue(allp[2]["baseline"])

    def test_three_objectives(self):
        pts = [(1, 5, 0.5), (2, 1, 0.5), (1, 5, 0.4), (3, 3, 0.9)]
        # minimise 0 and 1, maximise 2; (1,5,0.4) is dominated by (1,5,0.5).
        self.assertEqual(sweep.pareto_front(pts, [0, 1], [2]), [0, 1, 3])


class Tiny(unittest.TestCase):
    """A sweep on a tiny scene: the expected rows and columns, reproducible numbers."""

    def test_rows_columns_reproducible(self):
        with tempfile.TemporaryDirectory() as d:
            a, b = os.path.join(d, "a.csv"), os.path.join(d, "b.csv")
            args = [TETRA, "--param", "precision=4,6", "--param", "table=16x2,unbounded",
                    "--param", "mode=closest-exact,closest-spec", "--res", "24x24",
                    "--no-dask", "--no-timing"]
            p = run_sweep(*args, "--csv", a, "--plots", os.path.join(d, "plots"),
                          "--report", os.path.join(d, "report.md"))
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("sweep: [8/8]", p.stderr)  # progress
            p = run_sweep(*args, "--csv", b)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(pathlib.Path(a).read_text(), pathlib.Path(b).read_text())
            rows = read(a)
            # 8 configurations x (primary, shadow, ao, all).
            self.assertEqual(len(rows), 8 * 4)
            self.assertEqual(list(rows[0]), ["scene", "kind", "res"] + list(sweep.PARAMS)
                             + sweep.RESULT_COLUMNS)
            self.assertEqual([r["kind"] for r in rows[:4]], ["primary", "shadow", "ao", "all"])
            self.assertEqual({(r["precision"], r["table"], r["mode"]) for r in rows},
                             {(p, t, m) for p in ("4", "6") for t in ("16x2", "unbounded")
                              for m in ("closest-exact", "closest-spec")})
            for r in rows:
                self.assertEqual(r["scene"], "spd_tetra")
                self.assertEqual(r["res"], "24x24")
                self.assertEqual(r["baseline_ns_per_ray"], "")
                if r["mode"] == "closest-exact":
                    self.assertEqual(float(r["accuracy"]), 1.0)
                    self.assertEqual(int(r["wrong_results"]), 0)
            # The "all" row is the sum of the kinds' rows.
            for i in range(0, len(rows), 4):
                kinds, total = rows[i:i + 3], rows[i + 3]
                self.assertEqual(sum(int(k["rays"]) for k in kinds), int(total["rays"]))
                self.assertEqual(int(kinds[0]["rays"]), 24 * 24)
                base = sum(float(k["baseline_cycles_per_ray"]) * int(k["rays"]) for k in kinds)
                self.assertAlmostEqual(base / int(total["rays"]),
                                       float(total["baseline_cycles_per_ray"]), places=4)
            # A finite table's bytes follow from its fields: the same in every mode.
            small = {r["table_bytes"] for r in rows if r["table"] == "16x2" and r["precision"] == "6"}
            self.assertEqual(len(small), 1)
            for f in ("accuracy_vs_time.png", "skipped_vs_bytes.png", "spec_error_vs_saved.png"):
                self.assertGreater(os.path.getsize(os.path.join(d, "plots", f)), 1000, f)
            report = pathlib.Path(d, "report.md").read_text()
            self.assertIn("## Pareto-optimal configurations", report)
            self.assertIn("### spd_tetra / all / closest-hit queries", report)
            self.assertIn("Smallest table keeping 90%", report)
            self.assertIn("| no predictor (the baseline walk, spp=1) |", report)

    def test_latency_rows(self):
        with tempfile.TemporaryDirectory() as d:
            a = os.path.join(d, "a.csv")
            p = run_sweep(CORNELL, "--param", "latency=0,100",
                          "--res", "16x16", "--no-dask", "--csv", a, "--plots", d,
                          "--report", os.path.join(d, "report.md"))
            self.assertEqual(p.returncode, 0, p.stderr)
            rows = read(a)
            delays = sorted({int(r["update_delay_rays"]) for r in rows})
            self.assertEqual(len(delays), 2)
            self.assertEqual(delays[1], 63)  # capped by the RTL's 64 ray ids
            self.assertTrue(all(float(r["hrpp_ns_per_ray"]) > 0 for r in rows))
            self.assertGreater(os.path.getsize(os.path.join(d, "hit_rate_vs_latency.png")), 1000)
            report = pathlib.Path(d, "report.md").read_text()
            self.assertIn("## Pipeline latency against the untimed model", report)
            self.assertIn("| cornell_box | all | default | 100 | 63 |", report)

    def test_doc_blocks(self):
        """--doc rewrites the sweep-* blocks of a copy of docs/results.md and nothing else."""
        page = ROOT / "docs" / "results.md"
        with tempfile.TemporaryDirectory() as d:
            grid, lat, delay = (os.path.join(d, f"{n}.csv") for n in ("grid", "lat", "delay"))
            common = [CORNELL, "--res", "32x32", "--no-dask", "--no-timing"]
            for csv_, params in ((grid, ["precision=4,5", "table=16x2,unbounded",
                                         "mode=closest-exact,closest-spec"]),
                                 (lat, ["table=16x2", "mode=anyhit,closest-spec",
                                        "latency=none,0"]),
                                 (delay, ["table=16x2", "mode=anyhit,closest-spec",
                                          "update_delay=0,16"])):
                p = run_sweep(*common, *[a for v in params for a in ("--param", v)],
                              "--csv", csv_)
                self.assertEqual(p.returncode, 0, p.stderr)
            doc = pathlib.Path(d, "results.md")
            doc.write_text(page.read_text())
            p = run_sweep("--from-csv", grid, lat, delay, "--doc", str(doc))
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("sweep: wrote sweep-pareto, sweep-latency, sweep-delay, sweep-spec, "
                          "sweep-recommend blocks of", p.stderr)
            old, new = page.read_text(), doc.read_text()

            def split(text):  # (text outside the blocks, {name: body})
                bodies = {}
                for name in sweep.DOC_BLOCKS:
                    begin, end = sweep.markers(name)
                    head, rest = text.split(begin, 1)
                    bodies[name], tail = rest.split(end, 1)
                    text = head + begin + end + tail
                return text, bodies

            old_out, old_blocks = split(old)
            new_out, new_blocks = split(new)
            self.assertEqual(old_out, new_out)  # the hand-written text is left alone
            for name in sweep.DOC_BLOCKS:
                self.assertTrue(old_blocks[name] != new_blocks[name], f"{name} not rewritten")
                self.assertIn("| cornell_box |", new_blocks[name], name)
            self.assertIn("| cornell_box | all | closest-hit |", new_blocks["sweep-pareto"])
            self.assertRegex(new_blocks["sweep-pareto"],
                             r"P=4 16x2 closest-spec \(\d+, \d+\.\d\d%\)")
            self.assertIn("no predictor (", new_blocks["sweep-pareto"])
            self.assertIn("| scene | mode | precision: untimed / 16 rays |",
                          new_blocks["sweep-latency"])
            self.assertIn("| cornell_box | closest-spec |", new_blocks["sweep-latency"])
            self.assertIn("recall at 0 / 16 rays of delay", new_blocks["sweep-delay"])
            self.assertIn("| scene | mode | P = 4 | P = 5 |", new_blocks["sweep-recommend"])
            self.assertIn("- one more bit of precision (P to P+1):", new_blocks["sweep-recommend"])
            # The same rows give the same page.
            p = run_sweep("--from-csv", grid, lat, delay, "--doc", str(doc))
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(doc.read_text(), new)
            # A page without the blocks is an error, and is left as it was.
            bare = pathlib.Path(d, "bare.md")
            bare.write_text("# no blocks\n")
            p = run_sweep("--from-csv", grid, "--doc", str(bare))
            self.assertEqual(p.returncode, 2)
            self.assertIn("no sweep-pareto, sweep-latency", p.stderr)
            self.assertEqual(bare.read_text(), "# no blocks\n")


class Errors(unittest.TestCase):
    def test_bad_input(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "a.csv")
            p = run_sweep(TETRA, "--param", "colour=red", "--csv", out, "--no-dask")
            self.assertEqual(p.returncode, 2)
            self.assertIn("unknown parameter 'colour'", p.stderr)
            # The same through `hrpp sweep`, which runs this driver with the venv's python.
            p = subprocess.run([HRPP, "sweep", TETRA, "--param", "colour=red", "--csv", out],
                               capture_output=True, text=True)
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("unknown parameter 'colour'", p.stderr)
            p = run_sweep(os.path.join(d, "nope.glb"), "--param", "precision=4", "--csv", out)
            self.assertEqual(p.returncode, 2)
            self.assertIn("nope.glb: no such scene file", p.stderr)
            p = run_sweep(TETRA, "--param", "table=3x4", "--csv", out, "--no-dask")
            self.assertEqual(p.returncode, 2)
            self.assertIn("power of two", p.stderr)  # hrpp predict's own message
            p = run_sweep(TETRA, "--param", "latency=5", "--param", "update_delay=1",
                          "--csv", out, "--no-dask")
            self.assertEqual(p.returncode, 2)
            self.assertIn("not both", p.stderr)
            self.assertFalse(os.path.exists(out))


class Dask(unittest.TestCase):
    """A real Dask LocalCluster with two worker processes, reached by its address: the CSV
    equals the single-process run's byte for byte."""

    def test_cluster_equals_single_process(self):
        from dask.distributed import Client, LocalCluster
        with tempfile.TemporaryDirectory() as d:
            a, b = os.path.join(d, "dask.csv"), os.path.join(d, "single.csv")
            args = [TETRA, CORNELL, "--param", "precision=4,6", "--param",
                    "table=16x2,unbounded", "--param", "mode=anyhit,closest-spec",
                    "--res", "16x16", "--no-timing"]
            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster:
                p = run_sweep(*args, "--scheduler", cluster.scheduler_address, "--csv", a)
                self.assertEqual(p.returncode, 0, p.stderr)
                self.assertIn("on 2 Dask workers", p.stderr)
            p = run_sweep(*args, "--no-dask", "--csv", b)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(pathlib.Path(a).read_text(), pathlib.Path(b).read_text())
            self.assertEqual(len(read(a)), 2 * 8 * 4)


if __name__ == "__main__":
    unittest.main()
