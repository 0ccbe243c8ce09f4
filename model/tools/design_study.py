#!/usr/bin/env python3
"""Predictor design study for secondary rays in simulated time (docs/results.md, "A predictor for
secondary rays"): every design of model/tools/design_study.json on every shared and own scene x ray
kind x GPU configuration with `hrpp simulate`, and the tables of docs/results.md made from them.

  make design-study [STUDY_RES=mobile=256x256,desktop=1024x1024] [JOBS=2] [STUDY_OPTS=--resume]
  model/tools/design_study.py --hrpp build/hrpp --shared ../shared
      [--res mobile=256x256,desktop=1024x1024 | --res 256x256]
      [--gpu mobile,desktop] [--scenes bunny,sponza] [--kinds ao] [--designs a,b] [--doc ...]
      [--workers 2 | --scheduler ADDRESS | --no-dask] [--resume]

A design is a preset (`hrpp simulate --preset`): a named one, or options written to a preset file
(out/design_study/presets/NAME.json); its "sim_options" are `hrpp simulate`'s own (e.g.
"entry_timeout"), its "gpus" limit it to some GPU configurations. Ray kinds as in sim_results.py
(primary, shadow, AO as MICRO 2021, short AO), each simulated alone with an empty table. The
first design (on every GPU) also runs the oracle. Storage: the table's bits as the golden model
counts them (the largest over the scenes: node ids are as wide as the scene's BVH needs, 21 bits
on happy_buddha_full; an rtl-NAME preset's are its configuration's).

The protocol (design_study.json's "protocol"): every scene is a training scene (designs are
chosen and tuned on them) or a validation scene (only reported); the tables are made per set
(study-designs: validation, study-designs-training, the ablation on the training scenes, the goals
on both), and study-losses gives, per scene, what the baseline, the winner and its build lose
against the oracle on AO (hrpp simulate's loss breakdown).

"Never slower" is decided on more than one frame: every scene x kind where the winner, its
build or the noise design ran below --confirm-below (1.01) is run again for all three with
seeds 2 .. --seeds (5), and the goals judge the geometric mean over the seeds.

The runs go through the study driver (pyhrpp/study.py, docs/studies.md), the first runs and then
the confirmation seeds chosen from them: --workers, --scheduler or --no-dask; a progress line
per run; the journal OUT/journal.jsonl, whose finished runs --resume keeps when their command and
preset file are unchanged (so after a change to one design, or to one GPU's frame size, only the
runs it changes run again; another hrpp version is refused). Writes each run's report
OUT/GPU/SCENE-KIND-DESIGN.json and OUT/GPU/seeds/...-sSEED.json, OUT/summary.json, OUT/study.md
and (a full study only) the blocks of --doc that it places (study-protocol, study-designs,
study-designs-training, study-ablation, study-goal, study-losses; the others are named on stderr
and left in OUT/study.md).
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
from sim_results import KINDS  # noqa: E402
from sim_study import (fx, geomean, label, made_by, open_study, pct, reports,  # noqa: E402
                       scenes_of, task)

KIND_SHORT = {"primary": "primary", "shadow": "shadow", "ao": "AO", "ao-short": "short AO"}


def scene_sets(spec, scenes):
    """The protocol (spec "protocol"): {"training": [(where, path)], "validation": [...]}, the
    scenes in SCENES of each set, those it excludes left out. Every scene must be in one set."""
    prot = spec["protocol"]
    excluded = set(prot.get("exclude", []))
    sets = {name: [] for name in ("training", "validation")}
    where_of = {}
    for name in sets:
        for s in prot[name]:
            if s in where_of:
                raise SystemExit(f"design_study: protocol: {s} in both sets")
            where_of[s] = name
    unassigned = []
    for where, path in scenes:
        key = f"{where}:{path.stem}"
        if key in excluded:
            continue
        if key not in where_of:
            unassigned.append(key)
            continue
        sets[where_of[key]].append((where, path))
    if unassigned:
        raise SystemExit(f"design_study: protocol: scenes in no set: {', '.join(unassigned)} "
                         "(model/tools/design_study.json, protocol.training / validation)")
    return sets


def check_kinds(kinds, what):
    """Exit naming WHAT when KINDS has a name that is not a ray kind."""
    bad = [k for k in kinds if k not in KINDS]
    if bad:
        raise SystemExit(f"design_study: {what}: {bad} are not ray kinds ({', '.join(KINDS)})")


def load_designs(path):
    spec = json.loads(pathlib.Path(path).read_text())
    designs, names = [], set()
    for d in spec["designs"]:
        if d["name"] in names:
            raise SystemExit(f"design_study: {path}: design {d['name']!r} twice")
        names.add(d["name"])
        opts = dict(d.get("options", {}))
        if "ablation_of" in d:
            base = next((b for b in designs if b["name"] == d["ablation_of"]), None)
            if base is None:
                raise SystemExit(f"design_study: {path}: {d['name']}: ablation_of "
                                 f"{d['ablation_of']!r} is not an earlier design")
            # null removes an option of the base design's
            opts = {k: v for k, v in {**base["options"], **opts}.items() if v is not None}
            d = {**d, "sim_options": {**base.get("sim_options", {}), **d.get("sim_options", {})}}
        designs.append({**d, "options": opts})
    for gpu, kinds in spec.get("skip_kinds", {}).items():
        check_kinds(kinds, f"{path}: skip_kinds {gpu}")
    for k in ("winner", "baseline"):
        if spec[k] not in names:
            raise SystemExit(f"design_study: {path}: {k} {spec[k]!r} is not a design")
    return spec, designs


def preset_arg(design, out):
    """The --preset argument: a named preset as is, else a preset file of the design's options."""
    opts = design["options"]
    if list(opts) == ["preset"]:
        return opts["preset"]
    path = out / "presets" / f"{design['name']}.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps({"name": design["name"], **opts}, indent=1) + "\n"
    if not path.exists() or path.read_text() != text:
        path.write_text(text)
    return str(path)


