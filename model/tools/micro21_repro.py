#!/usr/bin/env python3
"""Reproducing MICRO 2021 (docs/results.md, "Reproducing MICRO 2021"): a ladder from the
project's own set-up (the `mobile` GPU, AO rays from a camera's primary hits) to MICRO 2021's
simulator as its code times the RT unit, one modelled difference per rung, each rung keeping the
ones below it. On every rung, on every shared and own scene (the Cornell box once), `hrpp
simulate` runs:

- `micro21` (MICRO 2021's predictor) with the oracle beside it; from the repacking rung on, its
  figure is the run with MICRO 2021's repacking (`--repack --repack-by micro21`);
- `rtl-default`, the built design (the RTL's default configuration behind the RT unit's gate,
  `--gate 512 --gate-first 128`), and `secondary`, the secondary-ray study's winner in the golden
  model (both as model/tools/design_study.json defines them). MICRO 2021's predictor-integration
  rungs (replay, repacking, update timing) are its design, not its simulator's: our designs keep
  their own timing there, and the workload, BVH, memory and measurement rungs apply to them.

The rungs' GPU configurations are model/gpu/mobile.json with the fields of
model/gpu/micro21-sim.json (each citing MICRO 2021's code) taken one group at a time; the top
timing rung is micro21-sim.json itself. Runs go through the study driver (pyhrpp/study.py):
--workers N, --scheduler ADDRESS, --resume; reports in OUT/RUNG/WHERE.SCENE.DESIGN.json, the
tables in OUT/*.md and, a full run, the micro21-* blocks of --doc.

  micro21_repro.py [--hrpp build/hrpp] [--shared ../shared] [--out out/micro21_repro]
                   [--scenes a,b] [--doc docs/results.md] [--workers N]
"""
import argparse
import copy
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
sys.path.insert(0, str(ROOT / "model" / "tools"))
from pyhrpp import study  # noqa: E402
from pyhrpp.docs import update_blocks  # noqa: E402
from sim_study import (fx, geomean, label, made_by, open_study, reports, scenes_of,  # noqa: E402
                       task)
import design_study  # noqa: E402

MICRO21_AO_SPEEDUP = 1.26  # MICRO 2021's geometric-mean AO speed-up (Liu et al., abstract)
PAPER_SCENES = ("bunny", "teapot", "sponza")  # in rtao-benchmark/scenes/ and in ../shared
# The meshes of MICRO 2021's models in the shared scenes that add a floor or a light to them.
MODEL_MESHES = {"bunny": "bunny", "teapot": "teapot"}
CAMERA_AO = ["--res", "256x256", "--kinds", "ao", "--ao-distance", "inf"]

