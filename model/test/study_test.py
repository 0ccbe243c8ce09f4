#!/usr/bin/env python3
"""Tests of the study driver (pyhrpp/study.py; ctest study.*), on a stand-in tool (this file run
as `tool`): results in task order whatever the workers, the journal and --resume, interruption,
failures, and a Dask scheduler with two worker processes started as separate processes.

Run one class:  .venv/bin/python model/test/study_test.py Journal
"""
import json
import os
import pathlib
import signal
import subprocess
import sys
import tempfile
import time
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from pyhrpp import study  # noqa: E402

ME = str(pathlib.Path(__file__).resolve())
PY = sys.executable
DASK = str(pathlib.Path(PY).parent / "dask")


def tool(argv):
    """The stand-in tool: tool N --json PATH|- [--log FILE] [--rc RC] [--sleep S]: writes the
    report {"n": N, "square": N*N, "json": PATH} (PATH: the tool's own record of where it wrote,
    as hrpp's reports record their command line) and appends N to FILE (to count runs)."""
    n = int(argv[0])
    opts = dict(zip(argv[1::2], argv[2::2]))
    time.sleep(float(opts.get("--sleep", 0)))
    if "--log" in opts:
        with open(opts["--log"], "a") as f:
            f.write(f"{n}\n")
    rc = int(opts.get("--rc", 0))
    if rc:
        print(f"tool: bad input {n}" + (": node ids name at most 6 bits" if rc == 2 else ""),
              file=sys.stderr)
        return rc
    text = json.dumps({"n": n, "square": n * n, "json": opts["--json"]}) + "\n"
    if opts["--json"] == "-":
        sys.stdout.write(text)
    else:
        pathlib.Path(opts["--json"]).write_text(text)
    print(f"tool: {n} done", file=sys.stderr)
    return 0


def drive(argv):
    """A small study: drive OUT N [driver options] [--fail K] [--unsupported K] [--stdout]:
    N tasks; task i sleeps (N - i) * 0.05 s (later tasks finish first); writes OUT/i.json and
    OUT/summary.json (the reports in task order)."""
    import argparse
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("n", type=int)
    ap.add_argument("--fail", type=int, default=-1)
    ap.add_argument("--unsupported", type=int, default=-1)
    ap.add_argument("--stdout", action="store_true")
    ap.add_argument("--name", default="teststudy")
    ap.add_argument("--ident", default="1")
    study.add_arguments(ap)
    args = ap.parse_args(argv)
    out = pathlib.Path(args.out)

    def go():
        tasks = []
        for i in range(args.n):
            # The stand-in by its path relative to the driver's folder: the workers (elsewhere
            # in the Scheduler test) run it from there.
            cmd = [PY, os.path.relpath(ME), "tool", i, "--json", "-" if args.stdout else "{json}",
                   "--sleep", (args.n - i) * 0.05, "--log", out / "log.txt"]
            if i == args.fail:
                cmd += ["--rc", 3]
            if i == args.unsupported:
                cmd += ["--rc", 2]
            tasks.append(study.Task(key=("task", str(i)), cmd=cmd,
                                    files={} if args.stdout else {"json": out / f"{i}.json"},
                                    report="stdout" if args.stdout else "json",
                                    unsupported="node ids name at most"))
        with study.Study(args.name, out / "journal.jsonl", {"ident": args.ident}, args) as st:
            res = st.run(tasks, summary=lambda t, r: f"square {r.report['square']}"
                         if r.report else r.unsupported)
            (out / "summary.json").write_text(json.dumps(
                [r.report if r.report else {"unsupported": r.unsupported} for r in res]) + "\n")
            st.complete()
        return 0
    return study.main_errors(args.name, go)


def run_drive(out, *args, env_add=None):
    env = dict(os.environ, **(env_add or {}))
    return subprocess.run([PY, ME, "drive", str(out)] + [str(a) for a in args],
                          capture_output=True, text=True, env=env)


def outputs(out):
    """The study's outputs (not its journal or log), name -> text, the folder OUT named OUT."""
    return {p.name: p.read_text().replace(str(out), "OUT")
            for p in sorted(pathlib.Path(out).iterdir()) if p.suffix == ".json"}


def runs_logged(out):
    p = pathlib.Path(out, "log.txt")
    return sorted(int(x) for x in p.read_text().split()) if p.exists() else []