def res_of(res, gpu):
    """The frame size of GPU from --res: one WxH for every GPU, or GPU=WxH,GPU=WxH."""
    if "=" not in res:
        return res
    sizes = dict(item.split("=", 1) for item in res.split(",") if item)
    if gpu not in sizes:
        raise SystemExit(f"design_study: --res {res}: no frame size for GPU {gpu}")
    return sizes[gpu]


def sim_task(key, args, gpu, scene, kopts, d, out, path, oracle, seed=None):
    """The run KEY of design D: its report to PATH."""
    cmd = [args.hrpp, "simulate", str(scene), "--res", res_of(args.res, gpu), "--gpu", gpu,
           "--preset", preset_arg(d, out), "--json", "{json}"] + kopts
    for k, v in d.get("sim_options", {}).items():  # simulate's own options (null: not given)
        if v is not None:
            cmd += ["--" + k.replace("_", "-"), str(v)]
    if not oracle:
        cmd.append("--no-oracle")
    if seed is not None:
        cmd += ["--seed", str(seed)]
    return task(key, cmd, path)


def kinds_of(spec, gpu, only=None):
    """The ray kinds run on GPU: every kind (or those of --kinds) but the spec's "skip_kinds" for
    it."""
    skip = spec.get("skip_kinds", {}).get(gpu, [])
    return [k for k in KINDS if k not in skip and (only is None or k in only)]


def tasks_for(args, spec, scenes, designs, out):
    tasks = []
    for gpu in args.gpu.split(","):
        for where, scene in scenes:
            for kind in kinds_of(spec, gpu, args.kinds):
                kopts = KINDS[kind]
                for i, d in enumerate(designs):
                    if gpu not in d.get("gpus", [gpu]):
                        continue
                    path = out / gpu / f"{where}-{scene.stem}-{kind}-{d['name']}.json"
                    tasks.append(sim_task((gpu, where, scene.stem, kind, d["name"]), args, gpu,
                                          scene, kopts, d, out, path, oracle=i == 0))
    return tasks