# The rungs, each (name, change, what it sets): "workload" the rays' options, "meshes" whether
# the shared scenes' models stand alone, "bvh" the BVH, "gpu" the micro21-sim.json fields taken,
# "micro21" simulate's options for MICRO 2021's predictor only, "all" for every run.
RUNGS = [
    ("ours", "the project's set-up: `mobile`, AO rays from the primary hits of a 256x256 "
     "camera frame (cosine, unbounded), our BVH", {}),
    ("workload", "MICRO 2021's AO rays: one per triangle in triangle order, from [0.1, inf) "
     "(`--workload micro21-ao`)", {"workload": ["--workload", "micro21-ao"]}),
    ("models", "its models alone: the bunny and the teapot without the floor and light of "
     "their shared scenes (`--meshes`)", {"meshes": True}),
    ("bvh", "its BVH: Embree's spatial-split build, leaves of up to 32 triangles, its node "
     "order (`--bvh micro21-sbvh`)", {"bvh": "micro21-sbvh"}),
    ("requests", "one 32-byte request per node or triangle record, sectored L1 and L2, its "
     "48-byte triangles and leaf terminators", {"gpu": ["l1.sector_bytes", "l2.sector_bytes",
                                                        "rt_unit.request_bytes",
                                                        "rt_unit.triangle_bytes",
                                                        "rt_unit.leaf_end_bytes"]}),
    ("l1-hits", "L1 hits free (the RT unit reads its cache directly; 20 cycles before)",
     {"gpu": ["l1.hit_latency"]}),
    ("tests", "2 cycles of test per record, triangles one at a time, no test issue limit",
     {"gpu": ["rt_unit.triangle_records", "box.per_cycle", "triangle.per_cycle"]}),
    ("replay", "`micro21`: fetch lists settled at the prediction (no decision round trip, no "
     "parent-pair fetch; `--replay`)", {"micro21": ["--replay"]}),
    ("repacking", "`micro21`: MICRO 2021's repacking: warps wait in the predictor, predicted "
     "rays pooled (`--repack --repack-by micro21`)",
     {"micro21": ["--repack", "--repack-by", "micro21"]}),
    ("updates", "`micro21`: table writes visible at once (`--update-latency 0`; 1 cycle "
     "before)", {"micro21": ["--update-latency", "0"]}),
    ("launch", "a 5,000-cycle kernel launch in every run (model/gpu/micro21-sim.json complete)",
     {"gpu": ["rt_unit.launch_latency"]}),
    ("kernel-end", "its kernel end: cycles until the last thread-block warp retires, not the "
     "last ray (`--cycles-until original-warps`)",
     {"all": ["--cycles-until", "original-warps"]}),
    ("sorted", "assumed from its README's example run: rays sorted by its ray-sorting key "
     "(`--workload micro21-ao-sorted`)", {"workload": ["--workload", "micro21-ao-sorted"]}),
    ("readme-run", "assumed from its README's example run: the first 40,000 rays, 10,000 of them "
     "a warm-up kernel (`--max-rays 40000 --warmup-rays 10000`; a scene with fewer rays: all, "
     "the first quarter a warm-up)", {"readme": True}),
]
TIMING_TOP = "launch"  # the rung whose GPU is model/gpu/micro21-sim.json
MODELLED_TOP = "kernel-end"  # the last rung every step of which their code shows
DESIGNS = ("micro21", "rtl-default", "secondary")
# On the top modelled rung, micro21 with one more change each: where its gap comes from.
VARIANTS = [
    ("unbounded-table", "an unbounded table (`--table unbounded`): no capacity or conflict misses",
     ["--table", "unbounded"]),
    ("flipped-normals", "its AO rays about the flipped normal (`--ao-normal flipped`)",
     ["--ao-normal", "flipped"]),
]


def rung_settings():
    """[(name, change, settings)]: each rung's settings with every rung below it applied."""
    out, cur = [], {"workload": [], "meshes": False, "bvh": None, "gpu": [], "micro21": [],
                    "all": [], "readme": False}
    for name, change, s in RUNGS:
        cur = copy.deepcopy(cur)
        for k, v in s.items():
            if k in ("workload", "meshes", "bvh", "readme"):
                cur[k] = v
            else:
                cur[k] = cur[k] + v
        out.append((name, change, cur))
    return out


def get(d, dotted):
    for k in dotted.split("."):
        d = d[k]
    return d


def put(d, dotted, value):
    keys = dotted.split(".")
    for k in keys[:-1]:
        d = d.setdefault(k, {})
    d[keys[-1]] = value


def gpu_file(fields, out, name):
    """model/gpu/mobile.json with FIELDS of model/gpu/micro21-sim.json (their sources too),
    written to OUT/gpu/NAME.json; its path."""
    base = json.loads((ROOT / "model" / "gpu" / "mobile.json").read_text())
    top = json.loads((ROOT / "model" / "gpu" / "micro21-sim.json").read_text())
    if not fields:
        return str(ROOT / "model" / "gpu" / "mobile.json")
    g = copy.deepcopy(base)
    g["name"] = f"micro21-{name}"
    g["description"] = (f"model/gpu/mobile.json with model/gpu/micro21-sim.json's "
                        f"{', '.join(fields)} (the MICRO 2021 reproduction's rung {name})")
    for f in fields:
        put(g, f, get(top, f))
        g["sources"][f] = top["sources"][f]
    path = out / "gpu" / f"{name}.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(g, indent=2) + "\n"
    if not path.exists() or path.read_text() != text:
        path.write_text(text)
    return str(path)