class Order(unittest.TestCase):
    """The outputs are the same one after another, on one worker and on two; in task order
    though the later tasks finish first."""

    def test_same_outputs_whatever_the_workers(self):
        with tempfile.TemporaryDirectory() as d:
            got = {}
            for name, opts in (("no-dask", ["--no-dask"]), ("w1", ["--workers", 1]),
                               ("w2", ["--workers", 2])):
                out = pathlib.Path(d, name)
                r = run_drive(out, 6, *opts)
                self.assertEqual(r.returncode, 0, r.stderr)
                got[name] = outputs(out)
                self.assertEqual(runs_logged(out), list(range(6)))
            self.assertEqual(got["no-dask"], got["w1"])
            self.assertEqual(got["no-dask"], got["w2"])
            summary = json.loads(got["w2"]["summary.json"])
            self.assertEqual([s["n"] for s in summary], list(range(6)))
            # The report names where it was written, not the worker's temporary file.
            self.assertEqual(json.loads(got["w2"]["3.json"]),
                             {"n": 3, "square": 9, "json": "OUT/3.json"})
            # Progress: done of all, rate, time left; the header says where the runs go.
            self.assertIn("6 runs on 2 local Dask workers", r.stderr)
            self.assertRegex(r.stderr, r"\[6/6\] task \d square \d+ \([0-9.]+ s; [0-9.]+ "
                                       r"runs/min; 0 s left\)")

    def test_report_on_stdout(self):
        with tempfile.TemporaryDirectory() as d:
            r = run_drive(d, 3, "--no-dask", "--stdout")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual([(s["square"], s["json"]) for s in json.loads(
                pathlib.Path(d, "summary.json").read_text())], [(0, "-"), (1, "-"), (4, "-")])


class Journal(unittest.TestCase):
    def test_interrupt_then_resume_equals_uninterrupted(self):
        with tempfile.TemporaryDirectory() as d:
            ref = pathlib.Path(d, "ref")
            self.assertEqual(run_drive(ref, 5, "--no-dask").returncode, 0)
            for sig, how, rc in ((signal.SIGINT, "", 130), (signal.SIGTERM, ":TERM", 143)):
                out = pathlib.Path(d, f"cut{rc}")
                r = run_drive(out, 5, "--workers", 2,
                              env_add={study.STOP_ENV: "2" + how})
                self.assertEqual(r.returncode, rc, r.stderr)
                self.assertIn("interrupted; 2 of 5 runs kept in", r.stderr)
                self.assertNotIn("Traceback", r.stderr)
                self.assertFalse(pathlib.Path(out, "summary.json").exists())
                first = runs_logged(out)
                # Without --resume the interrupted journal is refused (its runs would be lost).
                r = run_drive(out, 5, "--no-dask")
                self.assertEqual(r.returncode, 2)
                self.assertIn("holds 2 finished runs of an interrupted teststudy; --resume "
                              "continues it", r.stderr)
                r = run_drive(out, 5, "--no-dask", "--resume")
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertIn("3 runs one after another (--no-dask); 2 of 5 kept", r.stderr)
                # The kept runs did not run again.
                again = runs_logged(out)
                self.assertEqual(len(again) - len(first), 3)
                self.assertEqual(sorted(set(again)), list(range(5)))
                self.assertEqual(outputs(out), outputs(ref))

    def test_resume_of_a_complete_study_runs_nothing(self):
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(run_drive(d, 3, "--no-dask").returncode, 0)
            before = outputs(d)
            pathlib.Path(d, "1.json").unlink()  # rewritten from the journal
            r = run_drive(d, 3, "--no-dask", "--resume")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(runs_logged(d), [0, 1, 2])
            self.assertEqual(outputs(d), before)
            # A complete journal without --resume: the study starts afresh.
            r = run_drive(d, 3, "--no-dask")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(runs_logged(d), [0, 0, 1, 1, 2, 2])

    def test_another_studys_journal_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(run_drive(d, 2, "--no-dask").returncode, 0)
            r = run_drive(d, 2, "--no-dask", "--resume", "--name", "other")
            self.assertEqual(r.returncode, 2)
            self.assertIn("is the journal of another study (teststudy, not other)", r.stderr)
            r = run_drive(d, 2, "--no-dask", "--resume", "--ident", "2")
            self.assertEqual(r.returncode, 2)
            self.assertIn("is of another teststudy: ident: '1' then, '2' now", r.stderr)
            self.assertEqual(runs_logged(d), [0, 1])

    def test_another_build_only_with_resume_any_build(self):
        with tempfile.TemporaryDirectory() as d:
            old, new = "hrpp 0.1.0 (commit 1111111)", "hrpp 0.1.0 (commit 2222222-dirty)"
            self.assertEqual(run_drive(d, 2, "--no-dask", "--ident", old).returncode, 0)
            r = run_drive(d, 2, "--no-dask", "--resume", "--ident", new)
            self.assertEqual(r.returncode, 2)
            self.assertIn("only the build differs: --resume-any-build keeps its runs", r.stderr)
            r = run_drive(d, 2, "--no-dask", "--resume-any-build", "--ident", new)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(runs_logged(d), [0, 1])  # kept
            # Another version is another tool, with or without it.
            r = run_drive(d, 2, "--no-dask", "--resume-any-build", "--ident", "hrpp 0.2.0")
            self.assertEqual(r.returncode, 2)
            self.assertNotIn("only the build differs", r.stderr)

    def test_a_changed_command_runs_again(self):
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(run_drive(d, 3, "--no-dask").returncode, 0)
            r = run_drive(d, 4, "--no-dask", "--resume")  # every sleep changes: all run again
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(runs_logged(d), [0, 0, 1, 1, 2, 2, 3])

    def test_a_journal_cut_short_by_a_kill(self):
        with tempfile.TemporaryDirectory() as d:
            out = pathlib.Path(d)
            r = run_drive(out, 4, "--no-dask", env_add={study.STOP_ENV: "2"})
            self.assertEqual(r.returncode, 130)
            j = out / "journal.jsonl"
            j.write_text(j.read_text()[:-20])  # the second run's line cut short
            r = run_drive(out, 4, "--no-dask", "--resume")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("3 runs one after another (--no-dask); 1 of 4 kept", r.stderr)