def confirm_names(spec, designs):
    """The designs whose slowest scene x kind the goals judge: the winner, its build, the noise
    design."""
    have = {d["name"] for d in designs}
    return [n for n in (spec["winner"], spec.get("built"), spec.get("noise")) if n in have]


def confirm_tasks(args, spec, designs, scenes, res, out):
    """"Never slower" is decided on more than one frame: every scene x kind where one of
    confirm_names() ran below --confirm-below is run again, for all of them, with seeds 2 ..
    --seeds (other rays of the same kind: sampled directions and jitter)."""
    names = confirm_names(spec, designs)
    by = {d["name"]: d for d in designs}
    paths = {(where, scene.stem): scene for where, scene in scenes}
    cells = sorted({k[:4] for k, r in res.items() if k[4] in names and r.get("speedup") is not None
                    and r["speedup"] < args.confirm_below})
    tasks = []
    for gpu, where, stem, kind in cells:
        for n in names:
            if gpu not in by[n].get("gpus", [gpu]):
                continue
            for seed in range(2, args.seeds + 1):
                path = out / gpu / "seeds" / f"{where}-{stem}-{kind}-{n}-s{seed}.json"
                tasks.append(sim_task((gpu, where, stem, kind, n, seed), args, gpu,
                                      paths[(where, stem)], KINDS[kind], by[n], out, path,
                                      oracle=False, seed=seed))
    return cells, tasks


def confirmed(res, seeds_res, cells, names, seeds):
    """{(gpu, where, stem, kind, name): (geometric mean over seeds 1 .. seeds, [speed-ups])} for
    the re-run cells."""
    out = {}
    for cell in cells:
        for n in names:
            first = res.get(cell + (n,))
            if not first or first.get("speedup") is None:
                continue
            sp = [first["speedup"]] + [seeds_res[cell + (n, str(sd))]["speedup"]
                                       for sd in range(2, seeds + 1)
                                       if cell + (n, str(sd)) in seeds_res]
            out[cell + (n,)] = (geomean(sp), sp)
    return out


def slowest(res, conf, gpu, name, scenes):
    """The slowest scene x kind of a design on a GPU, the re-run cells at their mean over the
    seeds: (speed-up, scene label, kind, frames) or None."""
    best = None
    for where, scene in scenes:
        for kind in KINDS:
            key = (gpu, where, scene.stem, kind, name)
            if key in conf:
                v, n = conf[key][0], len(conf[key][1])
            else:
                r = res.get(key)
                if not r or "speedup" not in r or r.get("rays", 0) == 0:
                    continue
                v, n = r["speedup"], 1
            if best is None or v < best[0]:
                best = (v, label(where, scene), kind, n)
    return best


def summarize(res, gpus, scenes, designs):
    """Per design: storage bits and, per GPU and kind, the speed-ups' geometric mean and minimum
    and the gain as a fraction of the oracle's (geometric means over the scenes)."""
    first = designs[0]["name"]
    summ = {}
    for d in designs:
        n = d["name"]
        bits = [r["preset"].get("table_bits", 0) for r in
                (res.get(k) for k in res if k[4] == n) if r and "preset" in r]
        s = {"bits": max(bits) if bits else None, "gpu": {}}
        for gpu in gpus:
            s["gpu"][gpu] = {}
            for kind in KINDS:
                sp, orc, worst, skipped = [], [], None, []
                for where, scene in scenes:
                    r = res.get((gpu, where, scene.stem, kind, n))
                    o = res.get((gpu, where, scene.stem, kind, first))
                    if not r or "unsupported" in r or not o or o["rays"] == 0 or \
                            "speedup" not in r:
                        if r and "unsupported" in r:
                            skipped.append(label(where, scene))
                        continue
                    sp.append(r["speedup"])
                    orc.append(o["oracle"]["speedup"])
                    if worst is None or r["speedup"] < worst[0]:
                        worst = (r["speedup"], label(where, scene))
                g, go = geomean(sp), geomean(orc)
                s["gpu"][gpu][kind] = {
                    "geomean": g, "oracle": go, "worst": worst, "skipped": skipped,
                    "of_oracle": (g - 1) / (go - 1) if go and go > 1 else None}
        summ[n] = s
    return summ


