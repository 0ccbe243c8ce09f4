#!/usr/bin/env python3
"""The exactness check on every shared and own scene (docs/bvh.md, "Exactness check";
docs/results.md, "Reliability: exactness of the BVH walk"): `hrpp exactness` per scene, its JSON
reports and walk misses in OUT, and a summary table (OUT/summary.md, OUT/summary.json, and the
block `exactness` of --doc).

  make exactness [EXACTNESS_RAYS=10000000] [JOBS=2] [STUDY_OPTS=--resume]
  model/tools/exactness.py --hrpp build/hrpp --shared ../shared [--scenes bunny,sponza] [--no-own]
      [--min-rays N] [--workers 2 | --scheduler ADDRESS | --no-dask] [--resume]
      [--out out/exactness] [--doc docs/results.md] [--from-out]

Per scene: `hrpp exactness SCENE --min-rays N --json OUT/SCENE.json --misses
OUT/SCENE-walk-misses.txt`, plus `--replay model/test/exactness/SCENE.txt` when that file exists
(walk misses found before, kept as regression rays); its text report in OUT/SCENE.txt. Each scene
is a task of the study driver (pyhrpp/study.py: --workers N scenes at a time on a local Dask
cluster, --jobs the same option; --scheduler, --no-dask); its journal OUT/journal.jsonl lets
--resume continue an interrupted check. Exit 0 when every scene passes, 1 when one fails (walk
misses, or disagreements beyond ties and grazes), 2 on a tool error (the check stops there); 77
(ctest's skip code) with --require-shared when the shared scenes are absent.
"""
import argparse
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp import study  # noqa: E402
from pyhrpp.docs import update_blocks  # noqa: E402
from pyhrpp.files import write_atomic  # noqa: E402

KINDS = ["primary", "shadow", "ao", "ao-short", "reflection", "refraction", "diffuse"]
REPLAY_DIR = ROOT / "model" / "test" / "exactness"
SKIP = 77


def scenes_of(args):
    """[(label, path)]: the shared scenes (those of --scenes when given), then the own ones."""
    out = []
    wanted = set(args.scenes.split(",")) if args.scenes else None
    shared = pathlib.Path(args.shared) / "scenes" if args.shared else None
    if shared and shared.is_dir():
        out += [("shared", p) for p in sorted(shared.glob("*.glb"))
                if wanted is None or p.stem in wanted]
    if not args.no_own:
        out += [("own", p) for p in sorted((ROOT / "scenes").glob("*.glb"))
                if wanted is None or p.stem in wanted]
    return out


def names(where, path):
    """(file name, table label) of a scene."""
    return ((path.stem, path.stem) if where == "shared"
            else (f"own-{path.stem}", f"{path.stem} (own)"))


def task(args, where, path, out):
    """hrpp exactness on one scene: its report OUT/NAME.json, walk misses
    OUT/NAME-walk-misses.txt, text report OUT/NAME.txt; exit 1 (the check failed) is a finished
    run. record: the replayed walk misses, which --resume must see unchanged."""
    name, _ = names(where, path)
    cmd = [args.hrpp, "exactness", path, "--min-rays", args.min_rays, "--json", "{json}",
           "--misses", "{misses}"]
    replay = REPLAY_DIR / f"{path.stem}.txt"
    if replay.exists():
        cmd += ["--replay", replay]
    return study.Task(key=(name,), cmd=cmd, ok=(0, 1), stdout=out / f"{name}.txt",
                      files={"json": out / f"{name}.json",
                             "misses": out / f"{name}-walk-misses.txt"},
                      record=replay.read_text() if replay.exists() else "")


def seconds(t):
    return f"{t:.1f} s" if t < 10 else f"{t:.0f} s" if t < 600 else f"{t / 60:.0f} min"


def millions(n):
    return f"{n / 1e6:.1f}M" if n >= 100000 else f"{n:,}"


