"""The project's one study driver: every study (the sweep, make sim-results, make design-study,
make results, make port-rate, make exactness, the figure capture) is a list of tasks, each one run
of a tool (`hrpp`, `tb_hrpp`) with its arguments and the report it writes, run here.

    from pyhrpp import study
    study.add_arguments(ap)                       # --workers N | --scheduler ADDRESS | --no-dask,
                                                  # --resume
    with study.Study("design_study", journal=OUT / "journal.jsonl", identity={...},
                     args=args) as st:
        results = st.run([study.Task(key=("mobile", "bunny"), cmd=[hrpp, "simulate", scene,
                                     "--json", "{json}"], files={"json": OUT / "bunny.json"})])
        results[0].report                          # the parsed JSON report, in task order

Where the tasks run: on a Dask LocalCluster of --workers workers (the default: one per core), in
this process: each worker is a thread that waits for one tool process at a time, and the tools do
the work, so threads cost less than worker processes (a design study of 200 runs of 0.3 s took 1-2%
longer than on a plain thread pool, against about 6% with worker processes: each starts Python and
imports Dask, and every result crosses a socket); on a running Dask cluster (--scheduler
tcp://HOST:PORT; its workers must see the same tool and scene paths: a shared file system or the
same checkout), or one after another in this process (--no-dask, which needs no Dask). This module
is shipped to the workers by value, so a remote worker needs Python and Dask, not the repository.

A task's files: `{NAME}` in its command names a file the tool writes. The worker gives the tool a
path in a temporary folder of its own for each (the tool runs in the driver's working folder),
reads the files back and returns them with the tool's output; the
driver writes each to its destination (Task.files[NAME], through NAME.tmp and a rename: never half
written). Where the tool's output names a file's temporary path (hrpp's reports record their own
command line), the destination is put in its place, so the outputs are those of a tool run that
wrote its files in place. The file `json` is the task's report (Result.report); a task with
report="stdout" has it on the tool's standard output instead (`--json -`).

Results come back in task order whatever the number of workers or the order the runs finish, so a
study's outputs are byte for byte the same on one worker, two, a cluster or --no-dask.

The journal (JSON lines: a header naming the study, then one line per finished run with its
result) is written as each run finishes, and kept when the study completes. --resume keeps every
run the journal holds whose key and record (its command, and any text its Task.record adds, e.g.
the contents of a preset file) are unchanged, and runs the rest; a journal of another study, or of
the same study with another identity (another tool version, another grid), is refused, naming the
difference; --resume-any-build also keeps the runs of another build of the same tool version
(another commit in its `--version` line). Without --resume a complete journal is started afresh,
and an incomplete one (an interrupted study) is refused: its runs would be lost.

Progress: one line per finished run on stderr (done of all, the run's summary, runs per minute,
time left). SIGINT or SIGTERM stops the study with one line (exit 130 or 143): the Dask workers
are shut down and the journal keeps the finished runs. A run that fails (exit code not in
Task.ok) stops the study: its command, exit code and standard error are printed, and the exit
code is 2 when the tool said bad input (exit 2), 1 otherwise.

Standard library only, except Dask when it is used.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

STOP_ENV = "HRPP_STUDY_STOP_AFTER"  # a test hook: N[:TERM|:WAIT], see Study._after_run


class StudyError(Exception):
    """Bad options or a journal that cannot be used: exit code 2, the message names the fix."""


@dataclass(frozen=True)
class Task:
    """One tool run. key: its name in the study (unique; strings), shown in progress lines and
    stored in the journal. cmd: the command line; `{NAME}` stands for the file NAME the tool
    writes (see files). files: NAME -> where the driver writes that file (None: kept in the result
    only). report: "json" (the file `json` is the report), "stdout" (the standard output is) or
    None. stdout: where to write the tool's standard output (None: not written). ok: the exit
    codes that are a finished run (None: any). unsupported: a run exiting 2 with this text (or
    one of these texts) in its standard error is a finished run whose Result.unsupported is the
    error's last line (a limit of the configuration, not a failure). record: more text that
    identifies the run for --resume besides its command (e.g. the contents of a file the command
    names)."""
    key: tuple
    cmd: list
    files: dict = field(default_factory=dict)
    report: str | None = "json"
    stdout: str | Path | None = None
    ok: tuple = (0,)
    unsupported: str | tuple | None = None
    record: str = ""

    def plain(self) -> dict:
        return {"cmd": [str(c) for c in self.cmd],
                "files": {n: str(d) if d else "{" + n + "}" for n, d in self.files.items()},
                "unsupported": self.unsupported, "cwd": os.getcwd()}

    def record_text(self):
        return "\n".join(map(str, self.cmd)) + ("\n" + self.record if self.record else "")


class Result:
    """A finished run: rc, seconds, stdout, stderr, files (NAME -> text), unsupported (None or the
    tool's last line of error) and report (the parsed JSON report, None without one)."""

    def __init__(self, data: dict, report_kind: str | None):
        self.data = data
        self.rc, self.seconds = data["rc"], data["seconds"]
        self.stdout, self.stderr = data["stdout"], data["stderr"]
        self.files, self.unsupported = data["files"], data.get("unsupported")
        self._kind, self._report = report_kind, None

    @property
    def report(self):
        if self._report is None and not self.unsupported:
            text = (self.files.get("json") if self._kind == "json"
                    else self.stdout if self._kind == "stdout" else None)
            self._report = json.loads(text) if text else None
        return self._report


def execute(task: dict) -> dict:
    """Runs TASK (a Task's plain() form: plain data, which any worker unpickles) here or on a
    Dask worker, in the driver's working folder, its files in a temporary folder of its own; the
    data of its Result. Standard library only."""
    tmp = tempfile.mkdtemp(prefix="hrpp-study-")
    try:
        paths = {name: os.path.join(tmp, f"{name}.out") for name in task["files"]}
        cmd = list(task["cmd"])
        for name, p in paths.items():
            cmd = [c.replace("{" + name + "}", p) for c in cmd]
        if not os.path.isdir(task["cwd"]):
            return {"rc": 127, "seconds": 0.0, "stdout": "", "files": {}, "cmd": cmd,
                    "stderr": f"the driver's folder {task['cwd']} is not on this worker (the "
                              "workers must see the driver's paths: docs/studies.md)"}
        t0 = time.time()
        try:
            # In the driver's folder, so that relative paths (build/hrpp, ../shared) name the
            # same files on a cluster's workers as here.
            proc = subprocess.run(cmd, capture_output=True, text=True, cwd=task["cwd"])
        except OSError as e:  # no such tool or folder, not executable
            return {"rc": 127, "seconds": 0.0, "stdout": "", "stderr": f"{cmd[0]}: {e}",
                    "files": {}, "cmd": cmd}
        data = {"rc": proc.returncode, "seconds": round(time.time() - t0, 3),
                "stdout": proc.stdout, "stderr": proc.stderr, "files": {}, "cmd": cmd}
        texts = task["unsupported"] or ()
        if proc.returncode == 2 and any(t in proc.stderr for t in
                                        ([texts] if isinstance(texts, str) else texts)):
            data["unsupported"] = proc.stderr.strip().splitlines()[-1]
            return data
        for name, p in paths.items():
            if os.path.exists(p):
                with open(p) as f:
                    data["files"][name] = f.read()

        def named(text):  # the tool's own record of its command names the destinations
            for name, p in paths.items():
                text = text.replace(p, task["files"][name])
            return text
        data["files"] = {n: named(t) for n, t in data["files"].items()}
        data["stdout"], data["stderr"] = named(data["stdout"]), named(data["stderr"])
        return data
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def add_arguments(ap, what="runs"):
    """The driver's options on the argparse parser AP."""
    g = ap.add_argument_group("where the runs go (pyhrpp/study.py)")
    g.add_argument("--workers", "--jobs", type=int, default=os.cpu_count() or 1,
                   help=f"{what} at a time on a local Dask cluster of this many workers "
                        "(default: one per core)")
    g.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on the Dask cluster whose scheduler is at ADDRESS "
                        "(tcp://HOST:PORT); its workers must see the same tool and scene paths")
    g.add_argument("--no-dask", action="store_true",
                   help=f"run the {what} one after another in this process")
    g.add_argument("--resume", action="store_true",
                   help="keep the finished runs of the study's journal whose command is "
                        "unchanged and run the rest")
    g.add_argument("--resume-any-build", action="store_true",
                   help="--resume, keeping also the runs of another build of the tools (another "
                        "commit in `--version`): for changes since then that cannot move them "
                        "(docs, a study's spec), which is yours to judge")


