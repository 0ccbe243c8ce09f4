#!/usr/bin/env python3
"""Tests of the sweep, model/tools/sweep.py and its modules model/tools/sweeplib/ (ctest sweep.*:
Pareto, Tiny, Errors, Dask, Simulate, Resume, Presets, Plots).

Run one class:  .venv/bin/python model/test/sweep_test.py Pareto
The tool is $HRPP_TOOL (default build/hrpp); scenes are the project's own (scenes/).
"""
import csv
import json
import os
import pathlib
import re
import signal
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT), str(ROOT / "model" / "tools")]
from pyhrpp import study  # noqa: E402
from pyhrpp.docs import markers  # noqa: E402
from sweeplib import pareto, plots, tasks  # noqa: E402
from sweeplib.doc import DOC_BLOCKS  # noqa: E402

HRPP = os.environ.get("HRPP_TOOL", str(ROOT / "build" / "hrpp"))
TETRA = str(ROOT / "scenes" / "spd_tetra.glb")
CORNELL = str(ROOT / "scenes" / "cornell_box.glb")
SWEEP = [sys.executable, str(ROOT / "model" / "tools" / "sweep.py"), "--hrpp", HRPP]


def run_sweep(*args, env_add=None):
    env = dict(os.environ, **(env_add or {}))
    return subprocess.run(SWEEP + list(args), capture_output=True, text=True, env=env)


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def split_blocks(text):
    """(TEXT outside the page's sweep-* blocks, {name: body})."""
    bodies = {}
    for name in DOC_BLOCKS:
        begin, end = markers(name)
        head, rest = text.split(begin, 1)
        bodies[name], tail = rest.split(end, 1)
        text = head + begin + end + tail
    return text, bodies


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
        self.assertEqual(pareto.pareto_front(pts, ["c"], ["a"]), [3, 6, 1, 0])

    def test_duplicates_and_single_objective(self):
        pts = [{"c": 5}, {"c": 3}, {"c": 3}, {"c": 9}]
        self.assertEqual(pareto.pareto_front(pts, ["c"]), [1, 2])  # equal points both stay
        self.assertEqual(pareto.pareto_front([], ["c"]), [])

    def test_baseline_point_joins_the_front(self):
        pts = [{"scene": "s", "kind": "all", "spp": "1", "hrpp_cycles_per_ray": 120.0,
                "baseline_cycles_per_ray": 100.0, "accuracy": 1.0},   # exact but slower
               {"scene": "s", "kind": "all", "spp": "1", "hrpp_cycles_per_ray": 80.0,
                "baseline_cycles_per_ray": 100.0, "accuracy": 0.9}]   # speculative, faster
        allp = pareto.with_baselines(pts)
        front = pareto.pareto_front(allp, ["hrpp_cycles_per_ray"], ["accuracy"])
        self.assertEqual(front, [1, 2])  # the speculative point and the baseline, not point 0
        self.assertTrue(allp[2]["baseline"])

    def test_three_objectives(self):
        pts = [(1, 5, 0.5), (2, 1, 0.5), (1, 5, 0.4), (3, 3, 0.9)]
        # minimise 0 and 1, maximise 2; (1,5,0.4) is dominated by (1,5,0.5).
        self.assertEqual(pareto.pareto_front(pts, [0, 1], [2]), [0, 1, 3])


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
            self.assertIn("\n[8/8] ", p.stderr)  # progress
            # Each progress line names the configuration's swept parameters.
            self.assertRegex(p.stderr, r"config \d+ \(precision=[46] table=(16x2|unbounded) "
                                       r"mode=closest-(exact|spec)\)")
            p = run_sweep(*args, "--csv", b)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(pathlib.Path(a).read_text(), pathlib.Path(b).read_text())
            rows = read(a)
            # 8 configurations x (primary, shadow, ao, all).
            self.assertEqual(len(rows), 8 * 4)
            # dir_code is written only when a row has another direction code than the grid.
            self.assertEqual(list(rows[0]), ["scene", "kind", "res"]
                             + [n for n in tasks.PARAMS if n != "dir_code"]
                             + tasks.RESULT_COLUMNS)
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
            small = {r["table_bytes"] for r in rows
                     if r["table"] == "16x2" and r["precision"] == "6"}
            self.assertEqual(len(small), 1)
            for f in ("time_saved.png", "accuracy_vs_time.png", "skipped_vs_bytes.png",
                      "spec_error_vs_saved.png"):
                self.assertGreater(os.path.getsize(os.path.join(d, "plots", f)), 1000, f)
            report = pathlib.Path(d, "report.md").read_text()
            self.assertIn("## Pareto-optimal configurations", report)
            self.assertIn("### spd_tetra / all / closest-hit queries", report)
            self.assertIn("Smallest table keeping 90%", report)
            self.assertIn("| no predictor (the baseline walk, spp=1) |", report)

    def test_dir_code(self):
        """dir_code=grid,oct on the improved hash: the column appears, the octahedral rows have
        the key of hrpp predict --dir-code oct (2b direction bits), and read back the CSV's rows
        keep their codes; on the faithful hash the parameter is not passed (and not refused)."""
        with tempfile.TemporaryDirectory() as d:
            a = os.path.join(d, "a.csv")
            p = run_sweep(TETRA, "--param", "hash=improved,faithful", "--param",
                          "dir_code=grid,oct", "--param", "table=16x2", "--res", "8x8",
                          "--no-dask", "--no-timing", "--csv", a)
            self.assertEqual(p.returncode, 0, p.stderr)
            rows = read(a)
            self.assertIn("dir_code", rows[0])
            codes = {(r["hash"], r["dir_code"]) for r in rows}
            self.assertEqual(codes, {(h, c) for h in ("improved", "faithful")
                                     for c in ("grid", "oct")})
            by = {(r["hash"], r["dir_code"], r["kind"]): r for r in rows}
            # The octahedral and the grid code differ on the improved hash, not on the faithful.
            self.assertNotEqual(by[("improved", "grid", "all")]["true_positive"] + "/"
                                + by[("improved", "grid", "all")]["table_entries"],
                                by[("improved", "oct", "all")]["true_positive"] + "/"
                                + by[("improved", "oct", "all")]["table_entries"])
            for k in ("true_positive", "table_entries", "skipped_interior"):
                self.assertEqual(by[("faithful", "grid", "all")][k],
                                 by[("faithful", "oct", "all")][k])
            self.assertEqual({r["dir_code"] for r in tasks.read_csv([a])}, {"grid", "oct"})

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
            old_out, old_blocks = split_blocks(old)
            new_out, new_blocks = split_blocks(new)
            self.assertEqual(old_out, new_out)  # the hand-written text is left alone
            for name in DOC_BLOCKS:
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


