#!/usr/bin/env python3
"""How many lookups and updates per cycle an RT unit needs from its predictor (issue 18;
docs/results.md, "Lookups per cycle the RT units need").

  make port-rate [SIM_RES=256x256] [JOBS=2] [STUDY_OPTS=--resume]
  model/tools/port_rate.py --hrpp build/hrpp --shared ../shared [--res 256x256]
      [--gpu mobile,desktop] [--rates 1,2,4,32] [--doc docs/results.md] [--tables-only]
      [--workers 2 | --scheduler ADDRESS | --no-dask] [--resume]

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
mean and named (its report: {"unsupported": why}).

The runs go through the study driver (pyhrpp/study.py, docs/studies.md): --workers, --scheduler
or --no-dask; a progress line per run; the journal OUT/journal.jsonl, whose finished runs
--resume keeps (another hrpp version or --res is refused). --tables-only rewrites the blocks from
the reports in OUT and runs nothing.
"""
import argparse
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
sys.path.insert(0, str(ROOT / "model" / "tools"))
from pyhrpp import study  # noqa: E402
from pyhrpp.docs import update_blocks  # noqa: E402
from pyhrpp.files import write_atomic  # noqa: E402
from sim_study import geomean, open_study, reports, task  # noqa: E402

KINDS = {
    "primary": ["--kinds", "primary"],
    "shadow": ["--kinds", "shadow"],
    "ao": ["--kinds", "ao", "--effects", "ao", "--ao-distance", "inf"],
}
TOLERANCE = 0.01  # a rate is enough when its speed-up is within 1% of the largest rate's


def tasks_for(args, scenes, gpus, rates, built, out):
    """Every run: per GPU, scene and ray kind, each rate and each RTL preset of --built. A run
    with no rays of its kind (shadow rays of a scene without lights) is finished, without a
    report (no_rays)."""
    tasks = []
    for gpu in gpus:
        for s in scenes:
            for kind, kopts in KINDS.items():
                for n in rates:
                    cmd = [args.hrpp, "simulate", s, "--res", args.res, "--gpu", gpu,
                           "--preset", "rtl-primary", "--hash", "improved", "--credits", "0",
                           "--lookups-per-cycle", n, "--updates-per-cycle", n, "--no-oracle",
                           "--no-per-kind", "--json", "{json}"] + kopts
                    tasks.append(task((gpu, s.stem, kind, n), cmd,
                                      out / gpu / f"{s.stem}-{kind}-{n}.json", no_rays=True))
                for p in built:
                    cmd = [args.hrpp, "simulate", s, "--res", args.res, "--gpu", gpu,
                           "--preset", p, "--no-oracle", "--no-per-kind", "--json",
                           "{json}"] + kopts
                    tasks.append(task((gpu, s.stem, kind, p), cmd,
                                      out / gpu / f"{s.stem}-{kind}-{p}.json", no_rays=True))
    return tasks


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
                runs = {n: results.get((gpu, s, kind, str(n))) for n in rates}
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
                    r[(gpu, s, kind, str(n))] = (json.loads(p.read_text()) if p.exists()
                                                 else None)
    return r


def write_tables(args, results, gpus, stems, rates, built):
    """The blocks port-rate and port-rate-built, on stdout and in --doc."""
    block = table(results, gpus, stems, rates)
    print(block)
    blocks = {"port-rate": block}
    if built:
        blocks["port-rate-built"] = built_table(results, gpus, stems, built)
        print(blocks["port-rate-built"])
    if args.doc:
        update_blocks(pathlib.Path(args.doc), blocks)
        print(f"port_rate: updated {args.doc}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--hrpp", default=str(ROOT / "build" / "hrpp"))
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"))
    ap.add_argument("--res", default="256x256")
    ap.add_argument("--gpu", default="mobile,desktop")
    ap.add_argument("--rates", default="1,2,4,32")
    ap.add_argument("--out", default=str(ROOT / "out" / "port_rate"))
    ap.add_argument("--doc", default=str(ROOT / "docs" / "results.md"))
    ap.add_argument("--built", default="rtl-primary,rtl-primary_x2,rtl-primary_x4,rtl-mobile",
                    help="RTL presets run through their cycle models (block port-rate-built); "
                         "'' for none")
    ap.add_argument("--tables-only", action="store_true",
                    help="rewrite the table from the reports already in --out; run nothing")
    study.add_arguments(ap)
    args = ap.parse_args()
    scenes = sorted(pathlib.Path(args.shared, "scenes").glob("*.glb"))
    if not scenes:
        sys.exit(f"port_rate: no scenes in {args.shared}/scenes (the shared folder is needed)")
    rates = sorted(int(n) for n in args.rates.split(","))
    built = [p for p in args.built.split(",") if p]
    gpus = args.gpu.split(",")
    out = pathlib.Path(args.out)
    stems = [s.stem for s in scenes]
    if args.tables_only:
        write_tables(args, load(out, gpus, stems, rates + built), gpus, stems, rates, built)
        return
    tasks = tasks_for(args, scenes, gpus, rates, built, out)
    with open_study("port_rate", args, res=args.res) as st:
        results = reports(st, tasks)
        for t in tasks:  # a configuration that cannot run: a report that says why
            if results[t.key] and "unsupported" in results[t.key]:
                t.files["json"].parent.mkdir(parents=True, exist_ok=True)
                write_atomic(t.files["json"], json.dumps(results[t.key]))
        write_tables(args, results, gpus, stems, rates, built)
        st.complete()


if __name__ == "__main__":
    sys.exit(study.main_errors("port_rate", main))
