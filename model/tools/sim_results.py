#!/usr/bin/env python3
"""Time on RT units (docs/results.md, "Time on RT units"): `hrpp simulate` on every shared and own
scene x ray kind x preset x GPU configuration, and the tables of docs/results.md made from them.

  make sim-results [SIM_RES=256x256] [JOBS=2] [STUDY_OPTS=--resume]
  model/tools/sim_results.py --hrpp build/hrpp --shared ../shared [--res 256x256]
      [--gpu mobile,desktop] [--scenes bunny,sponza] [--doc docs/results.md]
      [--workers 2 | --scheduler ADDRESS | --no-dask] [--resume]

Ray kinds, each simulated alone (`--kinds`, an empty table per run): primary; shadow (scenes
with lights); ao: MICRO 2021's ambient occlusion (cosine hemisphere, unbounded, 1 spp); ao-short:
the project's AO (5% of the scene diagonal). Presets: study2019, micro21, rtl-primary, rtl-mobile
(1,024 ray ids), rtl-default (issue 17's winner: any-hit rays only, the confidence bit); every
`hrpp simulate` run also simulates `none` (the baseline) and the first of a group the `oracle`.
AO runs of micro21 and the RTL presets add `--repack`. Per scene on `mobile`: one mixed run of
all kinds with rtl-primary beside `hrpp predict` on the same rays (the cost model's figure).

The runs go through the study driver (pyhrpp/study.py, docs/studies.md): --workers, --scheduler
or --no-dask; a progress line per run; the journal OUT/journal.jsonl, whose finished runs
--resume keeps (another hrpp version or --res is refused). Writes each run's report
OUT/GPU/SCENE-KIND-PRESET.json, OUT/summary.json and the blocks sim-mobile, sim-desktop,
sim-disagree and sim-repack of --doc.
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
from sim_study import (fx, geomean, label, made_by, open_study, pct, reports,  # noqa: E402
                       scenes_of, task)

KINDS = {
    "primary": ["--kinds", "primary"],
    "shadow": ["--kinds", "shadow"],
    "ao": ["--kinds", "ao", "--ao-distance", "inf"],
    "ao-short": ["--kinds", "ao"],
}
KIND_TITLES = {
    "primary": "primary rays",
    "shadow": "shadow rays",
    "ao": "ambient occlusion as MICRO 2021 (cosine hemisphere, unbounded length, 1 spp)",
    "ao-short": "short ambient occlusion (5% of the scene diagonal)",
}
PRESETS = ["study2019", "micro21", "rtl-primary", "rtl-mobile", "rtl-default"]
RTL_PRESETS = [p for p in PRESETS if p.startswith("rtl-")]  # the RTL's cycle model: ray ids
REPACK = ["micro21"] + RTL_PRESETS  # AO runs with --repack too
MICRO21_AO_GAIN = 0.26  # MICRO 2021's geometric-mean AO speed-up (Liu et al., abstract)


def tasks_for(args, scenes, out):
    """Every run, in the order the tables read them."""
    tasks = []
    for gpu in args.gpu.split(","):
        for where, scene in scenes:
            for kind, kopts in KINDS.items():
                for i, preset in enumerate(PRESETS):
                    path = out / gpu / f"{where}-{scene.stem}-{kind}-{preset}.json"
                    cmd = [args.hrpp, "simulate", str(scene), "--res", args.res, "--gpu", gpu,
                           "--preset", preset, "--json", "{json}"] + kopts
                    if i > 0:
                        cmd.append("--no-oracle")  # the group's first run has it
                    if kind in ("ao", "ao-short") and preset in REPACK:
                        cmd.append("--repack")
                    tasks.append(task((gpu, where, scene.stem, kind, preset), cmd, path))
            if gpu == "mobile":  # the cost model beside the simulator, all kinds mixed
                path = out / gpu / f"{where}-{scene.stem}-mixed-rtl-primary.json"
                cmd = [args.hrpp, "simulate", str(scene), "--res", args.res, "--gpu", gpu,
                       "--preset", "rtl-primary", "--no-per-kind", "--no-oracle", "--json",
                       "{json}"]
                tasks.append(task((gpu, where, scene.stem, "mixed", "rtl-primary"), cmd, path))
                path = out / gpu / f"{where}-{scene.stem}-mixed-predict.json"
                cmd = [args.hrpp, "predict", str(scene), "--res", args.res, "--preset",
                       "rtl-primary", "--timing", "cost-model", "--json", "{json}"]
                tasks.append(task((gpu, where, scene.stem, "mixed", "predict"), cmd, path))
    return tasks


def kind_table(res, gpu, scenes, kind):
    """One ray kind on one GPU: per scene the speed-up of each preset and the oracle."""
    rows = ["| scene | rays | cycles, none | " + " | ".join(PRESETS) + " | oracle | "
            "gain as % of the oracle's: " + " / ".join(PRESETS) + " | stall cycles: "
            + " / ".join(RTL_PRESETS) + " |",
            "| --- | ---: | ---: | " + "---: | " * (len(PRESETS) + 3)]
    rows[1] = rows[1].rstrip()
    cols = {p: [] for p in PRESETS + ["oracle"]}
    notes = set()
    for where, scene in scenes:
        runs = {p: res.get((gpu, where, scene.stem, kind, p)) for p in PRESETS}
        first = runs[PRESETS[0]]
        if not first or first["rays"] == 0:
            continue
        sp = {p: (r.get("speedup") if r else None) for p, r in runs.items()}
        sp["oracle"] = first["oracle"]["speedup"] if "oracle" in first else None
        for p, v in sp.items():
            cols[p].append(v)
        for p in RTL_PRESETS:
            if runs[p] and "unsupported" in runs[p]:
                notes.add(f"{p}: {label(where, scene)}: "
                          f"{runs[p]['unsupported'].replace('hrpp simulate: ', '')}")
        # Each preset's gain (speed-up - 1) as a fraction of the oracle's, when the oracle gains.
        fracs = " / ".join(
            pct((sp[p] - 1) / (sp["oracle"] - 1)) if sp[p] and sp["oracle"] and sp["oracle"] > 1
            else "-" for p in PRESETS)
        stall = " / ".join(
            pct(r["predictor"]["stall_cycles"] / max(1, r["cycles"] * r["units"]))
            if r and "unsupported" not in r else "-" for r in (runs[p] for p in RTL_PRESETS))
        rows.append(f"| {label(where, scene)} | {first['rays']:,} | {first['baseline_cycles']:,} | "
                    + " | ".join(fx(sp[p]) for p in PRESETS + ["oracle"])
                    + f" | {fracs} | {stall} |")
    g = {p: geomean(v) for p, v in cols.items()}
    rows.append("| **geometric mean** | | | " + " | ".join(f"**{fx(g[p])}**" for p in PRESETS
                                                         + ["oracle"]) + " | | |")
    for n in sorted(notes):
        p, n = n.split(": ", 1)
        rows.append(f"\nNot simulated with {p}: {n}; its geometric mean leaves the scene out.")
    return "\n".join(rows), g


def gpu_block(res, gpu, scenes, args):
    parts = [f"GPU configuration `{gpu}` (model/gpu/{gpu}.json), {args.res}, 1 spp; speed-up = "
             "cycles with no predictor / cycles with the preset, each ray kind simulated alone "
             "(an empty table at the start). Stall cycles: unit cycles in which a ray waited to "
             "enter the RTL predictor and none was taken (its ray ids all in use: 64 in "
             "rtl-primary, 1,024 in rtl-mobile and rtl-default; or its input pipeline full)."]
    means = {}
    for kind in KINDS:
        table, g = kind_table(res, gpu, scenes, kind)
        means[kind] = g
        parts.append(f"**{KIND_TITLES[kind]}**\n\n{table}")
    ao = means["ao"]
    line = ("AO as MICRO 2021, geometric-mean gain (speed-up - 1): "
            + ", ".join(f"{p} {100 * (ao[p] - 1):+.1f}%" for p in PRESETS + ["oracle"])
            + f"; MICRO 2021 published +{100 * MICRO21_AO_GAIN:.0f}% for its predictor on its "
              "mobile configuration and scenes.")
    parts.append(line)
    return "\n\n".join(parts), means


def disagree_block(res, scenes):
    rows = ["| scene | cost model: cycles saved | simulated (mobile): cycles saved | "
            "interior tests skipped, untimed | simulated | top-8-level node fetches that hit L1 | "
            "deeper | L1 port wait per request | rays in flight | stall cycles |",
            "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for where, scene in scenes:
        s = res.get(("mobile", where, scene.stem, "mixed", "rtl-primary"))
        p = res.get(("mobile", where, scene.stem, "mixed", "predict"))
        if not s or not p or "unsupported" in s or "unsupported" in p:
            continue
        b = s["baseline"]
        saved = 1 - s["cycles"] / s["baseline_cycles"]
        reqs = b["l1_accesses"] or 1
        rows.append(
            f"| {label(where, scene)} | {pct(p['cost']['saved_cycle_fraction'])} | {pct(saved)} | "
            f"{pct(p['skipped_interior_fraction'])} | "
            f"{pct(s['predictor']['skipped_interior_fraction'])} | "
            f"{pct(b['top_node_l1_hit_rate'])} | "
            f"{pct(b['deep_node_l1_hit_rate']) if b['deep_node_fetches'] else '-'} | "
            f"{b['l1_port_wait_cycles'] / reqs:.0f} | {b['mean_in_flight']:.0f} | "
            f"{pct(s['predictor']['stall_cycles'] / max(1, s['cycles'] * s['units']))} |")
    return "\n".join(rows)


def repack_block(res, gpus, scenes):
    rows = ["| GPU | scene | preset | speed-up | with repacking | SIMD efficiency | "
            "with repacking | repacked warps |",
            "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |"]
    for gpu in gpus:
        for where, scene in scenes:
            for preset in REPACK:
                r = res.get((gpu, where, scene.stem, "ao", preset))
                if not r or "repacked" not in r or "unsupported" in r:
                    continue
                rp = r["repacked"]
                rows.append(f"| {gpu} | {label(where, scene)} | {preset} | {fx(r['speedup'])} | "
                            f"{fx(rp['speedup'])} | {pct(r['simd_efficiency'])} | "
                            f"{pct(rp['simd_efficiency'])} | {rp['repacked_warps']:,} |")
    return "\n".join(rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hrpp", default=str(ROOT / "build" / "hrpp"))
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"))
    ap.add_argument("--out", default=str(ROOT / "out" / "sim"))
    ap.add_argument("--res", default="256x256")
    ap.add_argument("--gpu", default="mobile,desktop")
    ap.add_argument("--scenes", help="comma-separated scene stems (default: all)")
    ap.add_argument("--doc", default=str(ROOT / "docs" / "results.md"),
                    help="the Markdown file whose sim-* blocks are rewritten ('' for none)")
    study.add_arguments(ap)
    args = ap.parse_args()
    scenes = scenes_of(args.shared, args.scenes)
    out = pathlib.Path(args.out)
    tasks = tasks_for(args, scenes, out)
    with open_study("sim_results", args, res=args.res) as st:
        res = reports(st, tasks)
        gpus = args.gpu.split(",")
        blocks, summary = {}, {"res": args.res, "gpus": gpus, "geomean": {}}
        cmd = (f"make sim-results SIM_RES={args.res}" if args.gpu == "mobile,desktop"
               else made_by())
        for gpu in gpus:
            body, means = gpu_block(res, gpu, scenes, args)
            summary["geomean"][gpu] = means
            blocks[f"sim-{gpu}"] = f"Made by `{cmd}`.\n\n{body}"
        if "mobile" in gpus:
            blocks["sim-disagree"] = f"Made by `{cmd}`.\n\n{disagree_block(res, scenes)}"
        blocks["sim-repack"] = f"Made by `{cmd}`.\n\n{repack_block(res, gpus, scenes)}"
        summary["runs"] = {"/".join(k): v.get("speedup") for k, v in res.items()}
        out.mkdir(parents=True, exist_ok=True)
        (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
        if args.doc:
            update_blocks(args.doc, blocks)
        st.complete()
    for gpu in gpus:
        print(f"{gpu}: AO (MICRO 2021) geometric-mean speed-up: "
              + ", ".join(f"{p} {summary['geomean'][gpu]['ao'][p]:.3f}x"
                          for p in PRESETS + ["oracle"]))


if __name__ == "__main__":
    sys.exit(study.main_errors("sim_results", main))