class Resume(unittest.TestCase):
    """Each finished run is kept in the study driver's journal, CSV.journal.jsonl, as it finishes
    (pyhrpp/study.py): SIGINT / SIGTERM leave one line and the journal, --resume runs only the
    missing runs of the same sweep, and the CSV is byte for byte an uninterrupted run's."""

    ARGS = [TETRA, CORNELL, "--param", "precision=4,6", "--param", "mode=anyhit,closest-spec",
            "--res", "16x16", "--no-timing"]

    @staticmethod
    def journal_runs(path):
        """The finished runs a journal holds (a line each after the header naming the sweep)."""
        return sum('"key"' in line for line in pathlib.Path(path).read_text().splitlines())

    @staticmethod
    def others(stderr):
        """stderr without the progress lines and the driver's first line (how many runs where),
        or its line waiting for a signal."""
        return [line for line in stderr.splitlines() if not line.startswith("[")
                and not re.match(r"hrpp sweep: (\d+ runs |waiting for a signal)", line)]

    @staticmethod
    def progress(stderr):
        return re.findall(r"^\[\d+/\d+\] ", stderr, re.M)

    def test_interrupt_resume_equals_uninterrupted(self):
        with tempfile.TemporaryDirectory() as d:
            ref, a = os.path.join(d, "ref.csv"), os.path.join(d, "a.csv")
            journal = a + ".journal.jsonl"
            p = run_sweep(*self.ARGS, "--no-dask", "--csv", ref)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(self.journal_runs(ref + ".journal.jsonl"), 8)  # kept, complete
            # SIGINT after 3 runs (the driver signals itself: the real handler path).
            p = run_sweep(*self.ARGS, "--no-dask", "--csv", a,
                          env_add={study.STOP_ENV: "3"})
            self.assertEqual(p.returncode, 130, p.stderr)
            self.assertEqual(self.others(p.stderr), [
                f"hrpp sweep: interrupted; 3 of 8 runs kept in {journal}; --resume continues"])
            self.assertNotIn("Traceback", p.stderr)
            self.assertFalse(os.path.exists(a))
            self.assertEqual(self.journal_runs(journal), 3)
            # Without --resume the journal is not overwritten.
            p = run_sweep(*self.ARGS, "--no-dask", "--csv", a)
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("holds 3 finished runs of an interrupted hrpp sweep; --resume continues "
                          "it", p.stderr)
            # Another sweep's journal is refused, naming the difference.
            res = self.ARGS.index("--res") + 1
            other = os.path.join(d, "hrpp-other")  # hrpp of another version
            pathlib.Path(other).write_text(
                f'#!/bin/sh\n[ "$1" = --version ] && {{ echo "hrpp 9.9"; exit 0; }}\n'
                f'exec {HRPP} "$@"\n')
            os.chmod(other, 0o755)
            timed = [x for x in self.ARGS if x != "--no-timing"]
            for args, why in ((self.ARGS[:res] + ["24x24"] + self.ARGS[res + 1:],
                               "res: '16x16' then, '24x24' now"),
                              (self.ARGS + ["--param", "table=16x2"],
                               "--param table: 'not swept' then, '16x2' now"),
                              (self.ARGS + ["--param", "go_up=1"],
                               "--param go_up: 'not swept' then"),
                              (timed, "CPU times: 'not measured' then, 'measured' now"),
                              (self.ARGS[1:], "scenes: "),
                              (self.ARGS + ["--hrpp", other], "'hrpp 9.9' now")):
                p = run_sweep(*args, "--resume", "--no-dask", "--csv", a)
                self.assertEqual(p.returncode, 2, p.stderr)
                self.assertIn(f"--resume: {journal} is of another hrpp sweep: ", p.stderr)
                self.assertIn(why, p.stderr)
                self.assertEqual(self.progress(p.stderr), [])
            self.assertEqual(self.journal_runs(journal), 3)
            # --resume on a Dask cluster, SIGTERM after 2 more runs.
            p = run_sweep(*self.ARGS, "--resume", "--workers", "2", "--csv", a,
                          env_add={study.STOP_ENV: "2:TERM"})
            self.assertEqual(p.returncode, 143, p.stderr)
            self.assertIn(f"hrpp sweep: 5 runs on 2 local Dask workers; 3 of 8 kept from "
                          f"{journal}", p.stderr)
            self.assertEqual(self.others(p.stderr), [
                f"hrpp sweep: interrupted; 5 of 8 runs kept in {journal}; --resume continues"])
            self.assertEqual(self.journal_runs(journal), 5)
            # A last line cut short by a kill is dropped; the kept runs do not run again.
            with open(journal, "a") as f:
                f.write('{"key": ["cut sh')
            p = run_sweep(*self.ARGS, "--resume", "--no-dask", "--csv", a)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(len(self.progress(p.stderr)), 3)  # only 3 ran
            self.assertIn("\n[6/8] ", p.stderr)
            self.assertEqual(pathlib.Path(a).read_text(), pathlib.Path(ref).read_text())
            # The journals are kept; no .tmp file.
            self.assertEqual(sorted(os.listdir(d)), ["a.csv", "a.csv.journal.jsonl", "hrpp-other",
                                                     "ref.csv", "ref.csv.journal.jsonl"])
            # --resume of a complete sweep runs nothing and writes the same CSV; without
            # --resume a complete sweep starts afresh.
            pathlib.Path(a).unlink()
            p = run_sweep(*self.ARGS, "--resume", "--no-dask", "--csv", a)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(self.progress(p.stderr), [])
            self.assertEqual(pathlib.Path(a).read_text(), pathlib.Path(ref).read_text())
            p = run_sweep(*self.ARGS, "--no-dask", "--csv", a)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(len(self.progress(p.stderr)), 8)
            self.assertEqual(self.journal_runs(journal), 8)

    def test_ctrl_c_to_the_process_group(self):
        """A Ctrl-C reaches the driver, the Dask workers and the hrpp runs: one line, exit 130,
        the workers shut down without tracebacks."""
        with tempfile.TemporaryDirectory() as d:
            a = os.path.join(d, "a.csv")
            env = dict(os.environ, **{study.STOP_ENV: "2:WAIT"})
            proc = subprocess.Popen(SWEEP + self.ARGS + ["--workers", "2", "--csv", a],
                                    stderr=subprocess.PIPE, text=True, env=env,
                                    start_new_session=True)
            err = ""
            for line in proc.stderr:
                err += line
                if line.startswith("hrpp sweep: waiting for a signal"):
                    os.killpg(proc.pid, signal.SIGINT)
                    break
            err += proc.stderr.read()
            proc.stderr.close()
            self.assertEqual(proc.wait(timeout=60), 130, err)
            self.assertEqual(self.others(err), [f"hrpp sweep: interrupted; 2 of 8 runs kept in "
                                                f"{a}.journal.jsonl; --resume continues"], err)
            self.assertEqual(os.listdir(d), ["a.csv.journal.jsonl"])


