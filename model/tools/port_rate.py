#!/usr/bin/env python3
"""How many lookups and updates per cycle an RT unit needs from its predictor (issue 18;
docs/results.md, "Lookups per cycle the RT units need").

  make port-rate [SIM_RES=256x256] [JOBS=2]
  model/tools/port_rate.py --hrpp build/hrpp --shared ../shared [--jobs 2] [--res 256x256]
      [--gpu mobile,desktop] [--rates 1,2,4,32] [--doc docs/results.md]

`hrpp simulate` with the golden predictor holding the RTL `primary` configuration's hash and
table (rtl-primary with `--hash improved` given, so the golden model behind the RTL's latencies:
prediction 10 cycles, decision 2), unlimited ray ids (`--credits 0`: the port rate alone limits
it), and N lookups and N updates per cycle (`--lookups-per-cycle N --updates-per-cycle N`), for N
in --rates, on every shared scene x ray kind (primary; shadow where the scene has lights; AO as
MICRO 2021 runs it: cosine hemisphere, unbounded) x GPU. A unit needs N lookups per cycle when N
gives the speed-up of the largest rate within 1% on every scene (the geometric mean is reported
too). Writes OUT/GPU/SCENE-KIND-N.json and the block port-rate of --doc.

The RTL as built (--built, block port-rate-built): the same scenes, kinds and GPUs with the RTL
configurations' cycle models at their ports (`--preset rtl-NAME`): `primary` (one lane, 64 ray
ids), `primary_x2` and `primary_x4` (hrpp_lanes: 2 and 4 lookups and updates per cycle, 64 ids
per lane) and `mobile` (one lane, 1,024 ids). Writes OUT/GPU/SCENE-KIND-rtl-NAME.json. A scene a
configuration cannot run (its node ids cannot name the BVH) is left out of that configuration's
mean and named. --resume keeps the reports already in OUT whose record (PATH.cmd, the command
line, written with the report) names the same command (a report without a record is kept).
"""
import argparse
import json
import math
import pathlib
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor, as_completed

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
sys.path.insert(0, str(ROOT / "model" / "tools"))
from pyhrpp.docs import update_blocks  # noqa: E402
from pyhrpp.files import write_atomic  # noqa: E402
from sim_results import RESUME_HELP, record_matches, run_record  # noqa: E402

KINDS = {
    "primary": ["--kinds", "primary"],
    "shadow": ["--kinds", "shadow"],
    "ao": ["--kinds", "ao", "--effects", "ao", "--ao-distance", "inf"],
}
TOLERANCE = 0.01  # a rate is enough when its speed-up is within 1% of the largest rate's


def run(task):
    key, cmd, path = task
    t0 = time.time()
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    if p.returncode != 0:
        if "no rays of the kinds" in p.stderr:  # e.g. shadow rays of a scene without lights
            return key, None, time.time() - t0
        if "node ids name at most" in p.stderr:  # the configuration cannot name the BVH's nodes
            data = {"unsupported": p.stderr.strip().splitlines()[-1]}
            path.write_text(json.dumps(data))
            write_atomic(path.with_suffix(".cmd"), run_record(cmd))
            return key, data, time.time() - t0
        raise SystemExit(f"port_rate: {' '.join(map(str, cmd))} exited {p.returncode}:\n"
                         f"{p.stderr[-2000:]}")
    write_atomic(path.with_suffix(".cmd"), run_record(cmd))
    return key, json.loads(path.read_text()), time.time() - t0


def kept(task, report):
    """--resume: a report is kept when it exists and its record names the same command (or it has
    no record: made before records were kept)."""
    _, cmd, path = task
    return report is not None and record_matches(path, cmd)


def geomean(xs):
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else float("nan")