def check_top(rungs):
    """The top timing rung's GPU file has every field of micro21-sim.json that differs from
    mobile.json: the ladder reaches it."""
    base = json.loads((ROOT / "model" / "gpu" / "mobile.json").read_text())
    top = json.loads((ROOT / "model" / "gpu" / "micro21-sim.json").read_text())

    def leaves(d, prefix=""):
        for k, v in d.items():
            if k in ("name", "description", "sources"):
                continue
            if isinstance(v, dict):
                yield from leaves(v, prefix + k + ".")
            else:
                yield prefix + k, v
    differ = {k for k, v in leaves(top) if dict(leaves(base)).get(k) != v}
    taken = set(next(s for n, _, s in rungs if n == TIMING_TOP)["gpu"])
    if differ != taken:
        raise SystemExit(f"micro21_repro: the ladder's GPU fields {sorted(taken)} differ from "
                         f"micro21-sim.json's differences from mobile.json {sorted(differ)}")


README_RAYS, README_WARMUP = 40000, 10000  # rtao-benchmark/README.MD 20: -f ..._40000 -w 10000


def tasks_for(args, rungs, scenes, designs, out, rays_of=None):
    """The runs of RUNGS; a rung of the README's run needs RAYS_OF {(where, stem): rays}."""
    tasks = []
    for name, _, s in rungs:
        gpu = gpu_file(s["gpu"], out, name)
        for where, scene in scenes:
            cmd0 = [args.hrpp, "simulate", str(scene), "--gpu", gpu, "--json", "{json}"]
            cmd0 += s["workload"] if s["workload"] else CAMERA_AO
            if s["meshes"] and where == "shared" and scene.stem in MODEL_MESHES:
                cmd0 += ["--meshes", MODEL_MESHES[scene.stem]]
            if s["bvh"]:
                cmd0 += ["--bvh", s["bvh"]]
            cmd0 += s["all"]
            if s["readme"]:
                n = min(README_RAYS, rays_of[(where, scene.stem)])
                cmd0 += ["--max-rays", str(n), "--warmup-rays",
                         str(n * README_WARMUP // README_RAYS)]
            for d in designs:
                cmd = cmd0 + ["--preset", design_study.preset_arg(d, out)]
                for k, v in d.get("sim_options", {}).items():
                    if v is not None:
                        cmd += ["--" + k.replace("_", "-"), str(v)]
                if d["name"] == "micro21":
                    cmd += s["micro21"]
                else:
                    cmd.append("--no-oracle")
                key = (name, where, scene.stem, d["name"])
                tasks.append(task(key, cmd, out / name / f"{where}.{scene.stem}.{d['name']}.json"))
                if d["name"] == "micro21" and name == MODELLED_TOP:
                    for v, _, extra in VARIANTS:
                        tasks.append(task((name, where, scene.stem, f"micro21:{v}"), cmd + extra,
                                          out / name / f"{where}.{scene.stem}.micro21.{v}.json"))
    return tasks


def speedup(rep, repacked):
    if not rep or "unsupported" in rep:
        return None
    return rep["repacked"]["speedup"] if repacked and "repacked" in rep else rep["speedup"]


def repacked(rung):
    """micro21's figure on RUNG is its run with repacking."""
    return "--repack" in dict((n, s) for n, _, s in rung_settings())[rung]["micro21"]


def ladder_table(rungs, scenes, res):
    """The ladder: geometric means per rung."""
    paper = [(w, p) for w, p in scenes if w == "shared" and p.stem in PAPER_SCENES]
    lines = ["| rung | change | `micro21` | `micro21`: bunny, teapot, Sponza | oracle | "
             "`rtl-default` | `secondary` |", "| --- | --- | ---: | ---: | ---: | ---: | ---: |"]
    for name, change, _ in rungs:
        rp = repacked(name)

        def sp(where, scene, d):
            return speedup(res.get((name, where, scene.stem, d)), rp and d == "micro21")

        def orc(where, scene):
            r = res.get((name, where, scene.stem, "micro21"))
            return r["oracle"]["speedup"] if r and "oracle" in r else None
        m = [sp(w, p, "micro21") for w, p in scenes]
        lines.append(
            f"| {name} | {change} | {fx(geomean(m))} | "
            f"{fx(geomean([sp(w, p, 'micro21') for w, p in paper]))} | "
            f"{fx(geomean([orc(w, p) for w, p in scenes]))} | "
            f"{fx(geomean([sp(w, p, 'rtl-default') for w, p in scenes]))} | "
            f"{fx(geomean([sp(w, p, 'secondary') for w, p in scenes]))} |")
    return "\n".join(lines)


def per_scene_of(rungs, scenes, res, design):
    """DESIGN's speed-up (the oracle's: "oracle") per scene and rung."""
    names = [label(w, p) for w, p in scenes]
    out = ["| rung | " + " | ".join(names) + " |",
           "| --- | " + " | ".join("---:" for _ in names) + " |"]
    for name, _, _ in rungs:
        row = []
        for w, p in scenes:
            r = res.get((name, w, p.stem, "micro21" if design == "oracle" else design))
            if design == "oracle":
                row.append(r["oracle"]["speedup"] if r and "oracle" in r else None)
            else:
                row.append(speedup(r, design == "micro21" and repacked(name)))
        out.append(f"| {name} | " + " | ".join(fx(x) for x in row) + " |")
    return "\n".join(out)


def breakdown(rung, scenes, res):
    """Per scene on RUNG: rays, cycles with no predictor and with micro21, the fetches of
    each, micro21's precision and recall and the share of node tests it skipped."""
    rp = repacked(rung)
    out = ["| scene | rays | cycles: none | `micro21` | speed-up | node fetches: none | "
           "`micro21` | triangle fetches: none | `micro21` | precision | recall | node tests "
           "skipped | oracle | `rtl-default` | `secondary` |",
           "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
           "---: | ---: | ---: |"]
    for where, p in scenes:
        r = res.get((rung, where, p.stem, "micro21"))
        if not r or "unsupported" in r:
            continue
        m = r["repacked"] if rp and "repacked" in r else r
        b = r["baseline"]
        pr = r["predictor"]
        o = speedup(res.get((rung, where, p.stem, "rtl-default")), False)
        sc = speedup(res.get((rung, where, p.stem, "secondary")), False)
        out.append(
            f"| {label(where, p)} | {r['rays']:,} | {b['cycles']:,} | {m['cycles']:,} | "
            f"{fx(b['cycles'] / m['cycles'])} | {b['node_fetches']:,} | {m['node_fetches']:,} | "
            f"{b['triangle_fetches']:,} | {m['triangle_fetches']:,} | {pr['precision']:.3f} | "
            f"{pr['recall']:.3f} | {100 * pr['skipped_interior_fraction']:.1f}% | "
            f"{fx(r['oracle']['speedup'])} | {fx(o)} | {fx(sc)} |")
    return "\n".join(out)


def variants_block(scenes, res):
    """Per scene on the top modelled rung: micro21 as the ladder runs it and with each variant:
    speed-up, precision, recall."""
    rung = MODELLED_TOP
    rp = repacked(rung)
    cols = [("as the ladder", "micro21")] + [(v, f"micro21:{v}") for v, _, _ in VARIANTS]
    out = ["| scene | " + " | ".join(f"{c}: speed-up | precision | recall" for c, _ in cols) + " |",
           "| --- | " + " | ".join("---: | ---: | ---:" for _ in cols) + " |"]
    geo = {c: [] for c, _ in cols}
    for where, p in scenes:
        cells = []
        for c, d in cols:
            r = res.get((rung, where, p.stem, d))
            if not r or "unsupported" in r:
                cells.append(" |  | ")
                continue
            sp = speedup(r, rp)
            geo[c].append(sp)
            cells.append(f"{fx(sp)} | {r['predictor']['precision']:.3f} | "
                         f"{r['predictor']['recall']:.3f}")
        out.append(f"| {label(where, p)} | " + " | ".join(cells) + " |")
    out.append("| **geometric mean** | " + " | ".join(f"**{fx(geomean(geo[c]))}** |  | "
                                                     for c, _ in cols) + " |")
    notes = "".join(f"\n- {v}: {text}" for v, text, _ in VARIANTS)
    return "\n".join(out) + "\n" + notes


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hrpp", default=str(ROOT / "build" / "hrpp"))
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"))
    ap.add_argument("--out", default=str(ROOT / "out" / "micro21_repro"))
    ap.add_argument("--scenes", help="comma-separated scene stems (default: all)")
    ap.add_argument("--rungs", help="comma-separated rung names (default: all)")
    ap.add_argument("--doc", default=str(ROOT / "docs" / "results.md"),
                    help="the Markdown file whose micro21-repro blocks are rewritten ('' for "
                    "none)")
    study.add_arguments(ap)
    args = ap.parse_args()
    rungs = rung_settings()
    check_top(rungs)
    if args.rungs:
        want = args.rungs.split(",")
        unknown = set(want) - {n for n, _, _ in rungs}
        if unknown:
            raise SystemExit(f"micro21_repro: unknown rungs {sorted(unknown)} (rungs: "
                             f"{', '.join(n for n, _, _ in rungs)})")
        rungs = [r for r in rungs if r[0] in want]
    # Every shared and own scene, the Cornell box once (the shared one when both are there).
    scenes = scenes_of(args.shared, args.scenes, "micro21_repro")
    shared = {p.stem for w, p in scenes if w == "shared"}
    scenes = [(w, p) for w, p in scenes if not (w == "own" and p.stem in shared)]
    if not scenes:
        raise SystemExit("micro21_repro: no scenes")
    spec, all_designs = design_study.load_designs(ROOT / "model" / "tools" / "design_study.json")
    designs = [next(d for d in all_designs if d["name"] == n) for n in DESIGNS]
    out = pathlib.Path(args.out)
    first = [r for r in rungs if not r[2]["readme"]]
    readme = [r for r in rungs if r[2]["readme"]]
    with open_study("micro21_repro", args) as st:
        res = reports(st, tasks_for(args, first, scenes, designs, out))
        if readme:  # the README's run: its ray counts from the workload rung's micro21 runs
            count = tasks_for(args, [r for r in rung_settings() if r[0] == "workload"], scenes,
                              designs[:1], out)
            missing = [t for t in count if t.key not in res]  # --rungs left them out
            counted = {**res, **(reports(st, missing) if missing else {})}
            rays_of = {(t.key[1], t.key[2]): counted[t.key]["rays"] for t in count}
            res.update(reports(st, tasks_for(args, readme, scenes, designs, out, rays_of)))
        ladder = ladder_table(rungs, scenes, res)
        per_scene = per_scene_of(rungs, scenes, res, "micro21")
        top = [n for n, _, _ in rungs]
        made = f"Made by `{made_by()}`."
        blocks = {"micro21-ladder": f"{made}\n\n{ladder}",
                  "micro21-per-scene": f"{made} `micro21`'s speed-up per scene and rung.\n\n"
                                       f"{per_scene}"}
        for rung in (TIMING_TOP, MODELLED_TOP, top[-1]):
            if rung in top:
                blocks[f"micro21-{rung}"] = f"{made}\n\n{breakdown(rung, scenes, res)}"
        if MODELLED_TOP in top:
            blocks["micro21-variants"] = f"{made}\n\n{variants_block(scenes, res)}"
        for d in ("oracle",) + DESIGNS[1:]:  # the others' per-scene tables: files only
            (out / f"per-scene-{d}.md").write_text(
                f"{made} {d}'s speed-up per scene and rung.\n\n"
                f"{per_scene_of(rungs, scenes, res, d)}\n")
        for name, body in blocks.items():
            (out / f"{name}.md").write_text(body + "\n")
        print(ladder)
        if args.doc and not args.scenes and not args.rungs:  # the kernel-end breakdown: a file
            update_blocks(args.doc, {k: v for k, v in blocks.items()
                                     if k != f"micro21-{MODELLED_TOP}"})
        st.complete()


if __name__ == "__main__":
    sys.exit(study.main_errors("micro21_repro", main))