class Presets(unittest.TestCase):
    """--param preset=NAME,...: passed as --preset, the other swept parameters override it; the
    CSV's preset column and parameter columns say what ran; misspelt names fail fast."""

    def predict(self, d, *opts):
        out = os.path.join(d, "direct.json")
        p = subprocess.run([HRPP, "predict", CORNELL, "--res", "16x16", "--json", out]
                           + list(opts), capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        with open(out) as f:
            return json.load(f)

    def test_presets_swept(self):
        with tempfile.TemporaryDirectory() as d:
            a = os.path.join(d, "a.csv")
            p = run_sweep(CORNELL, "--param", "preset=rtl-primary,micro21,study2019",
                          "--param", "table=64x4,unbounded", "--param", "mode=closest-spec",
                          "--res", "16x16", "--no-dask",
                          "--no-timing", "--csv", a, "--report", os.path.join(d, "r.md"))
            self.assertEqual(p.returncode, 0, p.stderr)
            rows = [r for r in read(a) if r["kind"] == "all"]
            self.assertEqual([(r["preset"], r["table"]) for r in rows],
                             [(n, t) for n in ("rtl-primary", "micro21", "study2019")
                              for t in ("64x4", "unbounded")])
            by = {(r["preset"], r["table"]): r for r in rows}
            # The preset's own values fill the parameter columns; the swept table overrides it.
            r = by[("rtl-primary", "64x4")]
            self.assertEqual((r["hash"], r["combine"], r["nodes_per_entry"]),
                             ("improved", "concat", "2"))
            self.assertEqual((by[("micro21", "unbounded")]["hash"],
                              by[("micro21", "unbounded")]["go_up"]), ("micro21", "3"))
            for (preset, table), r in by.items():
                data = self.predict(d, "--preset", preset, "--table", table, "--mode",
                                    "closest-spec")
                msg = f"{preset} {table}"
                self.assertEqual(int(r["true_positive"]), data["true_positive"], msg)
                self.assertAlmostEqual(float(r["hrpp_cycles_per_ray"]),
                                       data["cost"]["hrpp_cycles_per_ray"], places=6, msg=msg)
                self.assertEqual(int(r["table_bytes"]), data["table_bytes"], msg)
            # The preset alone is the preset's run (not the sweep's defaults).
            self.assertNotEqual(self.predict(d, "--preset", "rtl-primary", "--table", "64x4")
                                ["true_positive"],
                                self.predict(d, "--table", "64x4")["true_positive"])
            report = pathlib.Path(d, "r.md").read_text()
            self.assertIn("| rtl-primary table=64x4 |", report)
            self.assertIn("| micro21 table=unbounded |", report)
            # An unbounded table has no size to compare: the report says unbounded.
            self.assertRegex(report, r"\| rtl-primary table=unbounded \| .* \| unbounded \(\d+ "
                                     r"entries used\) \|")
            # Without a preset the column is empty.
            b = os.path.join(d, "b.csv")
            p = run_sweep(CORNELL, "--param", "table=64x4", "--res", "16x16", "--no-dask",
                          "--no-timing", "--csv", b)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual({r["preset"] for r in read(b)}, {""})

    def test_preset_simulated(self):
        with tempfile.TemporaryDirectory() as d:
            a = os.path.join(d, "a.csv")
            p = run_sweep(CORNELL, "--param", "preset=rtl-small", "--res", "8x8", "--no-dask",
                          "--timing", "simulate", "--csv", a)
            self.assertEqual(p.returncode, 0, p.stderr)
            rows = read(a)
            self.assertEqual({(r["preset"], r["table"], r["timing"]) for r in rows},
                             {("rtl-small", "64x2", "simulate")})

    def test_bad_presets_fail_fast(self):
        with tempfile.TemporaryDirectory() as d:
            a = os.path.join(d, "a.csv")
            p = run_sweep(CORNELL, "--param", "preset=rtl-primary,rtl-defualt", "--csv", a)
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("unknown preset 'rtl-defualt'; did you mean 'rtl-default'?", p.stderr)
            self.assertIn("known: ", p.stderr)
            p = run_sweep(CORNELL, "--param", f"preset={d}/mine.json", "--csv", a)
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("mine.json: no such preset file", p.stderr)
            self.assertEqual(os.listdir(d), [])  # nothing run, nothing written


class Plots(unittest.TestCase):
    """The plots of a 2-scene x 24-configuration sweep: time first, every plot names its scenes,
    the fixed configuration and its axes' units, titles and legends never overlap the panels,
    one legend per encoded dimension, unbounded tables apart, large sweeps paged; the report's
    first table is the time figure."""

    def test_plots_and_report(self):
        with tempfile.TemporaryDirectory() as d:
            a = os.path.join(d, "a.csv")
            p = run_sweep(TETRA, CORNELL, "--param", "precision=4,6", "--param",
                          "table=16x2,unbounded", "--param", "mode=anyhit,closest-exact,"
                          "closest-spec", "--param", "latency=none,0", "--res", "16x16",
                          "--no-dask", "--no-timing", "--csv", a)
            self.assertEqual(p.returncode, 0, p.stderr)
            rows = tasks.read_csv([a])
            # Pages of at most 16 configurations and 8 lines (40 and 12 in use).
            limits = plots.PAGE_CONFIGS, plots.PAGE_LINES
            plots.PAGE_CONFIGS, plots.PAGE_LINES = 16, 8
            try:
                files = [f.name for f in plots.plot_all(rows, os.path.join(d, "plots"))]
            finally:
                plots.PAGE_CONFIGS, plots.PAGE_LINES = limits
            self.assertEqual(files, ["time_saved.png", "time_saved-2.png", "accuracy_vs_time.png",
                                     "skipped_vs_bytes.png", "hit_rate_vs_latency.png",
                                     "hit_rate_vs_latency-2.png", "spec_error_vs_saved.png"])
            for f in files:
                self.assertEqual(plots.LAYOUT_PROBLEMS[f], [], f)
                t = plots.PLOT_TEXT[f]
                self.assertIn("cornell_box", t["title"], f)
                self.assertIn("fixed: hash=faithful exp_bits=3", t["title"].replace("\n", " "), f)
                self.assertIn("16x16 pixels", t["title"], f)
                self.assertTrue(all(t["xlabels"]) and all(t["ylabels"]), f)
                units = r"%|fraction|cycles per ray|bytes|, rays|scene|configuration"
                self.assertTrue(all(re.search(units, l) for l in t["xlabels"] + t["ylabels"]), f)
            t = plots.PLOT_TEXT["time_saved.png"]
            self.assertIn("cost model", t["title"])
            self.assertIn("(page 1 of 2)", t["title"])
            self.assertEqual(len([x for x in t["ticks"] if "precision=" in x]), 16)
            self.assertEqual(len([x for x in plots.PLOT_TEXT["time_saved-2.png"]["ticks"]
                                  if "precision=" in x]), 8)
            self.assertTrue(any(x.startswith("costs ") for x in t["texts"]))
            # One legend each for what colour and marker encode.
            t = plots.PLOT_TEXT["accuracy_vs_time.png"]
            title, entries = t["legends"][0]
            self.assertIn("colour: mode; marker: table (SETSxWAYS)", title)
            self.assertIn("not told apart: precision, latency", title)
            self.assertTrue({"anyhit", "closest-exact", "closest-spec", "16x2",
                             "unbounded"} <= set(entries))
            t = plots.PLOT_TEXT["skipped_vs_bytes.png"]
            self.assertEqual(t["legends"][0][0], "colour: precision; marker: mode; panels: "
                                                 "latency")
            self.assertIn("unbounded\n(no fixed size)", t["ticks"])
            self.assertEqual(len(t["xlabels"]), 4)  # 2 scenes x 2 latencies
            # 12 configurations at two delays: two pages of at most 8 lines.
            self.assertEqual(len(plots.PLOT_TEXT["hit_rate_vs_latency.png"]["legends"][0][1]), 8)
            self.assertEqual(len(plots.PLOT_TEXT["hit_rate_vs_latency-2.png"]["legends"][0][1]),
                             4)
            self.assertIn("(page 2 of 2)", plots.PLOT_TEXT["hit_rate_vs_latency-2.png"]["title"])
            # The report leads with time; an unbounded table is not a size.
            r = os.path.join(d, "r.md")
            p = run_sweep("--from-csv", a, "--report", r)
            self.assertEqual(p.returncode, 0, p.stderr)
            report = pathlib.Path(r).read_text()
            self.assertTrue(report.split("\n## ")[1].startswith("Time: what each configuration "
                                                                "saves (all rays; the cost "
                                                                "model's cycles per ray)"))
            self.assertRegex(report, r"\| precision=4 table=16x2 latency=none mode=anyhit \| "
                                     r"(saves|costs) \d+\.\d\d%")
            self.assertIn("% time |", report)


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

    def test_from_csv(self):
        with tempfile.TemporaryDirectory() as d:
            p = run_sweep("--from-csv", os.path.join(d, "missing.csv"), "--report",
                          os.path.join(d, "r.md"))
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("missing.csv: no such file", p.stderr)
            self.assertNotIn("Traceback", p.stderr)
            c = pathlib.Path(d, "a.csv")
            c.write_text(Simulate.COST_HEADER + "\n")
            p = run_sweep("--from-csv", str(c))
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("--from-csv needs an output: --plots DIR, --report FILE or --doc PAGE",
                          p.stderr)
            p = run_sweep("--from-csv", str(c), "--report", os.path.join(d, "r.md"), "--resume")
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("--from-csv runs nothing", p.stderr)


class Simulate(unittest.TestCase):
    """--timing simulate: rows carry `hrpp simulate`'s cycles; sweeping the update delay is an
    error; the default (cost-model) CSV keeps its columns and bytes; timings are never merged."""

    # The cost-model CSV's header as it was before --timing existed, with the preset column.
    COST_HEADER = ("scene,kind,res,preset,hash,precision,exp_bits,origin_bits,dir_bits,combine,"
                   "table,tag_bits,nodes_per_entry,go_up,update_delay,latency,mode,spp,order,rays,"
                   "table_bytes,table_entries,update_delay_rays,pred_precision,pred_recall,"
                   "true_positive,false_positive,false_negative,skipped_interior,skipped_tri,"
                   "skipped_walks,wrong_results,wrong_fraction,accuracy,baseline_cycles_per_ray,"
                   "hrpp_cycles_per_ray,saved_cycles,baseline_ns_per_ray,hrpp_ns_per_ray,"
                   "image_mae,image_differ,spec_image")

    def simulate(self, d, *opts):
        """`hrpp simulate` run directly on CORNELL at 16x16 with the sweep's default predictor
        options written out by hand (the golden model's), and OPTS."""
        out = os.path.join(d, "direct.json")
        p = subprocess.run([HRPP, "simulate", CORNELL, "--res", "16x16", "--no-oracle",
                            "--hash", "faithful", "--precision", "6", "--exp-bits", "3",
                            "--combine", "xor",
                            "--nodes-per-entry", "1", "--go-up", "0", "--spp", "1",
                            "--order", "scanline", "--json", out] + list(opts),
                           capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        with open(out) as f:
            return json.load(f)

    def test_rows_carry_simulated_cycles(self):
        with tempfile.TemporaryDirectory() as d:
            a, b = os.path.join(d, "a.csv"), os.path.join(d, "dask.csv")
            args = [CORNELL, "--param", "table=16x2", "--param", "mode=closest-exact,anyhit",
                    "--res", "16x16", "--timing", "simulate"]
            p = run_sweep(*args, "--no-dask", "--csv", a, "--report", os.path.join(d, "r.md"))
            self.assertEqual(p.returncode, 0, p.stderr)
            rows = read(a)
            self.assertEqual(list(rows[0]), self.COST_HEADER.split(",") + tasks.SIM_COLUMNS)
            self.assertEqual(len(rows), 2 * 4)
            by = {}
            for r in rows:
                by.setdefault(r["mode"], {})[r["kind"]] = r
            self.assertEqual(set(by), {"closest-exact", "anyhit"})
            for mode, kinds in by.items():
                data = self.simulate(d, "--table", "16x2", "--mode", mode, "--gpu", "mobile")
                want = dict(data["by_kind"])
                want["all"] = data
                self.assertEqual(set(kinds), set(want))
                for kind, r in kinds.items():
                    w = want[kind]
                    rays = int(r["rays"])
                    self.assertEqual(rays, w["rays"])
                    msg = f"{mode} {kind}"
                    self.assertAlmostEqual(float(r["hrpp_cycles_per_ray"]) * rays, w["cycles"],
                                           places=4, msg=msg)
                    self.assertAlmostEqual(float(r["baseline_cycles_per_ray"]) * rays,
                                           w["baseline_cycles"], places=4, msg=msg)
                    self.assertAlmostEqual(float(r["saved_cycles"]),
                                           1 - w["cycles"] / w["baseline_cycles"], places=8)
                    self.assertAlmostEqual(float(r["speedup"]), w["speedup"], places=8)
                    self.assertEqual((r["timing"], r["gpu"]), ("simulate", "mobile"))
                    self.assertEqual(r["baseline_ns_per_ray"], "")
                    self.assertEqual(r["oracle_speedup"], "")  # --no-oracle by default
                    self.assertAlmostEqual(float(r["pred_precision"]), w.get(
                        "precision", data["predictor"]["precision"]), places=8)
                self.assertAlmostEqual(float(kinds["all"]["l1_hit_rate"]), data["l1_hit_rate"],
                                       places=8)
                self.assertEqual(int(kinds["all"]["stall_cycles"]),
                                 data["predictor"]["stall_cycles"])
                self.assertEqual(int(kinds["all"]["table_bytes"]), data["preset"]["table_bytes"])
            # The modes differ in time (else the comparison above could not tell them apart).
            self.assertNotEqual(by["anyhit"]["primary"]["hrpp_cycles_per_ray"],
                                by["closest-exact"]["primary"]["hrpp_cycles_per_ray"])
            report = pathlib.Path(d, "r.md").read_text()
            self.assertIn("Time is simulated cycles per ray on the `mobile` GPU", report)
            self.assertIn("| simulated cycles/ray, mobile (baseline) |", report)
            # Through the Dask driver (a local cluster of two workers): the same bytes.
            p = run_sweep(*args, "--workers", "2", "--csv", b)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("on 2 local Dask workers", p.stderr)
            self.assertEqual(pathlib.Path(a).read_text(), pathlib.Path(b).read_text())
            # Never merged with cost-model rows (nor with another GPU's).
            c = os.path.join(d, "cost.csv")
            p = run_sweep(CORNELL, "--param", "table=16x2", "--res", "16x16", "--no-dask",
                          "--no-timing", "--csv", c)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(pathlib.Path(c).read_text().split("\n")[0], self.COST_HEADER)
            p = run_sweep("--from-csv", c, a, "--report", os.path.join(d, "mixed.md"))
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("of the cost model", p.stderr)
            self.assertIn("of the simulated, mobile", p.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, "mixed.md")))

    def test_fronts_on_the_page(self):
        """make report's flow, small: a simulated grid fills the page's fronts and recommendation
        (--doc-blocks), cost-model latency and delay sweeps the latency, delay and speculative
        image blocks; the fronts' header names the GPU, their cycles have two decimals; the
        report of a simulated closest-spec sweep has no pictures to show."""
        page = ROOT / "docs" / "results.md"
        with tempfile.TemporaryDirectory() as d:
            grid, lat, delay = (os.path.join(d, f"{n}.csv") for n in ("grid", "lat", "delay"))
            common = [CORNELL, "--res", "16x16", "--no-dask", "--no-timing"]
            for csv_, params in ((grid, ["precision=4,5", "table=16x2,unbounded",
                                         "mode=anyhit,closest-spec"]),
                                 (lat, ["table=16x2", "mode=anyhit,closest-spec",
                                        "latency=none,0"]),
                                 (delay, ["table=16x2", "mode=anyhit,closest-spec",
                                          "update_delay=0,16"])):
                p = run_sweep(*common, *[a for v in params for a in ("--param", v)],
                              *(["--timing", "simulate"] if csv_ == grid else []), "--csv", csv_)
                self.assertEqual(p.returncode, 0, p.stderr)
            doc = pathlib.Path(d, "results.md")
            doc.write_text(page.read_text())
            fronts, pipeline = pathlib.Path(d, "fronts.md"), pathlib.Path(d, "pipeline.md")
            p = run_sweep("--from-csv", grid, "--report", str(fronts), "--doc", str(doc),
                          "--doc-blocks", "sweep-pareto,sweep-recommend")
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("sweep: wrote sweep-pareto, sweep-recommend blocks of", p.stderr)
            text = fronts.read_text()
            self.assertIn("Time is simulated cycles per ray on the `mobile` GPU", text)
            self.assertNotIn("## Speculative closest hits", text)  # hrpp simulate: no pictures
            self.assertRegex(text, r"\| no predictor \(the baseline walk, spp=1\) \| \d+\.\d\d \|")
            p = run_sweep("--from-csv", lat, delay, "--report", str(pipeline), "--doc", str(doc),
                          "--doc-blocks", "sweep-latency,sweep-delay,sweep-spec")
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("sweep: wrote sweep-latency, sweep-delay, sweep-spec blocks of",
                          p.stderr)
            self.assertIn("Both are the cost model's", pipeline.read_text())
            new = doc.read_text()
            old_out, old_blocks = split_blocks(page.read_text())
            new_out, new_blocks = split_blocks(new)
            self.assertEqual(old_out, new_out)
            for name in DOC_BLOCKS:
                self.assertIn("| cornell_box |", new_blocks[name], name)
            self.assertIn("| scene | kind | query | baseline cycles/ray (simulated, mobile GPU) |",
                          new_blocks["sweep-pareto"])
            self.assertRegex(new_blocks["sweep-pareto"],
                             r"\| cornell_box \| all \| any-hit \| \d+\.\d\d \| .*"
                             r"no predictor \(\d+\.\d\d, 100\.00%\) \|")
            self.assertIn("| scene | mode | P = 4 | P = 5 |", new_blocks["sweep-recommend"])
            self.assertIn("| scene | mode | precision: untimed / 16 rays |",
                          new_blocks["sweep-latency"])
            self.assertNotIn("(simulated", new_blocks["sweep-latency"])
            # Each block from rows that fill it; unknown names; the page left as it was.
            for rows, blocks, err in (
                    ([grid], "sweep-latency", "--doc-blocks: these rows fill no sweep-latency "
                                              "block"),
                    ([grid], "sweep-spec", "these rows fill no sweep-spec block"),
                    ([lat], "sweep-fronts", "--doc-blocks: unknown block 'sweep-fronts'")):
                p = run_sweep("--from-csv", *rows, "--doc", str(doc), "--doc-blocks", blocks)
                self.assertEqual(p.returncode, 2, p.stderr)
                self.assertIn(err, p.stderr)
                self.assertEqual(doc.read_text(), new)

    def test_errors(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "a.csv")
            for param in ("update_delay=0,16", "latency=0"):
                p = run_sweep(CORNELL, "--param", param, "--timing", "simulate", "--res",
                              "16x16", "--no-dask", "--csv", out)
                self.assertEqual(p.returncode, 2, p.stderr)
                self.assertIn(f"--param {param.split('=')[0]}: does not apply to --timing "
                              "simulate", p.stderr)
            p = run_sweep(CORNELL, "--param", "table=16x2", "--gpu", "desktop", "--no-dask",
                          "--csv", out)
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("--gpu and --oracle need --timing simulate", p.stderr)
            p = run_sweep(CORNELL, "--param", "table=16x2", "--timing", "simulate", "--gpu",
                          os.path.join(d, "nope.json"), "--no-dask", "--csv", out)
            self.assertEqual(p.returncode, 2, p.stderr)
            self.assertIn("not mobile, desktop or a file", p.stderr)
            self.assertFalse(os.path.exists(out))

    def test_default_is_cost_model(self):
        with tempfile.TemporaryDirectory() as d:
            a, b = os.path.join(d, "a.csv"), os.path.join(d, "b.csv")
            args = [TETRA, "--param", "precision=4,6", "--res", "16x16", "--no-dask",
                    "--no-timing"]
            p = run_sweep(*args, "--csv", a)
            self.assertEqual(p.returncode, 0, p.stderr)
            p = run_sweep(*args, "--timing", "cost-model", "--csv", b)
            self.assertEqual(p.returncode, 0, p.stderr)
            text = pathlib.Path(a).read_text()
            self.assertEqual(text, pathlib.Path(b).read_text())
            self.assertEqual(text.split("\n")[0], self.COST_HEADER)
            # The cost model's figures: hrpp predict's cost fields.
            out = os.path.join(d, "p.json")
            p = subprocess.run([HRPP, "predict", TETRA, "--res", "16x16", "--precision", "6",
                                "--json", out], capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(out) as f:
                cost = json.load(f)["cost"]
            row = [r for r in read(a) if r["precision"] == "6" and r["kind"] == "all"][0]
            self.assertAlmostEqual(float(row["hrpp_cycles_per_ray"]),
                                   cost["hrpp_cycles_per_ray"], places=6)


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
                self.assertIn(f"on the Dask cluster at {cluster.scheduler_address}", p.stderr)
            p = run_sweep(*args, "--no-dask", "--csv", b)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(pathlib.Path(a).read_text(), pathlib.Path(b).read_text())
            self.assertEqual(len(read(a)), 2 * 8 * 4)


if __name__ == "__main__":
    unittest.main()