class Failures(unittest.TestCase):
    def test_a_failed_run_stops_the_study(self):
        with tempfile.TemporaryDirectory() as d:
            for opts in (["--no-dask"], ["--workers", 2]):
                out = pathlib.Path(d, str(opts[-1]))
                r = run_drive(out, 4, "--fail", 3, *opts)
                self.assertEqual(r.returncode, 1, r.stderr)
                self.assertRegex(r.stderr, r"teststudy: \S+ \S+ tool 3 .* exited 3:\n"
                                           r"tool: bad input 3\nteststudy: stopped; (\d runs? "
                                           r"finished kept in .*journal.jsonl; --resume "
                                           r"continues|no run had finished)")
                self.assertNotIn("Traceback", r.stderr)
                self.assertFalse((out / "summary.json").exists())

    def test_unsupported_is_a_finished_run(self):
        with tempfile.TemporaryDirectory() as d:
            r = run_drive(d, 3, "--no-dask", "--unsupported", 1)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(json.loads(pathlib.Path(d, "summary.json").read_text())[1],
                             {"unsupported": "tool: bad input 1: node ids name at most 6 bits"})

    def test_bad_options(self):
        with tempfile.TemporaryDirectory() as d:
            r = run_drive(d, 1, "--workers", 0)
            self.assertEqual(r.returncode, 2)
            self.assertIn("teststudy: --workers must be at least 1, got 0", r.stderr)
            r = run_drive(d, 1, "--no-dask", "--scheduler", "tcp://127.0.0.1:1")
            self.assertEqual(r.returncode, 2)
            self.assertIn("--scheduler and --no-dask exclude each other", r.stderr)
            r = run_drive(d, 1, "--scheduler", "tcp://127.0.0.1:1")
            self.assertEqual(r.returncode, 2)
            self.assertIn("--scheduler tcp://127.0.0.1:1: no Dask scheduler there", r.stderr)
            r = subprocess.run([PY, ME, "drive", d, "1", "--no-dask"], capture_output=True,
                               text=True)
            self.assertEqual(r.returncode, 0, r.stderr)


class Scheduler(unittest.TestCase):
    """A scheduler and two workers, each a separate process started as on a cluster's machines
    (`dask scheduler`, `dask worker ADDRESS`; the workers in another folder, without the
    repository on their path): the study through --scheduler equals --no-dask."""

    def test_scheduler_and_two_workers(self):
        with tempfile.TemporaryDirectory() as d:
            sched_file = pathlib.Path(d, "scheduler.json")
            env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
            procs = [subprocess.Popen([DASK, "scheduler", "--host", "127.0.0.1", "--port", "0",
                                       "--no-dashboard", "--scheduler-file", str(sched_file)],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                      env=env, cwd=d)]
            try:
                for _ in range(300):
                    if sched_file.exists() and sched_file.stat().st_size:
                        break
                    time.sleep(0.1)
                address = json.loads(sched_file.read_text())["address"]
                for _ in range(2):
                    procs.append(subprocess.Popen(
                        [DASK, "worker", address, "--nworkers", "1", "--nthreads", "1",
                         "--no-dashboard"], stdout=subprocess.DEVNULL,
                        stderr=subprocess.DEVNULL, env=env, cwd=d))
                ref, out = pathlib.Path(d, "ref"), pathlib.Path(d, "cluster")
                self.assertEqual(run_drive(ref, 6, "--no-dask").returncode, 0)
                r = run_drive(out, 6, "--scheduler", address)
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertIn(f"6 runs on the Dask cluster at {address}", r.stderr)
                self.assertEqual(outputs(out), outputs(ref))
            finally:
                for p in reversed(procs):
                    p.terminate()
                for p in procs:
                    try:
                        p.wait(timeout=20)
                    except subprocess.TimeoutExpired:
                        p.kill()


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "tool":
        sys.exit(tool(sys.argv[2:]))
    if len(sys.argv) > 1 and sys.argv[1] == "drive":
        sys.exit(drive(sys.argv[2:]))
    unittest.main()