def table(results, gpus, scenes, rates):
    lines = [
        "Regenerate with `make port-rate`. Speed-up over no predictor (geometric mean over the "
        "scenes), with the golden predictor holding the RTL `primary` configuration's hash and "
        "table, the RTL's latencies and unlimited ray ids, at N lookups and N updates per cycle; "
        "'needs' is the smallest N within 1% of the largest rate's speed-up on every scene; "
        "'worst loss' the largest slowdown of N = 1 against the largest rate on one scene; 'wait' "
        "the mean cycles a ray waits for the predictor's port at N = 1.",
        "",
        "| GPU | rays | " + " | ".join(f"N = {n}" for n in rates) +
        " | needs | worst loss at N = 1 | wait at N = 1 |",
        "|---|---|" + "---|" * len(rates) + "---|---|---|",
    ]
    for gpu in gpus:
        for kind in KINDS:
            per_rate = {n: [] for n in rates}
            need, worst, wait, rays = 1, (0.0, ""), 0, 0
            for s in scenes:
                runs = {n: results.get((gpu, s, kind, n)) for n in rates}
                if any(r is None for r in runs.values()):
                    continue
                best = runs[rates[-1]]["speedup"]
                for n in rates:
                    per_rate[n].append(runs[n]["speedup"])
                enough = next(n for n in rates if runs[n]["speedup"] >= best * (1 - TOLERANCE))
                need = max(need, enough)
                loss = 1 - runs[rates[0]]["speedup"] / best
                worst = max(worst, (loss, s))
                p = runs[rates[0]]["predictor"]
                wait += p.get("entry_wait_cycles", 0)
                rays += p.get("lookups", 0)
            if not per_rate[rates[0]]:
                continue
            cells = " | ".join(f"{geomean(per_rate[n]):.3f}x" for n in rates)
            lines.append(f"| {gpu} | {kind} | {cells} | {need} | {100 * worst[0]:.1f}% "
                         f"({worst[1]}) | {wait / max(1, rays):.1f} cycles |")
    return "\n".join(lines)


def built_table(results, gpus, scenes, presets):
    lines = [
        "Regenerate with `make port-rate`. Speed-up over no predictor (geometric mean over the "
        "scenes) with the RTL configurations as built: each one's cycle model at its ports in "
        "every RT unit (`hrpp simulate --preset rtl-NAME`). `primary`: one lookup and one update "
        "per cycle, 64 ray ids; `primary_x2`, `primary_x4`: 2 and 4 lanes (`hrpp_lanes`), 64 ids "
        "per lane; `mobile`: one lane, 1,024 ids. 'wait': the mean cycles a ray waits to enter.",
        "",
        "| GPU | rays | " + " | ".join(f"`{p.removeprefix('rtl-')}`" for p in presets) +
        " | wait: " + " / ".join(f"`{p.removeprefix('rtl-')}`" for p in presets) + " |",
        "|---|---|" + "---|" * len(presets) + "---|",
    ]
    left_out = {}
    for gpu in gpus:
        for kind in KINDS:
            cells, waits = [], []
            for p in presets:
                sp, wait, rays = [], 0, 0
                for s in scenes:
                    r = results.get((gpu, s, kind, p))
                    if r is None:
                        continue
                    if "unsupported" in r:
                        left_out.setdefault(p, set()).add(s)
                        continue
                    sp.append(r["speedup"])
                    wait += r["predictor"].get("entry_wait_cycles", 0)
                    rays += r["predictor"].get("lookups", 0)
                cells.append(f"{geomean(sp):.3f}x" if sp else "-")
                waits.append(f"{wait / max(1, rays):.0f}" if sp else "-")
            lines.append(f"| {gpu} | {kind} | {' | '.join(cells)} | {' / '.join(waits)} |")
    if left_out:
        lines += ["", "Left out of a configuration's means (its node ids cannot name the BVH): " +
                  "; ".join(f"`{p.removeprefix('rtl-')}`: {', '.join(sorted(s))}"
                            for p, s in left_out.items()) + "."]
    return "\n".join(lines)