LOSS_PARTS = ["compulsory", "evicted", "aliased", "stale", "suppressed", "gated", "not_offered",
              "unknown"]


def loss_at(res, gpu, where, stem, kind, name, first):
    """Design NAME's loss breakdown on one scene and kind (its oracle from the run of FIRST, the
    design that runs it), or None without a run, an oracle or a saving to share."""
    o = res.get((gpu, where, stem, kind, first))
    r = res.get((gpu, where, stem, kind, name))
    if not o or "oracle" not in o or not r or "loss_tally" not in r:
        return None
    lo = r["loss"] if "loss" in r else loss_of(r, o)
    return lo if lo["oracle_saved_cycles"] > 0 else None


def losses_block(res, gpu, kind, scenes, names, first):
    """Per scene, for the designs NAMES on GPU and KIND: the oracle's saved cycles and the share
    each design loses to each cause (hrpp simulate's "loss"; docs/timing_model.md, "Losses
    against the oracle"), as % of the oracle's saving."""
    head = ("| scene | design | gain, % of the oracle's | " + " | ".join(LOSS_PARTS)
            + " | wrong predictions | right predictions' walks | timing |")
    rows = [head, "| --- | --- |" + " ---: |" * (len(LOSS_PARTS) + 4)]
    for where, scene in scenes:
        for n in names:
            lo = loss_at(res, gpu, where, scene.stem, kind, n, first)
            if not lo:
                continue
            saved = lo["oracle_saved_cycles"]
            share = [lo["classes"][c]["cycles"] / saved for c in LOSS_PARTS]
            rest = [lo["wrong_predictions"]["cycles"] / saved,
                    lo["right_prediction_walks"]["cycles"] / saved,
                    lo["timing"]["cycles"] / saved]
            rows.append(f"| {label(where, scene)} | `{n}` | {pct(lo['saved_cycles'] / saved)} | "
                        + " | ".join(pct(x) for x in share + rest) + " |")
    return "\n".join(rows)


def loss_of(r, o):
    """hrpp simulate's "loss" (loss_json) for the run R whose oracle ran in the run O (the same
    rays and GPU): the oracle's saved cycles shared among R's classes by their node tests."""
    t = r["loss_tally"]
    base, orc, des = r["baseline_cycles"], o["oracle"]["cycles"], r["cycles"]
    tests = sum(c["tests"] for c in t["classes"].values())
    k = (base - orc) / tests if tests else 0.0
    classes = {n: {"rays": c["rays"], "tests": c["tests"], "cycles": k * c["tests"]}
               for n, c in t["classes"].items()}
    lost = sum(c["cycles"] for n, c in classes.items() if n != "captured")
    wrong, right = k * t["wrong_tests"], k * t["right_tests"]
    return {"oracle_saved_cycles": base - orc, "saved_cycles": base - des, "classes": classes,
            "wrong_predictions": {"cycles": wrong}, "right_prediction_walks": {"cycles": right},
            "timing": {"cycles": des - orc - lost - wrong - right}}