def table(results):
    """The summary table (Markdown) and its notes."""
    head = ("| scene | triangles | " + " | ".join(KINDS) +
            " | queries | disagreements | ours right / Embree right | ties / grazes / t rounding "
            "| walk misses (confirmed) | time |")
    rows = [head, "|" + "---|" * (len(KINDS) + 8)]
    none, notes = {}, []  # none: (kind, reason) -> scenes
    for label, rep in results:
        bk = rep["by_kind"]
        cells = []
        for k in KINDS:
            e = bk.get(k)
            if e is None:
                cells.append("not asked")
                continue
            cells.append(millions(e["rays"]) if e["rays"] else "0")
            note = e.get("note")
            if note and note.startswith("the scene has none: "):
                none.setdefault((k, note[len("the scene has none: "):]), []).append(label)
            elif note:
                notes.append(f"{label} {k}: {note}")
        c, a = rep["total"]["closest"], rep["total"]["any"]
        dis = c["disagreements"] + a["disagreements"]
        wrong = f"{c['ours_right'] + a['ours_right']} / {c['embree_right'] + a['embree_right']}"
        ties = (f"{c['ties'] + a['ties']:,} / {c['grazes'] + a['grazes']:,} / "
                f"{c['t_rounding'] + a['t_rounding']:,}")
        wm = c["walk_misses"] + a["walk_misses"]
        conf = c["walk_misses_confirmed"] + a["walk_misses_confirmed"]
        if rep.get("replayed"):
            notes.append(f"{label}: includes {rep['replayed']} replayed rays "
                         f"(model/test/exactness/)")
        rows.append(f"| {label} | {rep['triangles']:,} | " + " | ".join(cells) +
                    f" | {c['compared'] + a['compared']:,} | {dis:,} | {wrong} | {ties} | "
                    f"**{wm:,}** ({conf:,}) | {seconds(rep['seconds'])} |")
    notes = [f"{k}: 0 on {', '.join(scenes)} ({why})" for (k, why), scenes in none.items()] + notes
    if any(not rep["passed"] for _, rep in results):
        notes += [f"{label} fails: {rep['failure']}" for label, rep in results if not rep["passed"]]
    return "\n".join(rows), notes


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hrpp", default=str(ROOT / "build" / "hrpp"))
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"),
                    help="the shared folder ('' for none)")
    ap.add_argument("--scenes", help="comma-separated scene stems (default: all)")
    ap.add_argument("--no-own", action="store_true", help="leave out the own scenes (scenes/)")
    ap.add_argument("--require-shared", action="store_true",
                    help=f"exit {SKIP} (skipped) when the shared scenes asked for are absent")
    ap.add_argument("--min-rays", type=int, default=10_000_000)
    ap.add_argument("--out", default=str(ROOT / "out" / "exactness"))
    ap.add_argument("--doc", default="",
                    help="a Markdown file whose block `exactness` is rewritten ('': none)")
    ap.add_argument("--from-out", action="store_true",
                    help="run nothing: the summary and the block from the reports in --out")
    study.add_arguments(ap, "scenes")
    args = ap.parse_args()
    if not pathlib.Path(args.hrpp).exists():
        raise SystemExit(f"exactness: {args.hrpp} not found (make build)")
    scenes = scenes_of(args)
    if args.require_shared and not any(w == "shared" for w, _ in scenes):
        print(f"exactness: skipped: no shared scene ({args.scenes or 'any'}) in "
              f"{args.shared or '(none)'}/scenes", flush=True)
        return SKIP
    if not scenes:
        raise SystemExit("exactness: no scene")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.from_out:
        runs = []
        for where, path in scenes:
            name, label = names(where, path)
            js = out / f"{name}.json"
            if js.exists():
                rep = json.loads(js.read_text())
                runs.append((label, rep, 0 if rep["passed"] else 1))
        if not runs:
            raise SystemExit(f"exactness: no report in {out}")
        return summarize(args, out, runs)

    def check():
        tasks = [task(args, where, path, out) for where, path in scenes]
        identity = {"hrpp": study.tool_version(args.hrpp), "min_rays": args.min_rays}
        with study.Study("exactness", out / "journal.jsonl", identity, args) as st:
            try:
                res = st.run(tasks, summary=lambda t, r: status(r))
            except SystemExit as e:
                # A run that exits neither 0 nor 1 is a tool error: exit 2 (the study says 1
                # unless the tool said bad input), not the 1 of a failed check.
                raise SystemExit(2 if e.code == 1 else e.code)
            runs = []
            for t, r, (where, path) in zip(tasks, res, scenes):
                if r.report is None:
                    print(f"exactness: {' '.join(map(str, t.cmd))} wrote no report (see "
                          f"{t.stdout})", file=sys.stderr)
                    return 2
                runs.append((names(where, path)[1], r.report, r.rc))
            worst = summarize(args, out, runs)
            st.complete()
        return worst
    return study.main_errors("exactness", check)


def status(r):
    """A finished run in a few words: its rays and PASS or FAIL."""
    rep = r.report
    if rep is None:
        return "no report"
    return (f"{rep['total']['closest']['compared']:,} rays: "
            + ("PASS" if r.rc == 0 else "FAIL: " + rep.get("failure", "")))


def summarize(args, out, runs):
    """Writes the summary (OUT/summary.md, OUT/summary.json, the block of --doc) of RUNS [(label,
    report, exit code)] and prints it; the worst exit code."""
    results = [(label, rep) for label, rep, _ in runs]
    worst = max(rc for _, _, rc in runs)
    body, notes = table(results)
    min_rays = results[0][1]["min_rays"] if results else args.min_rays
    cmd = ("make exactness" if min_rays == 10_000_000
           else f"make exactness EXACTNESS_RAYS={min_rays}")
    text = (f"Made by `{cmd}` (at least {min_rays:,} rays of every kind per scene, each traced "
            f"as a closest-hit and an any-hit query; time: the check's own, without loading the "
            f"scene and building the BVH).\n\n{body}\n")
    if notes:
        text += "\n" + "\n".join(f"- {n}" for n in notes) + "\n"
    write_atomic(out / "summary.md", text)
    write_atomic(out / "summary.json", json.dumps(
        {"min_rays": min_rays,
         "scenes": {label: {"passed": rep["passed"], "failure": rep.get("failure"),
                            "total": rep["total"], "seconds": rep["seconds"],
                            "walk_misses": [m["line"] for m in rep["walk_misses"]]}
                    for label, rep in results}}, indent=2) + "\n")
    if args.doc:
        update_blocks(args.doc, {"exactness": text})
    print(text)
    return worst


if __name__ == "__main__":
    sys.exit(main())