def load(out, gpus, scenes, rates):
    """The reports of an earlier run in OUT."""
    r = {}
    for gpu in gpus:
        for s in scenes:
            for kind in KINDS:
                for n in rates:
                    p = out / gpu / f"{s}-{kind}-{n}.json"
                    r[(gpu, s, kind, n)] = json.loads(p.read_text()) if p.exists() else None
    return r


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--hrpp", default=str(ROOT / "build" / "hrpp"))
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"))
    ap.add_argument("--res", default="256x256")
    ap.add_argument("--gpu", default="mobile,desktop")
    ap.add_argument("--rates", default="1,2,4,32")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default=str(ROOT / "out" / "port_rate"))
    ap.add_argument("--doc", default=str(ROOT / "docs" / "results.md"))
    ap.add_argument("--built", default="rtl-primary,rtl-primary_x2,rtl-primary_x4,rtl-mobile",
                    help="RTL presets run through their cycle models (block port-rate-built); "
                         "'' for none")
    ap.add_argument("--resume", action="store_true", help=RESUME_HELP)
    ap.add_argument("--tables-only", action="store_true",
                    help="rewrite the table from the reports already in --out; run nothing")
    args = ap.parse_args()
    scenes = sorted(pathlib.Path(args.shared, "scenes").glob("*.glb"))
    if not scenes:
        sys.exit(f"port_rate: no scenes in {args.shared}/scenes (the shared folder is needed)")
    rates = sorted(int(n) for n in args.rates.split(","))
    built = [p for p in args.built.split(",") if p]
    gpus = args.gpu.split(",")
    out = pathlib.Path(args.out)
    tasks = []
    for gpu in gpus:
        (out / gpu).mkdir(parents=True, exist_ok=True)
        for s in scenes:
            for kind, kopts in KINDS.items():
                for n in rates:
                    path = out / gpu / f"{s.stem}-{kind}-{n}.json"
                    cmd = [args.hrpp, "simulate", s, "--res", args.res, "--gpu", gpu,
                           "--preset", "rtl-primary", "--hash", "improved", "--credits", "0",
                           "--lookups-per-cycle", n, "--updates-per-cycle", n, "--no-oracle",
                           "--no-per-kind", "--json", path] + kopts
                    tasks.append(((gpu, s.stem, kind, n), cmd, path))
                for p in built:
                    path = out / gpu / f"{s.stem}-{kind}-{p}.json"
                    cmd = [args.hrpp, "simulate", s, "--res", args.res, "--gpu", gpu,
                           "--preset", p, "--no-oracle", "--no-per-kind", "--json", path] + kopts
                    tasks.append(((gpu, s.stem, kind, p), cmd, path))
    results, t0 = {}, time.time()
    if args.tables_only or args.resume:
        results = load(out, gpus, [s.stem for s in scenes], rates + built)
        tasks = [] if args.tables_only else [t for t in tasks if not kept(t, results.get(t[0]))]
    with ThreadPoolExecutor(max_workers=args.jobs) as ex:
        for i, f in enumerate(as_completed([ex.submit(run, t) for t in tasks]), 1):
            key, data, secs = f.result()
            results[key] = data
            sp = (f"{data['speedup']:.3f}x" if data and "speedup" in data
                  else "cannot run" if data else "no rays")
            print(f"port_rate: [{i}/{len(tasks)}] {' '.join(map(str, key))}: {sp} ({secs:.1f} s; "
                  f"total {time.time() - t0:.0f} s)", flush=True)
    block = table(results, gpus, [s.stem for s in scenes], rates)
    print(block)
    blocks = {"port-rate": block}
    if built:
        blocks["port-rate-built"] = built_table(results, gpus, [s.stem for s in scenes], built)
        print(blocks["port-rate-built"])
    if args.doc:
        update_blocks(pathlib.Path(args.doc), blocks)
        print(f"port_rate: updated {args.doc}")


if __name__ == "__main__":
    main()