def tool_version(tool) -> str:
    """`TOOL --version`'s first line (part of a study's identity)."""
    try:
        proc = subprocess.run([str(tool), "--version"], capture_output=True, text=True)
    except OSError as e:
        raise StudyError(f"{tool}: {e.strerror} (build it: make build)")
    return (proc.stdout.strip().splitlines() or [f"unknown (exit {proc.returncode})"])[0]


class _Failed(Exception):
    def __init__(self, task, data):
        super().__init__(task.key)
        self.task, self.data = task, data


class Interrupted(Exception):
    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _build(value, ignore):
    """VALUE without the commit of a `--version` line ("hrpp 0.1.0 (commit 7bafa2b)") when
    IGNORE."""
    if ignore and isinstance(value, str):
        return re.sub(r" \(commit [^)]*\)", "", value)
    return value


def _runs(n):
    return f"{n} run{'s' * (n != 1)}"


def _duration(s):
    s = int(round(s))
    return f"{s // 3600} h {s % 3600 // 60:02d} min" if s >= 3600 else \
        f"{s // 60} min {s % 60:02d} s" if s >= 60 else f"{s} s"


class Study:
    """A study's runs and journal. NAME names it in messages and in the journal; IDENTITY (a
    JSON-able dict) is what every run of the journal must share with this study (tool versions,
    the options that shape every run); ARGS holds the options of add_arguments. Use as a context
    manager: the Dask cluster is shut down on leaving. quiet: no progress lines."""

    def __init__(self, name, journal, identity, args, quiet=False):
        self.name, self.path, self.identity = name, Path(journal), dict(identity)
        self.workers, self.scheduler = args.workers, args.scheduler
        self.any_build = getattr(args, "resume_any_build", False)
        self.no_dask, self.resume, self.quiet = args.no_dask, args.resume or self.any_build, quiet
        if self.scheduler and self.no_dask:
            raise StudyError("--scheduler and --no-dask exclude each other")
        if self.workers < 1:
            raise StudyError(f"--workers must be at least 1, got {self.workers}")
        self.done = {}  # key -> (record, data)
        self.client = self.cluster = None
        self._new = 0
        self._open_journal()

    # ---- the journal ---------------------------------------------------------------------------
    def _header(self):
        return {"study": self.name, "identity": self.identity}

    def _read_journal(self):
        lines = self.path.read_text().split("\n")
        try:
            header = json.loads(lines[0])
            header["study"], header["identity"]
        except (ValueError, KeyError, TypeError):
            raise StudyError(f"{self.path}: not a study journal (delete it to start again)")
        done, complete = {}, False
        for line in lines[1:]:
            try:
                e = json.loads(line)
            except ValueError:
                break  # a last line cut short by a kill
            if e.get("complete"):
                complete = True
                continue
            done[tuple(e["key"])] = (e["record"], e["result"])
        return header, done, complete

    def _open_journal(self):
        done = {}
        if self.path.exists():
            header, done, complete = self._read_journal()
            if header["study"] != self.name:
                raise StudyError(f"{self.path} is the journal of another study "
                                 f"({header['study']}, not {self.name}); give another --out or "
                                 "delete it")
            if self.resume:
                then = header["identity"]
                diff = [f"{k}: {then.get(k)!r} then, {v!r} now"
                        for k, v in self.identity.items()
                        if _build(then.get(k), self.any_build) != _build(v, self.any_build)]
                diff += [f"{k}: {v!r} then, not set now" for k, v in then.items()
                         if k not in self.identity]
                if diff:
                    builds = all(_build(then.get(k), True) == _build(v, True)
                                 for k, v in self.identity.items()) and set(then) <= set(
                                     self.identity)
                    raise StudyError(
                        f"--resume: {self.path} is of another {self.name}: " + "; ".join(diff)
                        + ("; only the build differs: --resume-any-build keeps its runs if "
                           "nothing since can move them" if builds else ""))
            elif not complete and done:
                raise StudyError(f"{self.path} holds {len(done)} finished runs of an interrupted "
                                 f"{self.name}; --resume continues it (or delete it to start "
                                 "again)")
            else:
                done = {}
        elif self.resume:
            self._say(f"--resume: no journal at {self.path}; every run is new")
        self.done = done
        self.path.parent.mkdir(parents=True, exist_ok=True)
        text = json.dumps(self._header()) + "\n" + "".join(
            json.dumps({"key": list(k), "record": r, "result": d}) + "\n"
            for k, (r, d) in done.items())
        tmp = self.path.with_name(self.path.name + ".tmp")
        tmp.write_text(text)
        os.replace(tmp, self.path)
        self.journal = open(self.path, "a")

    def _append(self, obj):
        self.journal.write(json.dumps(obj) + "\n")
        self.journal.flush()
        os.fsync(self.journal.fileno())

    def complete(self):
        """Marks the journal complete (the study's outputs are written): a later run without
        --resume starts afresh."""
        self._append({"complete": True})

    # ---- running -------------------------------------------------------------------------------
    def _say(self, msg):
        if not self.quiet:
            print(f"{self.name}: {msg}", file=sys.stderr, flush=True)

    def _start_dask(self):
        # Dask's warnings about tasks cancelled by an interruption are no news (errors still
        # show); set before the import, which reads it.
        os.environ.setdefault("DASK_LOGGING__DISTRIBUTED", "error")
        try:
            import cloudpickle
            from dask.distributed import Client, LocalCluster
        except ImportError:
            raise StudyError("Dask is not installed in this Python (run the study with "
                             ".venv/bin/python, or give --no-dask)")
        # Shipped by value: a remote worker needs no copy of the repository.
        cloudpickle.register_pickle_by_value(sys.modules[__name__])
        if self.scheduler:
            try:
                self.client = Client(self.scheduler, timeout="20s")
            except OSError as e:
                raise StudyError(f"--scheduler {self.scheduler}: no Dask scheduler there ({e})")
            return
        import warnings
        warnings.filterwarnings("ignore", message=r"Port \d+ is already in use")
        self.cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1,
                                    processes=False, dashboard_address=None)
        self.client = Client(self.cluster)

    def _runs(self, todo):
        """(index, data) of every task of TODO [(index, task)] as each finishes."""
        if not todo:
            return
        if self.no_dask:
            for i, t in todo:
                yield i, execute(t.plain())
            return
        if self.client is None:
            self._start_dask()
        from dask.distributed import as_completed
        client = self.client
        def run_task(task):  # local: Dask's pickle then ships it, and execute, by value
            return execute(task)

        futures = client.map(run_task, [t.plain() for _, t in todo], pure=False)
        index = {f.key: i for f, (i, _) in zip(futures, todo)}
        try:
            for fut in as_completed(futures):
                yield index[fut.key], fut.result()
        except BaseException:  # interrupted, failed, or closed by run()
            import logging
            logging.getLogger("distributed").setLevel(logging.CRITICAL)
            client.cancel(futures)
            raise

    def where(self):
        if self.no_dask:
            return "one after another (--no-dask)"
        if self.scheduler:
            return f"on the Dask cluster at {self.scheduler}"
        return f"on {self.workers} local Dask worker{'s' * (self.workers > 1)}"

    def run(self, tasks, summary=None) -> list:
        """Runs TASKS (the finished runs of the journal kept under --resume); their Results in
        task order. SUMMARY(task, result) -> a few words for the run's progress line."""
        keys = [t.key for t in tasks]
        if len(set(keys)) != len(keys):
            dup = next(k for k in keys if keys.count(k) > 1)
            raise ValueError(f"{self.name}: two tasks named {dup}")
        results = [None] * len(tasks)
        todo = []
        for i, t in enumerate(tasks):
            kept = self.done.get(tuple(t.key))
            if kept and kept[0] == t.record_text():
                results[i] = kept[1]
                self._write_outputs(t, kept[1])
            else:
                todo.append((i, t))
        n, k = len(tasks), len(tasks) - len(todo)
        if todo:
            self._say(f"{_runs(len(todo))} {self.where()}"
                      + (f"; {k} of {n} kept from {self.path}" if k else ""))
        t0 = time.time()
        finished = 0

        def on_signal(signum, frame):
            signal.signal(signal.SIGINT, signal.SIG_IGN)
            signal.signal(signal.SIGTERM, signal.SIG_IGN)
            raise Interrupted(signum)

        old = {s: signal.signal(s, on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
        runs = self._runs(todo)
        try:
            for i, data in runs:
                t = tasks[i]
                if t.ok is not None and data["rc"] not in t.ok and "unsupported" not in data:
                    raise _Failed(t, data)
                self._write_outputs(t, data)
                self.done[tuple(t.key)] = (t.record_text(), data)
                self._append({"key": list(t.key), "record": t.record_text(), "result": data})
                results[i] = data
                finished += 1
                self._new += 1
                if not self.quiet:
                    el = time.time() - t0
                    rate = finished / el * 60 if el > 0 else 0.0
                    left = (len(todo) - finished) * el / finished
                    words = summary(t, Result(data, t.report)) if summary else ""
                    print(f"[{k + finished}/{n}] {' '.join(map(str, t.key))}"
                          f"{' ' + words if words else ''} ({data['seconds']:.1f} s; "
                          f"{rate:.1f} runs/min; {_duration(left)} left)",
                          file=sys.stderr, flush=True)
                self._after_run()
        except Interrupted as e:
            runs.close()
            self.close()
            kept = sum(r is not None for r in results)
            more = len(self.done) - kept  # of the study's earlier run() calls
            print(f"{self.name}: interrupted; {kept} of {n} runs kept in {self.path}"
                  + (f" (and {_runs(more)} before them)" if more > 0 else "")
                  + "; --resume continues", file=sys.stderr, flush=True)
            raise SystemExit(128 + e.signum)
        except _Failed as e:
            runs.close()
            self.close()
            data = e.data
            err = data["stderr"].strip()
            kept = len(self.done)
            print(f"{self.name}: {' '.join(data.get('cmd') or map(str, e.task.cmd))} exited "
                  f"{data['rc']}:\n{err[-4000:]}\n{self.name}: stopped; "
                  + (f"{_runs(kept)} finished kept in {self.path}; --resume continues" if kept
                     else "no run had finished"), file=sys.stderr, flush=True)
            raise SystemExit(2 if data["rc"] == 2 else 1)
        except BaseException:
            runs.close()
            raise
        finally:
            for s, h in old.items():
                signal.signal(s, h)
        return [Result(d, t.report) for d, t in zip(results, tasks)]

    def _write_outputs(self, task, data):
        outs = [(dest, data["files"].get(name)) for name, dest in task.files.items() if dest]
        if task.stdout:
            outs.append((task.stdout, data["stdout"]))
        for dest, text in outs:
            if text is None:
                continue
            dest = Path(dest)
            dest.parent.mkdir(parents=True, exist_ok=True)
            tmp = dest.with_name(dest.name + ".tmp")
            tmp.write_text(text)
            os.replace(tmp, dest)

    def _after_run(self):
        stop = os.environ.get(STOP_ENV, "")
        after, _, how = stop.partition(":")
        if after and self._new == int(after):
            if how == "WAIT":  # for a signal from outside
                self._say("waiting for a signal")
                while True:
                    signal.pause()
            os.kill(os.getpid(), signal.SIGTERM if how == "TERM" else signal.SIGINT)

    def close(self):
        if getattr(self, "journal", None) and not self.journal.closed:
            self.journal.close()
        if self.client is not None:
            self.client.close()
            self.client = None
        if self.cluster is not None:
            self.cluster.close()
            self.cluster = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def main_errors(name, fn):
    """Runs FN(); a StudyError becomes `NAME: message` on stderr and exit code 2."""
    try:
        return fn()
    except StudyError as e:
        print(f"{name}: {e}", file=sys.stderr)
        return 2
