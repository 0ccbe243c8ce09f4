#!/usr/bin/env python3
"""The exactness check on every shared and own scene (docs/bvh.md, "Exactness check";
docs/results.md, "Reliability: exactness of the BVH walk"): `hrpp exactness` per scene, its JSON
reports and walk misses in OUT, and a summary table (OUT/summary.md, OUT/summary.json, and the
block `exactness` of --doc).

  make exactness [EXACTNESS_RAYS=10000000] [JOBS=2]
  model/tools/exactness.py --hrpp build/hrpp --shared ../shared [--scenes bunny,sponza] [--no-own]
      [--min-rays N] [--jobs 2] [--out out/exactness] [--doc docs/results.md]

Per scene: `hrpp exactness SCENE --min-rays N --json OUT/SCENE.json --misses
OUT/SCENE-walk-misses.txt`, plus `--replay model/test/exactness/SCENE.txt` when that file exists
(walk misses found before, kept as regression rays). Exit 0 when every scene passes, 1 when one
fails (walk misses, or disagreements beyond ties and grazes), 2 on a tool error; 77 (ctest's
skip code) with --require-shared when the shared scenes are absent.
"""
import argparse
import json
import os
import pathlib
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
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


def run_one(args, where, path, out):
    """Runs hrpp exactness on one scene; returns (report or None, exit code, seconds)."""
    name = path.stem if where == "shared" else f"own-{path.stem}"
    js = out / f"{name}.json"
    cmd = [args.hrpp, "exactness", str(path), "--min-rays", str(args.min_rays), "--json", str(js),
           "--misses", str(out / f"{name}-walk-misses.txt")]
    replay = REPLAY_DIR / f"{path.stem}.txt"
    if replay.exists():
        cmd += ["--replay", str(replay)]
    t0 = time.time()
    with open(out / f"{name}.txt", "w") as log:
        # Progress and walk misses as found go to our stderr; the report to OUT/NAME.txt.
        rc = subprocess.run(cmd, stdout=log).returncode
    secs = time.time() - t0
    if rc not in (0, 1) or not js.exists():
        print(f"exactness: {' '.join(cmd)} exited {rc} (see {out / (name + '.txt')})",
              file=sys.stderr)
        return None, 2, secs
    rep = json.loads(js.read_text())
    return rep, rc, secs


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
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--out", default=str(ROOT / "out" / "exactness"))
    ap.add_argument("--doc", default="",
                    help="a Markdown file whose block `exactness` is rewritten ('': none)")
    ap.add_argument("--from-out", action="store_true",
                    help="run nothing: the summary and the block from the reports in --out")
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
    def one(scene):
        where, path = scene
        rep, rc, secs = run_one(args, where, path, out)
        label = path.stem if where == "shared" else f"{path.stem} (own)"
        if rep is not None:
            status = "PASS" if rc == 0 else "FAIL: " + rep.get("failure", "")
            print(f"exactness {label}: {rep['total']['closest']['compared']:,} rays, "
                  f"{secs:.1f} s: {status}", flush=True)
        return label, rep, rc

    if args.from_out:
        runs = []
        for where, path in scenes:
            js = out / f"{path.stem if where == 'shared' else 'own-' + path.stem}.json"
            if js.exists():
                rep = json.loads(js.read_text())
                runs.append((path.stem if where == "shared" else f"{path.stem} (own)", rep,
                             0 if rep["passed"] else 1))
        if not runs:
            raise SystemExit(f"exactness: no report in {out}")
    else:
        with ThreadPoolExecutor(max(1, args.jobs)) as pool:
            runs = list(pool.map(one, scenes))  # in the scenes' order
    results = [(label, rep) for label, rep, _ in runs if rep is not None]
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