def loss_figure(res, gpu, kind, sets, name, first, path):
    """A figure of what design NAME loses against the oracle per scene on GPU and KIND (the
    validation scenes, then the training ones): each bar is the oracle's saved cycles, split into
    the design's own saving and each cause of loss (hrpp simulate's loss breakdown); a negative
    timing rest is named beside its bar. Returns the path, or None with no runs to show."""
    rows = []
    for set_name in ("validation", "training"):
        for where, scene in sets[set_name]:
            lo = loss_at(res, gpu, where, scene.stem, kind, name, first)
            if not lo:
                continue
            saved = lo["oracle_saved_cycles"]
            parts = [max(0.0, lo["saved_cycles"]) / saved]
            parts += [lo["classes"][c]["cycles"] / saved for c in LOSS_PARTS]
            parts += [lo["wrong_predictions"]["cycles"] / saved,
                      lo["right_prediction_walks"]["cycles"] / saved,
                      lo["timing"]["cycles"] / saved]
            rows.append((f"{label(where, scene)} ({set_name[0]})", parts))
    if not rows:
        return None
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = [f"`{name}`'s saving"] + LOSS_PARTS + ["wrong predictions", "right predictions' walks",
                                                   "timing"]
    fig, ax = plt.subplots(figsize=(11, 0.45 * len(rows) + 2.2))
    colors = plt.get_cmap("tab20").colors
    for i, (lab, parts) in enumerate(rows):
        left = 0.0
        for j, v in enumerate(parts):
            if v > 0:
                ax.barh(i, 100 * v, left=100 * left, color=colors[j % len(colors)],
                        label=names[j] if i == 0 else None)
                left += v
        if parts[-1] < 0:
            ax.text(100 * left + 1, i, f"timing {100 * parts[-1]:.0f}%", va="center", fontsize=7)
    handles = [plt.Rectangle((0, 0), 1, 1, color=colors[j % len(colors)])
               for j in range(len(names))]
    ax.set_yticks(range(len(rows)), [r[0] for r in rows], fontsize=8)
    ax.invert_yaxis()
    ax.set_xlabel("% of the cycles the oracle saves over no predictor")
    ax.set_title(f"`{name}` against the oracle, {KIND_SHORT[kind]} on `{gpu}` (v: validation, "
                 "t: training scene)", fontsize=10)
    fig.legend(handles, names, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def protocol_block(spec, sets):
    prot = spec["protocol"]
    lines = [" ".join(prot["about"]) if isinstance(prot["about"], list) else prot["about"], ""]
    for name in ("validation", "training"):
        lines.append(f"- {name}: " + ", ".join(label(w, p) for w, p in sets[name]))
    if prot.get("exclude"):
        lines.append("- left out: " + ", ".join(f"{k.split(':')[1]} ({k.split(':')[0]})"
                                                for k in prot["exclude"])
                     + " (the same scene as another)")
    return "\n".join(lines)


def bits_text(b):
    return f"{b:,}" if b else "unbounded"


def designs_block(spec, designs, summ, gpus):
    rows = []
    head = "| design | table bits |"
    sep = "| --- | ---: |"
    for gpu in gpus:
        for kind in KINDS:
            head += f" {gpu}: {KIND_SHORT[kind]} |"
            sep += " ---: |"
        head += f" {gpu}: AO gain, % of the oracle's | {gpu}: slowest scene x kind |"
        sep += " ---: | --- |"
    rows += [head, sep]
    for d in designs:
        if "ablation_of" in d:
            continue
        s = summ[d["name"]]
        cells = [f"`{d['name']}`", bits_text(s["bits"])]
        for gpu in gpus:
            g = s["gpu"][gpu]
            cells += [fx(g[k]["geomean"]) for k in KINDS]
            cells.append(pct(g["ao"]["of_oracle"]) if g["ao"]["of_oracle"] is not None else "")
            worst = min(((g[k]["worst"], k) for k in KINDS if g[k]["worst"]),
                        key=lambda w: w[0][0], default=None)
            cells.append(f"{worst[0][0]:.3f} ({worst[0][1]}, {KIND_SHORT[worst[1]]})"
                         if worst else "")
        rows.append("| " + " | ".join(cells) + " |")
    oracle = {gpu: {k: summ[designs[0]["name"]]["gpu"][gpu][k]["oracle"] for k in KINDS}
              for gpu in gpus}
    cells = ["oracle", ""]
    for gpu in gpus:
        cells += [fx(oracle[gpu][k]) for k in KINDS] + ["100.0%", ""]
    rows.append("| " + " | ".join(cells) + " |")
    legend = ["", "Designs (options as `hrpp simulate` takes them; timing: the golden predictor "
              "behind the RTL's latencies, except `micro21` (its simulator's) and the rtl-NAME "
              "presets (the RTL's cycle model)):", ""]
    for d in designs:
        if "ablation_of" in d:
            continue
        legend.append(f"- `{d['name']}`: {d['about']}")
    skipped = sorted({f"`{n}`: {', '.join(sorted(set(v)))}" for n, s in summ.items()
                      for v in [[x for gpu in gpus for k in KINDS
                                 for x in s["gpu"][gpu][k]["skipped"]]] if v})
    if skipped:
        legend += ["", "Scenes a design cannot run (its node ids cannot name the BVH), left out "
                   "of its means: " + "; ".join(skipped) + "."]
    return "\n".join(rows + legend)


def ablation_block(spec, designs, summ, gpus):
    w = spec["winner"]
    rows = ["| change against `" + w + "` | table bits | "
            + " | ".join(f"{gpu}: {KIND_SHORT[k]}" for gpu in gpus for k in KINDS) + " |",
            "| --- | ---: |" + " ---: |" * (len(gpus) * len(KINDS))]

    def cells(n):
        s = summ[n]
        return [bits_text(s["bits"])] + [fx(s["gpu"][gpu][k]["geomean"])
                                         for gpu in gpus for k in KINDS]
    rows.append(f"| none (`{w}` itself) | " + " | ".join(cells(w)) + " |")
    for d in designs:
        if d.get("ablation_of") == w:
            rows.append(f"| {d['about']} (`{d['name']}`) | " + " | ".join(cells(d["name"])) + " |")
    return "\n".join(rows)


def seeds_text(never, gpu, name, noise):
    """The slowest scene x kind of `name` and of the noise design with the re-run cells at their
    mean over the seeds, and whether it is slower than no predictor beyond the noise floor."""
    w, nz = never.get((gpu, name)), never.get((gpu, noise))
    if not w or w[3] == 1 and (not nz or nz[3] == 1):
        return ""
    text = (f"; over more frames (every scene x kind below the re-run threshold at seed 1 run with "
            f"{w[3]} seeds, geometric mean): slowest {w[0]:.3f} ({w[1]}, {KIND_SHORT[w[2]]})")
    if nz:
        text += f", `{noise}`'s slowest {nz[0]:.3f} ({nz[1]}, {KIND_SHORT[nz[2]]})"
        text += (": never slower than no predictor beyond the noise floor" if w[0] >= min(1.0, nz[0])
                 else ": slower than no predictor beyond the noise floor")
    return text


def goal_block(spec, summ, gpus, never, prefix=""):
    """The goals of the study for the winner and its build ("built"): the AO gain against the
    baseline's, shadow and primary rays, and the slowest scene x kind against the noise floor
    (the "noise" design's slowest); never: {(gpu, name): slowest()} over the seeds. PREFIX
    starts each line (the scene set)."""
    base, noise = spec["baseline"], spec.get("noise")
    lines = []
    for w in [spec["winner"]] + ([spec["built"]] if spec.get("built") in summ else []):
        for gpu in gpus:
            sw, sb = summ[w]["gpu"].get(gpu), summ[base]["gpu"][gpu]
            if not sw or not sw["ao"]["worst"]:
                continue
            gw, gb = sw["ao"]["geomean"] - 1, sb["ao"]["geomean"] - 1
            ratio = (f"{gw / gb:.2f}x its gain; the goal: at least 1.5x" if gb > 0 else
                     f"`{base}` loses time, so a ratio of gains means nothing")
            worst = min(((sw[k]["worst"], k) for k in KINDS if sw[k]["worst"]),
                        key=lambda x: x[0][0])
            floor = ""
            if noise in summ and summ[noise]["gpu"].get(gpu):
                nz = [summ[noise]["gpu"][gpu][k]["worst"] for k in KINDS]
                nz = min((x for x in nz if x), key=lambda x: x[0], default=None)
                if nz:
                    floor = f"; the noise floor (`{noise}`'s slowest): {nz[0]:.3f} ({nz[1]})"
            lines.append(
                f"- {prefix}`{w}` on `{gpu}`: AO gain {100 * gw:+.1f}% against `{base}`'s "
                f"{100 * gb:+.1f}% ({ratio}); {pct(sw['ao']['of_oracle'])} of the oracle's "
                f"(stretch goal: 50%); shadow rays {fx(sw['shadow']['geomean'])} against "
                f"{fx(sb['shadow']['geomean'])}; primary rays "
                f"{fx(sw['primary']['geomean']) or 'not run (skip_kinds)'}; "
                f"slowest scene x kind {worst[0][0]:.3f} ({worst[0][1]}, {KIND_SHORT[worst[1]]})"
                + floor + seeds_text(never, gpu, w, noise))
    return "\n".join(lines)


def write_outputs(args, spec, designs, scenes, out, res, seeds_res, cells):
    """OUT/summary.json, OUT/study.md and the blocks of --doc (those of a full study only) from
    the runs' reports RES and the confirmation seeds' SEEDS_RES (the scene x kind CELLS)."""
    conf = confirmed(res, seeds_res, cells, confirm_names(spec, designs), args.seeds)
    gpus = args.gpu.split(",")
    sets = scene_sets(spec, scenes)
    summ = summarize(res, gpus, sets["validation"], designs)
    summ_t = summarize(res, gpus, sets["training"], designs)
    never = {(gpu, n): slowest(res, conf, gpu, n, sets["validation"])
             for gpu in gpus for n in confirm_names(spec, designs)}
    never_t = {(gpu, n): slowest(res, conf, gpu, n, sets["training"])
               for gpu in gpus for n in confirm_names(spec, designs)}
    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.json").write_text(json.dumps(
        {"res": args.res, "gpus": gpus, "designs": summ, "designs_training": summ_t,
         "sets": {k: [label(w, p) for w, p in v] for k, v in sets.items()},
         "seeds": {"frames": args.seeds, "confirm_below": args.confirm_below,
                   "cells": {" ".join(k): {"geomean": v[0], "speedups": v[1]}
                             for k, v in conf.items()},
                   "slowest": {f"{gpu} {n}": v for (gpu, n), v in never.items()}}},
        indent=2, default=str) + "\n")
    full = not (args.scenes or args.designs or args.kinds) and args.gpu == "mobile,desktop"
    cmd = f"make design-study STUDY_RES={args.res}" if full else made_by()
    names = {d["name"] for d in designs}
    made = f"Made by `{cmd}`."
    blocks = {"study-protocol": protocol_block(spec, sets),
              "study-designs": f"{made} The validation scenes.\n\n"
              + designs_block(spec, designs, summ, gpus),
              "study-designs-training": f"{made} The training scenes.\n\n"
              + designs_block(spec, designs, summ_t, gpus)}
    if spec["winner"] in names:
        blocks["study-ablation"] = (f"{made} The training scenes.\n\n"
                                    + ablation_block(spec, designs, summ_t, gpus))
        if spec["baseline"] in names:
            blocks["study-goal"] = (f"{made}\n\n" + goal_block(spec, summ, gpus, never,
                                                                "validation: ")
                                    + "\n" + goal_block(spec, summ_t, gpus, never_t,
                                                         "training: "))
            print(blocks["study-goal"])
    shown = [n for n in (spec["baseline"], spec["winner"], spec.get("built")) if n in names]
    if spec["winner"] in names:
        fig = loss_figure(res, "mobile", "ao", sets, spec["winner"], designs[0]["name"],
                          out / "losses-mobile-ao.png")
        if fig:
            print(f"design_study: {spec['winner']}'s losses against the oracle: {fig}",
                  file=sys.stderr)
    blocks["study-losses"] = (
        f"{made} AO as MICRO 2021 on `mobile`, the validation scenes, then the training "
        "scenes.\n\n" + losses_block(res, "mobile", "ao", sets["validation"] + sets["training"],
                                      shown, designs[0]["name"]))
    if args.doc and full:
        # Only the blocks the document places; a new block is placed by hand first.
        text = pathlib.Path(args.doc).read_text()
        missing = [k for k in blocks if f"<!-- BEGIN {k} -->" not in text]
        if missing:
            print(f"design_study: {args.doc} has no place for the blocks {', '.join(missing)}: "
                  f"they are in {out / 'study.md'}", file=sys.stderr)
        update_blocks(args.doc, {k: v for k, v in blocks.items() if k not in missing})
    elif args.doc:
        print("design_study: a partial study (--scenes, --kinds, --designs or --gpu): docs "
              f"untouched; the tables are in {out / 'study.md'}", file=sys.stderr)
    (out / "study.md").write_text("\n\n".join(f"<!-- {k} -->\n{v}" for k, v in blocks.items())
                                  + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hrpp", default=str(ROOT / "build" / "hrpp"))
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"))
    ap.add_argument("--spec", default=str(ROOT / "model" / "tools" / "design_study.json"))
    ap.add_argument("--out", default=str(ROOT / "out" / "design_study"))
    ap.add_argument("--res", default="mobile=256x256,desktop=1024x1024",
                    help="frame size: WxH for every GPU, or GPU=WxH,... (default: desktop's "
                    "68 units get 16x mobile's frame, each unit about half the rays of one of "
                    "mobile's 2: docs/results.md)")
    ap.add_argument("--gpu", default="mobile,desktop")
    ap.add_argument("--seeds", type=int, default=5,
                    help="frames (simulate --seed 1 .. N) for the scene x kind cells where the "
                    "winner, its build or the noise design ran below --confirm-below; 1: none")
    ap.add_argument("--confirm-below", type=float, default=1.01)
    ap.add_argument("--scenes", help="comma-separated scene stems (default: all)")
    ap.add_argument("--kinds", help="comma-separated ray kinds (default: all; "
                    + ", ".join(KINDS) + ")")
    ap.add_argument("--designs", help="comma-separated design names (default: all; the first "
                    "design always runs, for the oracle)")
    ap.add_argument("--doc", default=str(ROOT / "docs" / "results.md"),
                    help="the Markdown file whose study-* blocks are rewritten ('' for none)")
    study.add_arguments(ap)
    args = ap.parse_args()
    spec, designs = load_designs(args.spec)
    if args.designs:
        want = set(args.designs.split(","))
        unknown = want - {d["name"] for d in designs}
        if unknown:
            raise SystemExit(f"design_study: unknown designs {sorted(unknown)}")
        designs = [d for i, d in enumerate(designs) if i == 0 or d["name"] in want]
    scenes = scenes_of(args.shared, args.scenes, "design_study")
    if args.kinds:
        args.kinds = args.kinds.split(",")
        check_kinds(args.kinds, "--kinds")
    out = pathlib.Path(args.out)
    for gpu in args.gpu.split(","):
        res_of(args.res, gpu)  # every GPU has a frame size
    tasks = tasks_for(args, spec, scenes, designs, out)
    with open_study("design_study", args) as st:
        res = reports(st, tasks)
        cells, ctasks = confirm_tasks(args, spec, designs, scenes, res, out) if args.seeds > 1 \
            else ([], [])
        if ctasks:
            print(f"design_study: {len(cells)} scene x kind cells below {args.confirm_below} at "
                  f"seed 1: seeds 2 .. {args.seeds}", file=sys.stderr)
        seeds_res = reports(st, ctasks) if ctasks else {}
        write_outputs(args, spec, designs, scenes, out, res, seeds_res, cells)
        st.complete()


if __name__ == "__main__":
    sys.exit(study.main_errors("design_study", main))
