"""What the studies of `hrpp simulate` share (sim_results.py, design_study.py, port_rate.py): a
run as a task of the study driver (pyhrpp/study.py), the study and its journal, the reports, and
the tables' helpers (scenes, labels, number formats, geometric means).

A run's command names its report `{json}`; the driver writes it to the run's OUT/GPU/NAME.json.
A run's record (what --resume compares) is its command and the contents of the --preset and --gpu
files it names, if any: a design's options live in a file whose name does not change with them. A
configuration whose node ids cannot name the scene's BVH is a finished run, its report
{"unsupported": the tool's last line of error}.
"""
import math
import os
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp import study  # noqa: E402

UNSUPPORTED = "node ids name at most"  # hrpp's error when a configuration cannot name the BVH
NO_RAYS = "no rays of the kinds"  # hrpp simulate's error when the workload has none of --kinds


def task(key, cmd, path, no_rays=False):
    """The run CMD (its report `{json}`, written to PATH) as a study task named KEY. no_rays: a
    run with no rays of its kinds is a finished run too (its report None; see reports)."""
    cmd = [str(c) for c in cmd]
    record = "".join(f"{flag[2:]} file {arg}: {pathlib.Path(arg).read_text()}"
                     for flag, arg in zip(cmd, cmd[1:])
                     if flag in ("--preset", "--gpu") and os.path.isfile(arg))
    return study.Task(key=tuple(map(str, key)), cmd=cmd, files={"json": path},
                      unsupported=(UNSUPPORTED, NO_RAYS) if no_rays else UNSUPPORTED,
                      record=record)


def open_study(name, args, **identity):
    """The study NAME, its journal OUT/journal.jsonl (--out); its identity the version of --hrpp
    and IDENTITY (what every run of the journal must share)."""
    return study.Study(name, pathlib.Path(args.out) / "journal.jsonl",
                       {"hrpp": study.tool_version(args.hrpp), **identity}, args)


def progress(t, r):
    """A run's words in its progress line: its speed-up, or why it has none."""
    if r.unsupported:
        return r.unsupported.replace("hrpp simulate: ", "")
    return f"{r.report['speedup']:.3f}x" if r.report and "speedup" in r.report else ""


def reports(st, tasks):
    """Runs TASKS on the study ST: {key: report} in task order; a configuration that cannot run
    gives {"unsupported": line}, a run with no rays of its kinds (task(no_rays=True)) None."""
    out = {}
    for t, r in zip(tasks, st.run(tasks, summary=progress)):
        if r.unsupported and NO_RAYS in r.unsupported:
            out[t.key] = None
        elif r.unsupported:
            out[t.key] = {"unsupported": r.unsupported}
        else:
            out[t.key] = r.report
    return out


def made_by(argv=None):
    """The command line ARGV (sys.argv) without the driver's options (--workers, --jobs,
    --scheduler, --no-dask, --resume, --resume-any-build): where the runs went does not change
    the tables."""
    argv, out = list(sys.argv if argv is None else argv), []
    skip = False
    for a in argv:
        if skip:
            skip = False
        elif a in ("--workers", "--jobs", "--scheduler"):
            skip = True
        elif a not in ("--no-dask", "--resume", "--resume-any-build") and not a.startswith(
                ("--workers=", "--jobs=", "--scheduler=")):
            out.append(a)
    return " ".join(out)


def scenes_of(shared, names, tool="sim_results"):
    """[(where, path)]: the shared scenes (SHARED/scenes/*.glb; SHARED '': none), then the own
    ones (scenes/*.glb); NAMES: comma-separated stems or where:stem (None: all)."""
    own = sorted((ROOT / "scenes").glob("*.glb"))
    sh = sorted(pathlib.Path(shared, "scenes").glob("*.glb")) if shared else []
    if shared and not sh:
        print(f"{tool}: no scenes in {shared}/scenes; own scenes only", file=sys.stderr)
    out = [("shared", p) for p in sh] + [("own", p) for p in own]
    if names:
        want = set(names.split(","))
        out = [(w, p) for w, p in out if p.stem in want or f"{w}:{p.stem}" in want]
        missing = want - {p.stem for _, p in out} - {f"{w}:{p.stem}" for w, p in out}
        if missing:
            raise SystemExit(f"{tool}: unknown scenes {sorted(missing)}")
    return out


def label(where, path):
    return path.stem if where == "shared" else f"{path.stem} (own)"


def geomean(xs):
    xs = [x for x in xs if x and x > 0]
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else float("nan")


def fx(x):
    return "" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.3f}"


def pct(x):
    return "" if x is None else f"{100 * x:.1f}%"
