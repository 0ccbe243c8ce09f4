#!/usr/bin/env python3
"""What accuracy costs in time: sweeps predictor parameters over scenes (docs/cost_model.md).

    hrpp sweep SCENE... --param NAME=V1,V2,... [--param ...] [--res WxH] [--spp N] --csv FILE
               [--timing cost-model | --timing simulate [--gpu mobile|desktop|FILE] [--oracle]]
               [--plots DIR] [--report FILE] [--workers N | --scheduler ADDRESS | --no-dask]
               [--resume]
    hrpp sweep --from-csv FILE... [--plots DIR] [--report FILE] [--doc PAGE]   (one at least)

Every configuration of the grid (the cartesian product of the --param lists) on every scene is one
`hrpp predict` run, a task of the project's study driver (pyhrpp/study.py): on a local Dask cluster
of --workers processes by default, on the cluster at --scheduler ADDRESS when given (its workers
must see the same paths: the hrpp binary and the scenes), or one after another in this process
with --no-dask. The rows are made here from the runs' reports, in task order. The CSV has one row
per scene x configuration x ray kind (and kind "all"), sorted by scene, grid order and kind, so a
run is reproducible byte for byte except the measured CPU times (--no-timing leaves them out).

Presets: --param preset=rtl-primary,micro21,study2019 (the names `hrpp predict --help` lists, or
FILE.json) runs each task with --preset NAME; the other swept parameters override the preset's
values (the parameters not swept are the preset's). The CSV's preset column names it (empty for
none) and the parameter columns hold the values that ran; labels name configurations by preset.

Interruption: the driver's journal, CSV.journal.jsonl, keeps each finished run as it finishes.
SIGINT or SIGTERM stops the sweep with one line (exit 130 / 143) and shuts the Dask cluster down;
--resume runs only the runs the journal lacks, for the same sweep (same scenes, parameters,
resolution, timing, GPU, oracle, CPU times, images folder and hrpp version; refused naming the
difference otherwise), and the CSV is then byte for byte an uninterrupted run's. The journal is
kept, marked complete, when the CSV is written (--resume then runs nothing).

The report and the plots lead with time (time_saved.png, the report's first table: cycles saved
per configuration and scene; a configuration that takes longer than the baseline "costs" time).
Every plot names its scenes, the fixed configuration and its axes' units; large sweeps go on
further pages (NAME-2.png, ...). Unbounded tables have no size: plots put them apart, the report
says "unbounded".

Pareto fronts use the cost model's deterministic cycles, never the noisy CPU times.

--timing simulate takes the time axis from the cycle-level model instead (docs/timing_model.md,
"Sweeps in simulated time"): each task runs `hrpp simulate` with the same predictor and workload
options (on --gpu, mobile by default; without the oracle unless --oracle), and the rows' cycles
per ray and saved cycles are simulated cycles: per ray kind from that kind's rays run alone, the
"all" row from the mixed run. update_delay and latency do not apply (the simulated table's
staleness follows from the simulated occupancy). The CSV then has the extra columns timing, gpu,
speedup, l1_hit_rate, stall_cycles, oracle_speedup and fraction_of_oracle; a cost-model CSV
keeps its columns. CSVs of different timings (or GPUs) are never merged into one report.
"""
import argparse
import csv
import difflib
import io
import itertools
import json
import math
import os
import pathlib
import re
import subprocess
import sys
import textwrap

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp import study  # noqa: E402
from pyhrpp.docs import markers, update_blocks  # noqa: E402
from pyhrpp.files import write_atomic  # noqa: E402

# Sweepable parameters: name -> (hrpp predict option, default as hrpp predict uses it). preset:
# a named predictor (hrpp predict --preset; "" for none): its values replace the defaults and the
# parameters swept beside it override them (PRESET_SET are the ones a preset sets).
PARAMS = {
    "preset": ("--preset", ""),
    "hash": ("--hash", "faithful"),
    "precision": ("--precision", "6"),
    "exp_bits": ("--exp-bits", "3"),
    "origin_bits": ("--origin-bits", "5"),
    "dir_bits": ("--dir-bits", "3"),
    "dir_code": ("--dir-code", "grid"),
    "combine": ("--combine", "xor"),
    "table": ("--table", "unbounded"),
    "tag_bits": ("--tag-bits", "full"),
    "nodes_per_entry": ("--nodes-per-entry", "1"),
    "go_up": ("--go-up", "0"),
    "update_delay": ("--update-delay", "0"),
    "latency": ("--pipeline-latency", "none"),
    "mode": ("--mode", "closest-exact"),
    "spp": ("--spp", "1"),
    "order": ("--order", "scanline"),
}
ALIASES = {"exp": "exp_bits", "ways": "table", "k": "nodes_per_entry", "nodes": "nodes_per_entry",
           "go_up_level": "go_up", "pipeline_latency": "latency", "ray_order": "order",
           "variant": "hash", "hash_variant": "hash", "size": "table"}
PRESET_SET = ("hash", "precision", "exp_bits", "origin_bits", "dir_bits", "dir_code", "combine",
              "table", "tag_bits", "nodes_per_entry", "go_up", "mode")
KIND_ORDER = ["primary", "shadow", "ao", "reflection", "refraction", "diffuse", "all"]

RESULT_COLUMNS = [
    "rays", "table_bytes", "table_entries", "update_delay_rays",
    "pred_precision", "pred_recall", "true_positive", "false_positive", "false_negative",
    "skipped_interior", "skipped_tri", "skipped_walks", "wrong_results", "wrong_fraction",
    "accuracy", "baseline_cycles_per_ray", "hrpp_cycles_per_ray", "saved_cycles",
    "baseline_ns_per_ray", "hrpp_ns_per_ray", "image_mae", "image_differ", "spec_image"]
# --timing simulate: columns after RESULT_COLUMNS (a cost-model CSV has none of them; read back,
# its rows get timing "cost-model" and the others empty).
SIM_COLUMNS = ["timing", "gpu", "speedup", "l1_hit_rate", "stall_cycles", "oracle_speedup",
               "fraction_of_oracle"]
SIM_NUMERIC = ["speedup", "l1_hit_rate", "stall_cycles", "oracle_speedup", "fraction_of_oracle"]
# Parameters that have no meaning in the cycle-level model.
NOT_SIMULATED = ("update_delay", "latency")


class BadInput(Exception):
    pass


def parse_params(specs, timing="cost-model"):
    """['precision=5,6', 'table=64x4,unbounded'] -> ordered {name: [values]}."""
    grid = {}
    for spec in specs:
        if "=" not in spec:
            raise BadInput(f"--param {spec!r}: expected NAME=V1,V2,...")
        name, values = spec.split("=", 1)
        name = name.strip().lower().replace("-", "_")
        name = ALIASES.get(name, name)
        if name not in PARAMS:
            raise BadInput(f"--param {spec!r}: unknown parameter {name!r}; known: "
                           + ", ".join(PARAMS))
        vals = [v.strip() for v in values.split(",")]
        if not vals or any(v == "" for v in vals):
            raise BadInput(f"--param {spec!r}: empty value")
        if name in grid:
            raise BadInput(f"--param {name} given twice")
        grid[name] = vals
    if timing == "simulate":
        for name in NOT_SIMULATED:
            if name in grid:
                raise BadInput(f"--param {name}: does not apply to --timing simulate (the "
                               "simulated table's staleness follows from the simulated rays in "
                               "flight, docs/timing_model.md); sweep it with --timing cost-model")
    if "latency" in grid and "update_delay" in grid:
        raise BadInput("sweep either latency (cycles of the traversal engine; the update delay "
                       "then comes from the RTL's cycle model) or update_delay (rays), not both")
    return grid


def expand(grid, presets=None):
    """The configurations, in grid order: dicts with every parameter (defaults filled in; a
    preset's values, from PRESETS {name: {parameter: value}}, replace the defaults)."""
    names = list(grid)
    configs = []
    for combo in itertools.product(*(grid[n] for n in names)):
        c = {n: d for n, (_, d) in PARAMS.items()}
        swept = dict(zip(names, combo))
        if swept.get("preset"):
            c.update(presets[swept["preset"]])
        c.update(swept)
        configs.append(c)
    return configs


def preset_names(hrpp):
    """The preset names `hrpp predict --help` lists (None when it lists none)."""
    proc = subprocess.run([hrpp, "predict", "--help"], capture_output=True, text=True)
    m = re.search(r"--preset TEXT:\{([^}]*)\}", proc.stdout)
    return m.group(1).split(",") if m else None


def is_preset_file(value):
    return value.endswith(".json") or os.sep in value


def preset_values(hrpp, scene, preset):
    """A preset's parameter values ({name: value} for PRESET_SET), from the configuration that
    `hrpp predict --preset PRESET --json -` reports on one pixel of SCENE."""
    cmd = [hrpp, "predict", scene, "--res", "1x1", "--preset", preset, "--timing", "cost-model",
           "--json", "-"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise BadInput(f"--param preset={preset}: {' '.join(cmd)} exited {proc.returncode}:\n"
                       + proc.stderr.strip())
    c = json.loads(proc.stdout)["config"]
    bounded = c["table"] != "unbounded"
    return {"hash": c["hash"], "precision": str(c["precision_bits"]),
            "exp_bits": str(c["exp_bits"]), "origin_bits": str(c["origin_bits"]),
            "dir_bits": str(c["dir_bits"]), "dir_code": c.get("dir_code", "grid"),
            "combine": c["combine"], "table": c["table"],
            "tag_bits": str(c["tag_bits"]) if bounded and c["tag_bits"] != c["full_tag_bits"]
            else "full",
            "nodes_per_entry": str(c["nodes_per_entry"]), "go_up": str(c["go_up"]),
            "mode": c["mode"]}


def check_presets(grid, hrpp, scene):
    """Checks the swept presets before any run (names against `hrpp predict --help`, files
    exist; a file is made absolute for the workers) and returns {preset: its values}."""
    if "preset" not in grid:
        return {}
    known = None
    for i, v in enumerate(grid["preset"]):
        if is_preset_file(v):
            if not os.path.isfile(v):
                raise BadInput(f"--param preset={v}: no such preset file")
            grid["preset"][i] = os.path.abspath(v)
            continue
        if known is None:
            known = preset_names(hrpp) or []
        if known and v not in known:
            close = difflib.get_close_matches(v, known, n=1)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            raise BadInput(f"--param preset={v}: unknown preset '{v}'{hint} (known: "
                           f"{', '.join(known)}, or a FILE.json)")
    if "tag_bits" in grid and "full" in grid["tag_bits"]:
        raise BadInput("--param tag_bits=full cannot override a preset's tag bits (hrpp has no "
                       "option for the full tag); sweep numbers of tag bits")
    return {v: preset_values(hrpp, scene, v) for v in grid["preset"]}


def applies(name, cfg):
    """Whether a parameter means anything for the configuration: hrpp refuses an option given
    for the other hash variant, and stored tag bits for an unbounded table."""
    if name in ("precision", "exp_bits"):
        return cfg["hash"] == "faithful"
    if name in ("origin_bits", "dir_bits"):
        return cfg["hash"] != "faithful"
    if name == "dir_code":  # the improved hash only; the default (grid) is passed only to
        # override a preset's code, so that every other command line stays as it was
        return cfg["hash"] == "improved" and (cfg["dir_code"] != PARAMS["dir_code"][1]
                                              or bool(cfg["preset"]))
    if name == "tag_bits":
        return cfg["table"] != "unbounded"
    return True


def predict_args(cfg, swept=()):
    """hrpp predict's options for a configuration: every parameter, or with a preset the preset
    and the parameters SWEPT beside it (the others are the preset's)."""
    args = []
    for name, (opt, default) in PARAMS.items():
        v = cfg[name]
        if name == "preset":
            args += [opt, v] if v else []
            continue
        if cfg["preset"] and name in PRESET_SET and name not in swept:
            continue
        if name in ("tag_bits", "latency") and v in ("full", "none") or not applies(name, cfg):
            continue
        if name == "update_delay" and cfg["latency"] != "none":
            continue  # the latency sets the update delay (from the RTL's cycle model)
        args += [opt, v]
    return args


def simulate_args(cfg, swept=()):
    """hrpp simulate's options for a configuration: predict_args without the update delay and
    the pipeline latency (parse_params refuses sweeping them; their defaults add nothing)."""
    args = []
    for name, (opt, default) in PARAMS.items():
        v = cfg[name]
        if name == "preset":
            args += [opt, v] if v else []
            continue
        if cfg["preset"] and name in PRESET_SET and name not in swept:
            continue
        if name in NOT_SIMULATED or (name == "tag_bits" and v == "full") or not applies(name, cfg):
            continue
        args += [opt, v]
    return args


def run_command(hrpp, scene, cfg, res, swept, timing="cost-model", gpu=None, oracle=False,
                cpu_times=False, images=None):
    """The command of one configuration on one scene: `hrpp predict` (the cost model) or `hrpp
    simulate` (--timing simulate on GPU, with the oracle when ORACLE). The report comes on hrpp's
    standard output (--json -): no temporary file to leave behind when the sweep is
    interrupted."""
    if timing == "simulate":
        return ([hrpp, "simulate", scene, "--res", res, "--gpu", gpu, "--json", "-"]
                + simulate_args(cfg, swept) + ([] if oracle else ["--no-oracle"]))
    cmd = [hrpp, "predict", scene, "--res", res, "--timing", "cost-model", "--json",
           "-"] + predict_args(cfg, swept)
    if cpu_times:
        cmd.append("--measure-time")
    if images:
        cmd += ["--spec-images", images]
    return cmd


class Sweep:
    """One sweep's runs: every configuration of CONFIGS (from GRID) on every scene of SCENES
    (absolute paths), each one `hrpp predict` or `hrpp simulate` run (run_command), a task of the
    study driver (pyhrpp/study.py). IMAGES: the folder of the closest-spec runs' pictures."""

    def __init__(self, hrpp, scenes, grid, configs, res, timing="cost-model", gpu=None,
                 oracle=False, cpu_times=False, images=None):
        self.hrpp, self.scenes, self.grid, self.configs = hrpp, scenes, grid, configs
        self.res, self.timing, self.gpu, self.oracle = res, timing, gpu, oracle
        self.cpu_times, self.images = cpu_times, images
        self.swept = [n for n in grid if n != "preset"]
        # The swept parameters, named in each progress line.
        self.varied = [k for k in PARAMS if k in grid and len({c[k] for c in configs}) > 1]
        # task key -> (scene, configuration index), in task order (scene, then grid order).
        self.runs = {(pathlib.Path(s).stem, f"config {ci}"): (s, ci)
                     for s in scenes for ci in range(len(configs))}

    def identity(self, version):
        """What a journal's runs must share with this sweep (the study's identity; VERSION is
        hrpp's): --resume of another sweep is refused, naming the difference."""
        ident = {"scenes": " ".join(self.scenes), "res": self.res, "timing": self.timing,
                 "CPU times": "measured" if self.cpu_times else "not measured",
                 "gpu": self.gpu, "oracle": self.oracle, "images": self.images, "hrpp": version}
        ident.update({f"--param {n}": ",".join(self.grid[n]) if n in self.grid else "not swept"
                      for n in PARAMS})
        return ident

    def tasks(self):
        """The study's tasks, in the CSV's order. A run's record (what --resume compares besides
        its command) holds the preset and GPU files it reads."""
        out = []
        for key, (s, ci) in self.runs.items():
            cfg = self.configs[ci]
            images = None
            if self.images and cfg["mode"] == "closest-spec":
                images = os.path.join(self.images, f"{key[0]}-{ci:04d}")
            cmd = run_command(self.hrpp, s, cfg, self.res, self.swept, self.timing, self.gpu,
                              self.oracle, self.cpu_times, images)
            files = ([cfg["preset"]] if is_preset_file(cfg["preset"]) else []) + (
                [self.gpu] if self.gpu not in (None, "mobile", "desktop") else [])
            out.append(study.Task(key=key, cmd=cmd, files={}, report="stdout",
                                  record="".join(f"{f}:\n{pathlib.Path(f).read_text()}"
                                                 for f in files)))
        return out

    def rows_of(self, key, report):
        """The rows of one run's REPORT (hrpp's JSON)."""
        s, ci = self.runs[tuple(key)]
        if self.timing == "simulate":
            return simulated_rows_of(s, self.configs[ci], self.res, report)
        return rows_of(s, self.configs[ci], self.res, report, self.cpu_times)

    def rows(self, tasks, results):
        """Every row, in task order (scene, grid order, kind)."""
        return [r for t, res in zip(tasks, results) for r in self.rows_of(t.key, res.report)]

    def summary(self, task, result):
        """A run's progress words: its swept parameters, saved cycles and skipped nodes."""
        a = self.rows_of(task.key, result.report)[-1]
        cfg = self.configs[self.runs[task.key][1]]
        params = " ".join(f"{k}={cfg[k]}" for k in self.varied)
        return (f"({params}) saved {100 * a['saved_cycles']:.2f}% cycles, skipped "
                f"{100 * a['skipped_interior']:.2f}% nodes")


def simulated_rows_of(scene, cfg, res, data):
    """The rows of one `hrpp simulate` report: the columns of rows_of with simulated cycles
    (a kind's from its rays run alone, "all" from the mixed run), and SIM_COLUMNS. The predictor's
    statistics are the mixed run's (per kind, and summed over the kinds for "all"); the L1 hit
    rate and the stall cycles are the mixed run's, on the "all" row only."""
    stem = pathlib.Path(scene).stem
    kinds = dict(data["by_kind"])
    total = {"rays": data["rays"], "cycles": data["cycles"],
             "baseline_cycles": data["baseline_cycles"], "speedup": data["speedup"]}
    for f in ("true_positive", "false_positive", "false_negative", "skipped_walks",
              "wrong_results"):
        total[f] = sum(k[f] for k in kinds.values())
    counts = {w: {c: sum(k[w][c] for k in kinds.values()) for c in ("interior_tests", "tri_tests")}
              for w in ("baseline", "hrpp")}

    def frac(c):  # as PredictStats::to_json: 1 - hrpp / baseline
        b = counts["baseline"][c]
        return 1.0 - counts["hrpp"][c] / b if b else 0.0

    tp, fp, fn = total["true_positive"], total["false_positive"], total["false_negative"]
    total.update({"precision": tp / (tp + fp) if tp + fp else 0.0,
                  "recall": tp / (tp + fn) if tp + fn else 0.0,
                  "skipped_interior_fraction": frac("interior_tests"),
                  "skipped_tri_fraction": frac("tri_tests")})
    if "oracle" in data:
        total["oracle_speedup"] = data["oracle"]["speedup"]
    kinds["all"] = total
    rows = []
    for kind in sorted(kinds, key=KIND_ORDER.index):
        k = kinds[kind]
        rays = k["rays"]
        osp = k.get("oracle_speedup", "")
        r = {"scene": stem, "kind": kind, "res": res}
        r.update(cfg)
        r.update({
            "rays": rays,
            # An unbounded table has no size here (one table per unit, no count of entries used).
            "table_bytes": data["preset"]["table_bytes"] if cfg["table"] != "unbounded" else "",
            "table_entries": "",  # one table per RT unit: no single count of entries used
            "update_delay_rays": "",  # follows from the simulated occupancy
            **predictor_columns(k),
            "baseline_cycles_per_ray": k["baseline_cycles"] / rays if rays else 0.0,
            "hrpp_cycles_per_ray": k["cycles"] / rays if rays else 0.0,
            "saved_cycles": 1.0 - k["cycles"] / k["baseline_cycles"] if k["baseline_cycles"]
            else 0.0,
            "baseline_ns_per_ray": "", "hrpp_ns_per_ray": "",
            "image_mae": "", "image_differ": "", "spec_image": "",
            "timing": "simulate",
            "gpu": data["gpu"]["name"],
            "speedup": k["speedup"],
            "l1_hit_rate": data["l1_hit_rate"] if kind == "all" else "",
            "stall_cycles": data["predictor"]["stall_cycles"] if kind == "all" else "",
            "oracle_speedup": osp,
            "fraction_of_oracle": ((k["speedup"] - 1) / (osp - 1)
                                   if osp != "" and osp > 1 else ""),
        })
        rows.append(r)
    return rows


def predictor_columns(k):
    """The predictor's statistics columns of one kind's report (hrpp predict's or simulate's)."""
    rays, wrong = k["rays"], k["wrong_results"]
    return {
        "pred_precision": k["precision"], "pred_recall": k["recall"],
        "true_positive": k["true_positive"], "false_positive": k["false_positive"],
        "false_negative": k["false_negative"],
        "skipped_interior": k["skipped_interior_fraction"],
        "skipped_tri": k["skipped_tri_fraction"],
        "skipped_walks": k["skipped_walks"],
        "wrong_results": wrong,
        "wrong_fraction": wrong / rays if rays else 0.0,
        "accuracy": 1.0 - (wrong / rays if rays else 0.0),
    }


def rows_of(scene, cfg, res, data, timing):
    stem = pathlib.Path(scene).stem
    kinds = dict(data.get("by_kind", {}))
    kinds["all"] = data
    ie = data.get("image_error", {})
    rows = []
    for kind in sorted(kinds, key=KIND_ORDER.index):
        k = kinds[kind]
        rays = k["rays"]
        cost = k["cost"]
        r = {"scene": stem, "kind": kind, "res": res}
        r.update(cfg)
        r.update({
            "rays": rays,
            "table_bytes": data["table_bytes"],
            "table_entries": data["table_entries"],
            "update_delay_rays": data["config"]["update_delay"],
            **predictor_columns(k),
            "baseline_cycles_per_ray": cost["baseline_cycles_per_ray"],
            "hrpp_cycles_per_ray": cost["hrpp_cycles_per_ray"],
            "saved_cycles": cost["saved_cycle_fraction"],
            "baseline_ns_per_ray": k["baseline_ns"] / rays if timing and rays else "",
            "hrpp_ns_per_ray": k["hrpp_ns"] / rays if timing and rays else "",
            # The image error is of the primary rays' picture: on the primary and "all" rows.
            "image_mae": ie.get("mean_abs_error", "") if kind in ("primary", "all") else "",
            "image_differ": ie.get("differing_pixel_fraction", "") if kind in ("primary", "all")
            else "",
            "spec_image": ie.get("image", "") if kind in ("primary", "all") else "",
        })
        rows.append(r)
    return rows


def fmt(v):
    if isinstance(v, float):
        return repr(round(v, 9))
    return str(v)


def write_csv(path, rows, simulated=False):
    # dir_code only when a row has another code than the grid: every other CSV as before.
    params = [n for n in PARAMS if n != "dir_code" or any(r["dir_code"] != "grid" for r in rows)]
    cols = ["scene", "kind", "res"] + params + RESULT_COLUMNS
    if simulated:
        cols += SIM_COLUMNS
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    for r in rows:
        w.writerow([fmt(r[c]) for c in cols])
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(path, buf.getvalue())


def timing_of(r):
    """What a row's time axis is: 'cost model' or 'simulated, GPU'."""
    return "cost model" if r["timing"] == "cost-model" else f"simulated, {r['gpu']}"


def read_csv(paths):
    """Rows of several CSVs; a scene x configuration x kind met again (e.g. the untimed default in
    two sweeps) is kept once, as first read. Rows of different time axes (the cost model, or
    simulated cycles on a GPU) are an error: their cycles are not comparable."""
    rows = []
    seen = set()
    axes = {}
    for p in paths:
        with open(p, newline="") as f:
            for r in csv.DictReader(f):
                r.setdefault("preset", "")  # a CSV from before presets could be swept
                r.setdefault("dir_code", "grid")  # written only when a row has another code
                if r.get("timing") is None:  # a cost-model CSV
                    r.update({c: "" for c in SIM_COLUMNS})
                    r["timing"] = "cost-model"
                axes.setdefault(timing_of(r), p)
                if len(axes) > 1:
                    (a, pa), (b, pb) = list(axes.items())[:2]
                    raise BadInput(f"{pa} has cycles of the {a}, {pb} of the {b}: cycles of "
                                   "different timings are not comparable; report them separately")
                for c in SIM_NUMERIC:
                    if r[c] != "":
                        r[c] = float(r[c])
                key = (r["scene"], r["kind"], r["res"]) + tuple(r[n] for n in PARAMS)
                if key in seen:
                    continue
                seen.add(key)
                for c in RESULT_COLUMNS:
                    if r.get(c, "") != "" and c != "spec_image":
                        r[c] = float(r[c])
                rows.append(r)
    return rows


# ---- Pareto fronts -------------------------------------------------------------------------------

def pareto_front(points, minimize=(), maximize=()):
    """Indices of the points no other point dominates (at least as good in every objective and
    better in one). points: dicts (or sequences) indexed by the objective keys. Sorted by the
    first objective."""
    def key(p):
        return tuple(p[m] for m in minimize) + tuple(-p[m] for m in maximize)
    keys = [key(p) for p in points]
    front = []
    for i, ki in enumerate(keys):
        dominated = any(all(a <= b for a, b in zip(kj, ki)) and kj != ki
                        for j, kj in enumerate(keys) if j != i)
        if not dominated:
            front.append(i)
    return sorted(front, key=lambda i: keys[i])


# ---- plots and report ----------------------------------------------------------------------------

# Parameters that mean nothing for the other hash variant.
UNUSED = {"faithful": ("origin_bits", "dir_bits", "dir_code"),
          "improved": ("precision", "exp_bits"), "micro21": ("precision", "exp_bits", "dir_code")}


def with_baselines(pts):
    """The points plus, per workload (spp), the baseline walk without a predictor: exact, at the
    baseline's cycles. A configuration slower than it is never worth building."""
    base = {}
    for p in pts:
        base.setdefault(p["spp"], p)
    out = list(pts)
    for spp, p in base.items():
        b = {n: "" for n in p}
        b.update({"scene": p["scene"], "kind": p["kind"], "spp": spp, "baseline": True,
                  "hrpp_cycles_per_ray": p["baseline_cycles_per_ray"],
                  "baseline_cycles_per_ray": p["baseline_cycles_per_ray"], "accuracy": 1.0,
                  "saved_cycles": 0.0})
        out.append(b)
    return out


def preset_name(v):
    """A preset as labels show it: its name, or a FILE.json's stem."""
    return pathlib.Path(v).stem if is_preset_file(v) else v


def label(r, varied):
    """A configuration in words: its preset's name (when it has one) and the swept parameters."""
    if r.get("baseline"):
        return f"no predictor (the baseline walk, spp={r['spp']})"
    shown = [n for n in varied if n not in UNUSED.get(r["hash"], ()) and n != "preset"]
    words = [preset_name(r["preset"])] if r.get("preset") else []
    return " ".join(words + [f"{n}={r[n]}" for n in shown]) or "default"


def query(r):
    """Rows answer the same query when this matches: any-hit kinds, or every ray in mode anyhit
    (the study's hit-any column), against closest hits. Fronts compare like with like."""
    return "any-hit" if r["mode"] == "anyhit" or r["kind"] in ("shadow", "ao") else "closest-hit"


def varied_params(rows):
    """The parameters that take more than one value: among the rows of one preset (a parameter
    that differs only between presets is the presets' doing, and their names say it)."""
    by = {}
    for r in rows:
        by.setdefault(r["preset"], []).append(r)
    return [n for n in PARAMS if len({r[n] for r in rows}) > 1 and (
        n == "preset" or any(len({r[n] for r in v}) > 1 for v in by.values()))]


def groups(rows, by_query=False):
    out = {}
    for r in rows:
        key = (r["scene"], r["kind"]) + ((query(r),) if by_query else ())
        out.setdefault(key, []).append(r)
    return out


def simulated_on(rows):
    """The GPU of simulated rows ('mobile', ...), None for the cost model's (read_csv admits one
    time axis per set of rows)."""
    return rows[0]["gpu"] if rows and rows[0]["timing"] == "simulate" else None


# The plots' limits: a page holds at most this many scenes (rows or columns of panels), lines
# (configurations) and configurations of the time summary; the rest go on further pages
# (NAME-2.png, ...).
PAGE_SCENES = 3
PAGE_LINES = 12
PAGE_CONFIGS = 40
TABLE_MARKERS = "os^vDPXhp<>"


def fixed_config(rows):
    """The configuration every row shares (the parameters not swept), in words: what a plot's
    title names besides its scenes."""
    r = rows[0]
    fixed = [n for n in PARAMS if len({x[n] for x in rows}) == 1 and n != "preset"
             and n not in UNUSED.get(r["hash"], ())
             and not (n == "tag_bits" and r["table"] == "unbounded")
             and not (n == "update_delay" and r["latency"] != "none")]
    words = [f"preset {preset_name(r['preset'])}"] if len({x["preset"] for x in rows}) == 1 \
        and r["preset"] else []
    words += [f"{n}={r[n]}" for n in fixed if not (r["preset"] and n in PRESET_SET)]
    res = sorted({x["res"] for x in rows})
    return "fixed: " + " ".join(words) + f"; {'/'.join(res)} pixels"


def time_axis(gpu):
    return "cost model" if gpu is None else f"simulated, {gpu} GPU"


def saved_words(r):
    """A row's time figure in words: `saves 3.10%` or `costs 6.60% time` (cost model), with the
    speed-up when simulated (`1.05x, saves 4.76%`, `0.94x: costs 6.38% time`)."""
    s = r["saved_cycles"]
    words = f"saves {pct(s)}" if s >= 0 else f"costs {pct(-s)} time"
    if r.get("speedup", "") != "":
        return f"{r['speedup']:.3f}x, {words}"
    return words


def config_labels(rows, varied):
    """{configuration key: label}, the configurations in grid (CSV) order."""
    out = {}
    for r in rows:
        out.setdefault(config_key(r), label(r, varied))
    return out


def config_key(r):
    return tuple(r[n] for n in PARAMS)


def layout_overlaps(fig):
    """Pairs of a figure's title, panels and legends whose boxes overlap (none in a readable
    figure): [(what, what)]. Checked on every plot written; sweep.Plots asserts there are none."""
    fig.canvas.draw()
    rend = fig.canvas.get_renderer()
    boxes = []
    if fig._suptitle is not None and fig._suptitle.get_text():
        boxes.append(("title", fig._suptitle.get_window_extent(rend)))
    for i, ax in enumerate(fig.axes):
        if ax.get_visible():
            boxes.append((f"panel {i} ({ax.get_title()})", ax.get_tightbbox(rend)))
    for i, leg in enumerate(fig.legends):
        boxes.append((f"legend {i}", leg.get_window_extent(rend)))
    out = []
    edge = fig.bbox
    for a, ba in boxes:  # cut off at the figure's edge
        if ba.x0 < edge.x0 - 1 or ba.y0 < edge.y0 - 1 or ba.x1 > edge.x1 + 1 \
                or ba.y1 > edge.y1 + 1:
            out.append((a, "the figure's edge"))
    for i, (a, ba) in enumerate(boxes):
        for b, bb in boxes[i + 1:]:
            if a.startswith("panel") and b.startswith("panel"):
                continue  # panels' tick labels may touch; titles and legends must not
            w = min(ba.x1, bb.x1) - max(ba.x0, bb.x0)
            h = min(ba.y1, bb.y1) - max(ba.y0, bb.y0)
            if w > 1 and h > 1:
                out.append((a, b))
    return out


LAYOUT_PROBLEMS = {}  # file name -> layout_overlaps of the last plot_all
PLOT_TEXT = {}  # file name -> its title, axis labels, tick labels and legend text (for tests)


def plot_all(rows, outdir):
    """Writes the plots (the first one leads with time) and returns their paths. Each names its
    scenes, the fixed configuration and the units of its axes; large sweeps go on pages."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    outdir = pathlib.Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    files = []
    LAYOUT_PROBLEMS.clear()
    PLOT_TEXT.clear()
    allrows = [r for r in rows if r["kind"] == "all"]
    scenes = sorted({r["scene"] for r in rows})
    kinds = [k for k in KIND_ORDER if any(r["kind"] == k for r in rows)]
    varied = varied_params(rows)
    gpu = simulated_on(rows)
    fixed = fixed_config(rows)
    labels = config_labels(allrows, varied)

    def pages(items, n):
        return [items[i:i + n] for i in range(0, len(items), n)] or [[]]

    def page_name(name, i):
        return f"{name}.png" if i == 0 else f"{name}-{i + 1}.png"

    def title(fig, what, page_scenes, page=None):
        head = what + (f" (page {page[0] + 1} of {page[1]})" if page and page[1] > 1 else "")
        width = int(fig.get_figwidth() * 72 / (9 * 0.62))  # characters of 9 points
        fig.suptitle("\n".join(textwrap.wrap(head, width)) + "\n"
                     + "\n".join(textwrap.wrap("scenes: " + ", ".join(page_scenes), width))
                     + "\n" + "\n".join(textwrap.wrap(fixed, width)), fontsize=9)

    def save(fig, name):
        p = outdir / name
        LAYOUT_PROBLEMS[name] = layout_overlaps(fig)
        axes = [ax for ax in fig.axes if ax.get_visible()]
        PLOT_TEXT[name] = {
            "title": fig._suptitle.get_text(),
            "xlabels": [ax.get_xlabel() for ax in axes if ax.get_label() != "<colorbar>"],
            "ylabels": [ax.get_ylabel() for ax in axes],
            "ticks": [t.get_text() for ax in axes for t in ax.get_xticklabels()
                      + ax.get_yticklabels()],
            "texts": [t.get_text() for ax in axes for t in ax.texts],
            "legends": [(leg.get_title().get_text(), [t.get_text() for t in leg.get_texts()])
                        for leg in fig.legends]}
        fig.savefig(p, dpi=80)
        plt.close(fig)
        files.append(p)

    # 1. Time first: saved cycles per configuration and scene, those that cost time in red.
    order = sorted(labels, key=lambda c: -sum(r["saved_cycles"] for r in allrows
                                              if config_key(r) == c))
    by = {(r["scene"], config_key(r)): r for r in allrows}
    cfg_pages = pages(order, PAGE_CONFIGS)
    for pi, cfgs in enumerate(cfg_pages):
        longest = max([len(labels[c]) for c in cfgs] + [10])
        fig, ax = plt.subplots(figsize=(max(7.0, 2.4 + 0.065 * longest + 1.3 * len(scenes)),
                                        2.8 + 0.28 * len(cfgs)), layout="constrained")
        vals = [[100 * by[(s, c)]["saved_cycles"] if (s, c) in by else math.nan
                 for s in scenes] for c in cfgs]
        lim = max([abs(v) for row in vals for v in row if not math.isnan(v)] + [0.1])
        im = ax.imshow(vals, cmap="RdBu_r", vmin=-lim, vmax=lim, aspect="auto")
        for i, row in enumerate(vals):
            for j, v in enumerate(row):
                if not math.isnan(v):
                    ax.text(j, i, f"saves {v:.2f}%" if v >= 0 else f"costs {-v:.2f}%",
                            ha="center", va="center", fontsize=7,
                            color="white" if abs(v) > 0.6 * lim else "black")
        ax.set_xticks(range(len(scenes)), scenes, fontsize=8)
        ax.set_yticks(range(len(cfgs)), [labels[c] for c in cfgs], fontsize=7)
        ax.set_xlabel("scene", fontsize=8)
        ax.set_ylabel("configuration (best on average first)", fontsize=8)
        cb = fig.colorbar(im, ax=ax, shrink=0.8)
        cb.set_label(f"cycles saved, % of the baseline walk's ({time_axis(gpu)}); blue: costs "
                     "time, red: saves (as in hrpp render's net_cycles.png)", fontsize=7)
        cb.ax.tick_params(labelsize=7)
        title(fig, f"time: cycles saved per configuration, all rays ({time_axis(gpu)})",
              scenes, (pi, len(cfg_pages)))
        save(fig, page_name("time_saved", pi))

    # 2. Correct answers against time; colour = mode, marker = table size (unbounded: its own).
    modes = [m for m in ("anyhit", "closest-exact", "closest-spec") if any(r["mode"] == m
                                                                          for r in rows)]
    mode_colour = {"anyhit": "tab:green", "closest-exact": "tab:blue",
                   "closest-spec": "tab:orange"}
    tables = sorted({r["table"] for r in rows if r["table"] != "unbounded"},
                    key=lambda t: tuple(int(x) for x in t.split("x")))
    table_marker = {t: TABLE_MARKERS[i % len(TABLE_MARKERS)] for i, t in enumerate(tables)}
    table_marker["unbounded"] = "*"
    g = groups(rows)
    rest = [n for n in varied if n not in ("mode", "table")]
    scene_pages = pages(scenes, PAGE_SCENES)
    for pi, ps in enumerate(scene_pages):
        fig, axes = plt.subplots(len(ps), len(kinds), squeeze=False, layout="constrained",
                                 figsize=(3.2 * len(kinds), 2.6 * len(ps) + 1.6))
        for i, s in enumerate(ps):
            for j, k in enumerate(kinds):
                ax = axes[i][j]
                pts = g.get((s, k), [])
                if not pts:
                    ax.set_visible(False)
                    continue
                for p in pts:
                    ax.scatter(p["hrpp_cycles_per_ray"], p["accuracy"], s=30, alpha=0.75,
                               c=mode_colour[p["mode"]], marker=table_marker[p["table"]],
                               edgecolors="black" if p["table"] == "unbounded" else "none",
                               linewidths=0.5)
                for q, style in (("closest-hit", "r-"), ("any-hit", "g--")):
                    sub = [p for p in pts if query(p) == q]
                    if not sub:
                        continue
                    sub = with_baselines(sub)
                    front = [sub[f] for f in pareto_front(sub, ["hrpp_cycles_per_ray"],
                                                          ["accuracy"])]
                    ax.plot([p["hrpp_cycles_per_ray"] for p in front],
                            [p["accuracy"] for p in front], style, lw=1)
                    ax.axvline(sub[0]["baseline_cycles_per_ray"], color="grey", ls=":", lw=1)
                ax.set_title(f"{s} / {k} rays", fontsize=8)
                ax.set_xlabel(f"cycles per ray ({time_axis(gpu)})", fontsize=7)
                ax.set_ylabel("correct answers (fraction)", fontsize=7)
                ax.tick_params(labelsize=7)
        handles = ([Patch(color=mode_colour[m], label=m) for m in modes]
                   + [Line2D([], [], ls="", marker=table_marker[t], c="grey",
                             mec="black" if t == "unbounded" else "grey", label=t)
                      for t in tables + (["unbounded"] if any(r["table"] == "unbounded"
                                                                for r in rows) else [])]
                   + [Line2D([], [], c="r", label="Pareto front, closest-hit queries"),
                      Line2D([], [], c="g", ls="--", label="Pareto front, any-hit queries"),
                      Line2D([], [], c="grey", ls=":", label="baseline walk (no predictor)")])
        fig.legend(handles=handles, loc="outside lower center", ncol=min(6, len(handles)),
                   fontsize=7, title="colour: mode; marker: table (SETSxWAYS)"
                   + (f"; not told apart: {', '.join(rest)}" if rest else ""),
                   title_fontsize=7)
        title(fig, f"correct answers vs cycles per ray ({time_axis(gpu)})", ps,
              (pi, len(scene_pages)))
        save(fig, page_name("accuracy_vs_time", pi))

    # 3. Skipped work against table bytes: colour = hash (or preset), marker = mode, one column
    # of panels per update delay (or latency) when swept; unbounded tables apart, at the right.
    facet = next((n for n in ("latency", "update_delay") if n in varied), None)
    colour_by = next((n for n in varied if n not in ("mode", "table", facet)), "hash")
    colour_vals = sorted({r[colour_by] for r in allrows},
                         key=lambda v: (0, int(v), "") if v.isdigit() else (1, 0, v))
    colour = {v: f"C{i % 10}" for i, v in enumerate(colour_vals)}
    mode_marker = {"anyhit": "^", "closest-exact": "o", "closest-spec": "s"}
    facet_vals = (sorted({r[facet] for r in allrows}, key=lambda v: -1 if v == "none" else int(v))
                  if facet else [None])
    for pi, ps in enumerate(scene_pages):
        fig, axes = plt.subplots(len(ps), len(facet_vals), squeeze=False, layout="constrained",
                                 figsize=(max(5.0, 3.6 * len(facet_vals)), 2.8 * len(ps) + 1.6))
        fin_bytes = [r["table_bytes"] for r in allrows if r["table"] != "unbounded"
                     and r["table_bytes"] != ""]
        unb_x = max(fin_bytes) * 4 if fin_bytes else 1.0
        for i, s in enumerate(ps):
            for j, fv in enumerate(facet_vals):
                ax = axes[i][j]
                pts = [r for r in allrows if r["scene"] == s and (facet is None or r[facet] == fv)]
                for p in pts:
                    unb = p["table"] == "unbounded"
                    if not unb and p["table_bytes"] == "":
                        continue
                    ax.scatter(unb_x if unb else p["table_bytes"], 100 * p["skipped_interior"],
                               s=30, alpha=0.75, c=colour[p[colour_by]],
                               marker=mode_marker[p["mode"]])
                ax.set_xscale("log")
                ax.minorticks_off()
                lo, hi = (min(fin_bytes) / 1.6, max(fin_bytes) * 1.6) if fin_bytes else (1, 2)
                ticks = [m * 10.0 ** e for e in range(math.floor(math.log10(lo)),
                                                      math.ceil(math.log10(hi)) + 1)
                         for m in (1, 2, 5) if lo <= m * 10.0 ** e <= hi]
                names = [f"{b / 1e3:g} KB" if b >= 1000 else f"{b:.0f} B" for b in ticks]
                if any(p["table"] == "unbounded" for p in pts):
                    ax.axvline(unb_x / 2, color="grey", lw=0.8, ls="--")
                    ticks.append(unb_x)
                    names.append("unbounded\n(no fixed size)")
                ax.set_xticks(ticks, names, fontsize=6)
                ax.set_xlim(lo, max(ticks) * 1.6)
                ax.set_title(s + (f" / {facet}={fv}" if facet else ""), fontsize=8)
                ax.set_xlabel("table size, bytes (log scale); unbounded apart", fontsize=7)
                ax.set_ylabel("interior-node tests skipped, % (net)", fontsize=7)
                ax.tick_params(labelsize=7)
        handles = ([Patch(color=colour[v], label=preset_name(v) if colour_by == "preset"
                          else f"{colour_by}={v}") for v in colour_vals]
                   + [Line2D([], [], ls="", marker=mode_marker[m], c="grey", label=m)
                      for m in modes])
        rest3 = [n for n in varied if n not in (colour_by, "mode", "table", facet)]
        fig.legend(handles=handles, loc="outside lower center", ncol=min(6, len(handles)),
                   fontsize=7, title=f"colour: {colour_by}; marker: mode"
                   + (f"; panels: {facet}" if facet else "")
                   + (f"; not told apart: {', '.join(rest3)}" if rest3 else ""),
                   title_fontsize=7)
        title(fig, "interior-node tests skipped vs table size, all rays", ps,
              (pi, len(scene_pages)))
        save(fig, page_name("skipped_vs_bytes", pi))

    # 4. Prediction precision and recall against the update delay (all rays): one column of
    # panels per scene, a row each for precision and recall, a line per configuration.
    lines3 = {k: v for k, v in delay_groups(rows).items() if k[1] == "all"}
    if lines3:
        others = sorted({o for (_, _, o) in lines3})
        names = [n for n in PARAMS if n not in ("update_delay", "latency")]
        vary = [i for i, n in enumerate(names) if len({o[i] for o in others}) > 1]

        def line_label(o):
            r = dict(zip(names, o))
            words = [preset_name(r["preset"])] if r["preset"] else []
            return " ".join(words + [f"{names[v]}={o[v]}" for v in vary
                                     if names[v] != "preset"]) or "default"

        line_pages = [(ps, os_) for ps in pages(scenes, PAGE_SCENES + 1)
                      for os_ in pages(others, PAGE_LINES)]
        for pi, (ps, os_) in enumerate(line_pages):
            longest = max(len(line_label(o)) for o in os_)
            width = max(5.0, 3.6 * len(ps), 0.075 * longest + 1.0)
            ncol = max(1, min(3, int(width / (0.075 * longest + 0.8))))
            fig, axes = plt.subplots(2, len(ps), squeeze=False, layout="constrained",
                                     figsize=(width, 5.6 + 0.16 * math.ceil(len(os_) / ncol)))
            colours = {o: f"C{i % 10}" for i, o in enumerate(os_)}
            for j, s in enumerate(ps):
                for i, (what, col) in enumerate((("prediction precision", "pred_precision"),
                                                 ("recall", "pred_recall"))):
                    ax = axes[i][j]
                    for o in os_:
                        pts = lines3.get((s, "all", o))
                        if not pts:
                            continue
                        ax.plot([max(0.5, p["update_delay_rays"]) for p in pts],
                                [p[col] for p in pts], "o-", ms=3, c=colours[o])
                    ax.set_xscale("log")
                    ax.set_ylim(-0.02, 1.02)
                    ax.set_title(f"{s}: {what}", fontsize=8)
                    ax.set_xlabel("update delay, rays (log; 0 drawn at 0.5)", fontsize=7)
                    ax.set_ylabel(f"{what} (fraction)", fontsize=7)
                    ax.tick_params(labelsize=7)
            handles = [Line2D([], [], marker="o", ms=3, c=colours[o], label=line_label(o))
                       for o in os_]
            fig.legend(handles=handles, loc="outside lower center", ncol=ncol, fontsize=7,
                       title="configuration (colour)", title_fontsize=7)
            title(fig, "prediction precision and recall vs the update delay, all rays", ps,
                  (pi, len(line_pages)))
            save(fig, page_name("hit_rate_vs_latency", pi))

    # 5. Speculative image error against time saved; the region where prediction costs time
    # shaded.
    spec = [r for r in allrows if r["mode"] == "closest-spec" and r["image_mae"] != ""]
    if spec:
        fig, ax = plt.subplots(figsize=(6, 4.6), layout="constrained")
        xs = [100 * p["saved_cycles"] for p in spec]
        lo = min(xs + [0.0])
        if lo < 0:
            ax.axvspan(lo * 1.1 - 0.1, 0, color="tab:red", alpha=0.08, lw=0)
            ax.text(lo * 0.55, 0.98, "costs time", transform=ax.get_xaxis_transform(),
                    ha="center", va="top", fontsize=7, color="tab:red")
        ax.axvline(0, color="grey", lw=0.8)
        for s in scenes:
            pts = [r for r in spec if r["scene"] == s]
            ax.scatter([100 * p["saved_cycles"] for p in pts],
                       [100 * p["image_differ"] for p in pts], s=14, label=s)
        ax.set_xlabel(f"cycles saved, % of the baseline's (all rays; {time_axis(gpu)})",
                      fontsize=8)
        ax.set_ylabel("pixels that differ from the exact image, %", fontsize=8)
        ax.tick_params(labelsize=7)
        fig.legend(loc="outside lower center", ncol=min(4, len(scenes)), fontsize=7,
                   title="scene (colour)", title_fontsize=7)
        title(fig, "closest-spec: image error vs time saved", scenes)
        save(fig, "spec_error_vs_saved.png")
    return files


def pct(x):
    return f"{100 * x:.2f}%"


def table_bytes(r):
    """A row's table bytes for a table cell: an unbounded table has no size (its entries used, when
    known, are not a size to compare with a fixed table's)."""
    if r["table"] == "unbounded":
        used = r.get("table_entries", "")
        return "unbounded" + (f" ({int(used):,} entries used)" if used != "" else "")
    return "-" if r["table_bytes"] == "" else f"{int(r['table_bytes']):,}"


def saved_cell(x):
    """Saved cycles for a table cell: `3.10%`, or `costs 6.60%` when prediction costs time."""
    return pct(x) if x >= 0 else f"costs {pct(-x)}"


def time_section(rows, varied, gpu):
    """The report's first table: every configuration's time figure on every scene (all rays),
    best on average first, those that cost time said so."""
    allrows = [r for r in rows if r["kind"] == "all"]
    scenes = sorted({r["scene"] for r in allrows})
    labels = config_labels(allrows, varied)
    by = {(r["scene"], config_key(r)): r for r in allrows}
    order = sorted(labels, key=lambda c: -sum(r["saved_cycles"] for r in allrows
                                              if config_key(r) == c))
    costs = [c for c in order if all(by[(s, c)]["saved_cycles"] < 0 for s in scenes
                                     if (s, c) in by)]
    what = ("the cost model's cycles per ray" if gpu is None
            else f"simulated cycles on the `{gpu}` GPU (speed-up = baseline / HRPP cycles)")
    out = [f"## Time: what each configuration saves (all rays; {what})", "",
           "Cycles saved against the baseline walk without a predictor; a configuration that "
           "takes longer than the baseline \"costs\" time. Best on average first."
           + (f" {len(costs)} of {len(order)} configurations cost time on every scene."
              if costs else ""), "",
           "| configuration | " + " | ".join(scenes) + " |", "|---|" + "---|" * len(scenes)]
    for c in order:
        out.append(f"| {labels[c]} | " + " | ".join(
            saved_words(by[(s, c)]) if (s, c) in by else "-" for s in scenes) + " |")
    return out + [""]


def report(rows, plots, path, command):
    varied = varied_params(rows)
    gpu = simulated_on(rows)
    time_is = ("Time is the cost model's cycles per ray (docs/cost_model.md; deterministic), and "
               "the golden model's measured CPU time per ray (noisy, reported only)."
               if gpu is None else
               f"Time is simulated cycles per ray on the `{gpu}` GPU (`hrpp simulate`, "
               "docs/timing_model.md; deterministic): per ray kind from that kind's rays run "
               "alone, \"all\" from the mixed run; not the cost model.")
    lines = [f"# HRPP sweep report", "",
             f"Regenerate with `{command}`.", "",
             time_is + " Accuracy: the share "
             "of correct answers (closest-spec answers that are not the closest hit, and in any-hit "
             "mode closest-hit rays answered with another hit, are wrong), prediction precision and "
             "recall, "
             "net skipped interior-node tests. Swept: " + (", ".join(varied) or "nothing") + ".", ""]
    lines += time_section(rows, varied, gpu)
    for p in plots:
        lines += [f"![{p.stem}]({os.path.relpath(p, pathlib.Path(path).parent)})", ""]
    lines += ["## Pareto-optimal configurations (cycles per ray vs correct answers)"
              + ("" if gpu is None else f" in simulated time ({gpu})"), "",
              "Per scene, ray kind and query: closest-hit queries (modes closest-exact and "
              "closest-spec) and any-hit queries (shadow and AO rays, and every ray in mode anyhit, "
              "the study's hit-any column) have different baselines and are not compared. The "
              "baseline walk without a predictor is a point too: a front that ends there says "
              "no exact configuration beats it.", ""]
    for (s, k, q), pts in sorted(groups(rows, by_query=True).items(),
                                 key=lambda x: (x[0][0], KIND_ORDER.index(x[0][1]), x[0][2])):
        pts = with_baselines(pts)
        front = [pts[i] for i in pareto_front(pts, ["hrpp_cycles_per_ray"], ["accuracy"])]
        lines += [f"### {s} / {k} / {q} queries", "",
                  ("| configuration | cycles/ray (baseline) | saved | correct | precision | recall "
                   "| skipped nodes | table bytes | CPU ns/ray base / HRPP |" if gpu is None else
                   f"| configuration | simulated cycles/ray, {gpu} (baseline) | saved | correct | "
                   "precision | recall | skipped nodes | table bytes | speed-up |"),
                  "|---|---|---|---|---|---|---|---|---|"]
        for p in front:
            if p.get("baseline"):
                lines.append(f"| {label(p, varied)} | {p['hrpp_cycles_per_ray']:.1f} | - | "
                             "100.00% | - | - | - | 0 | - |")
                continue
            cpu = (f"{p['baseline_ns_per_ray']:.0f} / {p['hrpp_ns_per_ray']:.0f}"
                   if p["hrpp_ns_per_ray"] != "" else "-")
            if gpu is not None:
                cpu = f"{p['speedup']:.3f}x"
            lines.append(
                f"| {label(p, varied)} | {p['hrpp_cycles_per_ray']:.1f} "
                f"({p['baseline_cycles_per_ray']:.1f}) | {saved_cell(p['saved_cycles'])} | "
                f"{pct(p['accuracy'])} | {p['pred_precision']:.3f} | {p['pred_recall']:.3f} | "
                f"{pct(p['skipped_interior'])} | {table_bytes(p)} | {cpu} |")
        lines.append("")
    lines += latency_section(rows, varied)
    lines += spec_section(rows, varied, path)
    lines += ["## Recommendation", ""] + recommend(rows, varied)
    pathlib.Path(path).parent.mkdir(parents=True, exist_ok=True)
    write_atomic(path, "\n".join(lines) + "\n")


def delay_groups(rows):
    """Rows run at more than one update delay, grouped by scene, kind and the other parameters."""
    g = {}
    for r in rows:
        other = tuple(r[n] for n in PARAMS if n not in ("update_delay", "latency"))
        g.setdefault((r["scene"], r["kind"], other), []).append(r)
    return {k: sorted(v, key=lambda r: r["update_delay_rays"]) for k, v in g.items()
            if len({r["update_delay_rays"] for r in v}) > 1}


def latency_section(rows, varied):
    """What the pipeline's update delay costs against the untimed model (delay 0)."""
    g = delay_groups(rows)
    if not g:
        return []
    shown = [n for n in varied if n not in ("update_delay", "latency")]
    out = ["## Pipeline latency against the untimed model", "",
           "Update delay: rays looked up between a ray's lookup and its table write (0: the "
           "untimed model; `latency=C`: the RTL's delay for a traversal engine taking C cycles, "
           "from the cycle model, at most 63 with the default 64 ray ids).", "",
           "| scene | kind | configuration | latency (cycles) | update delay (rays) | precision "
           "| recall | skipped nodes | saved cycles |", "|---|---|---|---|---|---|---|---|---|"]
    for (s, k, _), pts in sorted(g.items(), key=lambda x: (x[0][0], KIND_ORDER.index(x[0][1]),
                                                           x[0][2])):
        for p in pts:
            out.append(f"| {s} | {k} | {label(p, shown)} | {p['latency']} | "
                       f"{int(p['update_delay_rays'])} | {p['pred_precision']:.4f} | "
                       f"{p['pred_recall']:.4f} | {pct(p['skipped_interior'])} | "
                       f"{saved_cell(p['saved_cycles'])} |")
    return out + [""]


def spec_best(rows):
    """(scene, its closest-spec row of all rays with the most saved cycles), by scene."""
    spec = [r for r in rows if r["kind"] == "all" and r["mode"] == "closest-spec"]
    return [(s, max((r for r in spec if r["scene"] == s), key=lambda r: r["saved_cycles"]))
            for s in sorted({r["scene"] for r in spec})]


def spec_section(rows, varied, path):
    """Per scene, the closest-spec configuration that saves the most cycles: its wrong answers and
    image error, with its exact | speculative | difference picture when the sweep wrote one."""
    if not spec_best(rows):
        return []
    out = ["## Speculative closest hits at the configuration that saves the most time", "",
           "Image error of the primary rays' picture (base colour under a light at the eye; "
           "8-bit sRGB) against the exact one: mean absolute error over pixels and channels "
           "(0..1) and the share of pixels that differ.", "",
           "| scene | configuration | saved cycles | wrong answers (all rays) | MAE | pixels "
           "differ | picture |", "|---|---|---|---|---|---|---|"]
    pics = []
    for s, best in spec_best(rows):
        pic = best.get("spec_image", "")
        link = "-"
        if pic:
            rel = os.path.relpath(pic, pathlib.Path(path).parent)
            link = f"[png]({rel})"
            pics.append(f"![{s}]({rel})")
        out.append(f"| {s} | {label(best, varied)} | {saved_cell(best['saved_cycles'])} | "
                   f"{pct(best['wrong_fraction'])} | {best['image_mae']:.5f} | "
                   f"{pct(best['image_differ'])} | {link} |")
    return out + [""] + [p + "\n" for p in pics]


def smallest_tables(rows, varied):
    """Per unbounded-table configuration of all rays (sorted by scene): (its other parameters as
    {name: value}, the unbounded row, the smallest finite table's row keeping 90% of its saved
    cycles with the same other parameters, or None)."""
    allrows = [r for r in rows if r["kind"] == "all"]
    others = [n for n in varied if n != "table"]

    def key(r):
        return tuple(r[n] for n in others) + (r["scene"],)

    out = []
    unb = {key(r): r for r in allrows if r["table"] == "unbounded"}
    for kk, u in sorted(unb.items(), key=lambda x: x[0][::-1]):
        cands = sorted((r for r in allrows if r["table"] != "unbounded" and key(r) == kk),
                       key=lambda r: r["table_bytes"])
        best = next((r for r in cands if u["saved_cycles"] > 0
                     and r["saved_cycles"] >= 0.9 * u["saved_cycles"]), None)
        out.append(({n: u[n] for n in others}, u, best))
    return out


def deltas(rows):
    """What one more bit of precision (or origin or direction bit) or the next number of ways buys:
    the mean, min and max difference in saved cycles (all rays) over every pair of configurations
    of a scene that differ only there. [(what, [differences])], the swept ones only."""
    allrows = [r for r in rows if r["kind"] == "all"]
    out = []

    def delta(param, step_ok, what):
        d = []
        for a in allrows:
            for b in allrows:
                if a is b or a["scene"] != b["scene"]:
                    continue
                if any(a[n] != b[n] for n in PARAMS if n != param):
                    continue
                if step_ok(a[param], b[param]):
                    d.append(b["saved_cycles"] - a["saved_cycles"])
        if d:
            out.append((what, d))

    def int_step(a, b):
        return a.isdigit() and b.isdigit() and int(b) == int(a) + 1

    delta("precision", int_step, "one more bit of precision (P to P+1)")
    delta("origin_bits", int_step, "one more origin bit (improved hash)")
    delta("dir_bits", int_step, "one more direction bit (improved hash)")
    tables = sorted({r["table"] for r in allrows if "x" in r["table"]})

    def more_ways(a, b):  # same sets, the next larger number of ways swept
        if "x" not in a or "x" not in b:
            return False
        sa, wa = map(int, a.split("x"))
        sb, wb = map(int, b.split("x"))
        larger = sorted({int(t.split("x")[1]) for t in tables
                         if int(t.split("x")[0]) == sa and int(t.split("x")[1]) > wa})
        return sa == sb and larger and wb == larger[0]

    delta("table", more_ways, "the next number of ways (same sets)")
    return out


def delta_lines(rows):
    return [f"- {what}: {100 * sum(d) / len(d):+.2f} points of saved cycles on average "
            f"(min {100 * min(d):+.2f}, max {100 * max(d):+.2f}; {len(d)} pairs)"
            for what, d in deltas(rows)]


def recommend(rows, varied):
    """The smallest finite table keeping 90% of the unbounded table's cycle savings (same other
    parameters), and what one more bit of precision or one more way buys."""
    out = []
    smallest = smallest_tables(rows, varied)
    if smallest:
        out += ["Smallest table keeping 90% of the unbounded table's saved cycles (same other "
                "parameters):", "", "| scene | other parameters | unbounded saves | smallest "
                "table | its bytes | it saves |", "|---|---|---|---|---|---|"]
        for oth, u, best in smallest:
            oth = " ".join(f"{n}={v}" for n, v in oth.items()) or "-"
            if best is None:
                msg = ("none saves anything" if u["saved_cycles"] <= 0
                       else "none of the swept tables")
                out.append(f"| {u['scene']} | {oth} | {saved_cell(u['saved_cycles'])} | {msg} "
                           "| - | - |")
            else:
                out.append(f"| {u['scene']} | {oth} | {saved_cell(u['saved_cycles'])} | "
                           f"{best['table']} "
                           f"| {int(best['table_bytes']):,} | {pct(best['saved_cycles'])} |")
        out.append("")
    out += delta_lines(rows)
    if not out:
        out.append("(sweep `table` with `unbounded` and finite sizes, or `precision`, to get a "
                   "recommendation)")
    return out


# ---- docs/results.md's generated blocks ----------------------------------------------------------
# Summaries of the report's sections, between `<!-- BEGIN sweep-NAME -->` and `<!-- END
# sweep-NAME -->` in the page (--doc); the page's method and reading stay around them.

DOC_BLOCKS = ("sweep-pareto", "sweep-latency", "sweep-delay", "sweep-spec", "sweep-recommend")


def short_label(r):
    """A configuration in a few words: `P=p SxW MODE` (faithful hash), `improved o/d SxW Tt MODE`,
    with `lat C` (at the RTL pipeline's update delay for an engine latency of C cycles) or
    `delay N` (N rays of update delay); `no predictor` for the baseline walk."""
    if r.get("baseline"):
        return "no predictor"
    words = [f"improved {r['origin_bits']}/{r['dir_bits']}" if r["hash"] == "improved"
             else f"P={r['precision']}", r["table"]]
    if r.get("preset"):
        words = [preset_name(r["preset"]), r["table"]]
    if r["tag_bits"] != "full":
        words.append(f"T{r['tag_bits']}")
    words.append(r["mode"])
    if r["spp"] != PARAMS["spp"][1]:
        words.append(f"{r['spp']} spp")
    if r["latency"] != "none":
        words.append(f"lat {r['latency']}")
    elif r["update_delay"] != PARAMS["update_delay"][1]:
        words.append(f"delay {r['update_delay']}")
    return " ".join(words)


def doc_pareto(rows):
    """One row per scene, ray kind and query: the baseline and the Pareto front, equal points
    merged (`+N ties`), fronts of more than six points shortened to the fastest three and the
    most accurate two."""
    out = ["| scene | kind | query | baseline cycles/ray | Pareto front: configuration "
           "(cycles/ray, correct answers) |", "|---|---|---|---|---|"]
    for (s, k, q), pts in sorted(groups(rows, by_query=True).items(),
                                 key=lambda x: (x[0][0], KIND_ORDER.index(x[0][1]), x[0][2])):
        pts = with_baselines(pts)
        entries = []  # [point, ties]
        for i in pareto_front(pts, ["hrpp_cycles_per_ray"], ["accuracy"]):
            p = pts[i]
            if entries and all(entries[-1][0][m] == p[m]
                               for m in ("hrpp_cycles_per_ray", "accuracy")):
                entries[-1][1] += 1
                continue
            entries.append([p, 0])
        cells = [f"{short_label(p)}{f' +{n} ties' if n else ''} "
                 f"({p['hrpp_cycles_per_ray']:.0f}, {pct(p['accuracy'])})" for p, n in entries]
        if len(cells) > 6:
            cells = cells[:3] + [f"... {len(cells) - 5} more ..."] + cells[-2:]
        base = " / ".join(f"{b:.0f}" for b in sorted({p["baseline_cycles_per_ray"] for p in pts}))
        out.append(f"| {s} | {k} | {q} | {base} | {'; '.join(cells)} |")
    return out


def swept_against(rows, param, fixed):
    """Rows of all rays whose FIXED parameters have their defaults, grouped by scene and the other
    parameters, where PARAM takes more than one value: ({(scene, others): [rows]}, the other
    parameters that vary between the groups)."""
    sel = [r for r in rows if r["kind"] == "all"
           and all(r[n] == PARAMS[n][1] for n in fixed)]
    names = [n for n in PARAMS if n != param]
    g = {}
    for r in sel:
        g.setdefault((r["scene"], tuple(r[n] for n in names)), []).append(r)
    g = {kk: v for kk, v in g.items() if len({r[param] for r in v}) > 1}
    vary = [n for i, n in enumerate(names)
            if len({o[i] for (_, o) in g}) > 1]
    # By scene, then in the order of the sweep that varied PARAM (its first row off the default).
    first = {}
    for i, r in enumerate(rows):
        if r[param] != PARAMS[param][1]:
            first.setdefault((r["scene"], tuple(r[n] for n in names)), i)
    return dict(sorted(g.items(), key=lambda x: (x[0][0], first.get(x[0], -1)))), vary


def config_cell(r, vary):
    return r["mode"] if vary == ["mode"] else " ".join(f"{n}={r[n]}" for n in vary) or "default"


def doc_latency(rows):
    """The untimed model against the RTL pipeline's update delays (latency sweep), all rays."""
    g, vary = swept_against(rows, "latency", ["update_delay"])
    if not g:
        return []
    lats = sorted({r["latency"] for v in g.values() for r in v},
                  key=lambda c: -1 if c == "none" else int(c))

    def head(c):
        if c == "none":
            return "untimed"
        d = {int(r["update_delay_rays"]) for v in g.values() for r in v if r["latency"] == c}
        return f"{d.pop()} rays" if len(d) == 1 else f"latency {c}"

    heads = " / ".join(head(c) for c in lats)
    out = [f"| scene | {'mode' if vary == ['mode'] else 'configuration'} | precision: {heads} | "
           "recall | skipped interior tests | saved cycles |", "|---|---|---|---|---|---|"]
    for (s, _), pts in g.items():
        by = {r["latency"]: r for r in pts}

        def cells(f):
            return " / ".join(f(by[c]) if c in by else "-" for c in lats)

        out.append(f"| {s} | {config_cell(pts[0], vary)} | "
                   f"{cells(lambda r: format(r['pred_precision'], '.3f'))} | "
                   f"{cells(lambda r: format(r['pred_recall'], '.3f'))} | "
                   f"{cells(lambda r: format(100 * r['skipped_interior'], '.1f') + '%')} | "
                   f"{cells(lambda r: format(100 * r['saved_cycles'], '.1f') + '%')} |")
    return out


def doc_delay(rows):
    """Recall and saved cycles against the update delay in rays (untimed otherwise), all rays."""
    g, vary = swept_against(rows, "update_delay", ["latency"])
    if not g:
        return []
    delays = sorted({r["update_delay"] for v in g.values() for r in v}, key=int)
    heads = " / ".join(delays)
    out = [f"| scene | {'mode' if vary == ['mode'] else 'configuration'} | recall at {heads} "
           f"rays of delay | saved cycles at {heads} |", "|---|---|---|---|"]
    for (s, _), pts in g.items():
        by = {r["update_delay"]: r for r in pts}

        def cells(f):
            return " / ".join(f(by[d]) if d in by else "-" for d in delays)

        out.append(f"| {s} | {config_cell(pts[0], vary)} | "
                   f"{cells(lambda r: format(r['pred_recall'], '.3f'))} | "
                   f"{cells(lambda r: format(100 * r['saved_cycles'], '.1f') + '%')} |")
    return out


def doc_spec(rows):
    """Per scene, the closest-spec configuration that saves the most cycles (spec_section's
    choice; the report names it): its wrong answers and image error."""
    best = spec_best(rows)
    if not best:
        return []
    out = ["| scene | saved cycles | wrong answers (all rays) | mean absolute error (0..1) | "
           "pixels that differ |", "|---|---|---|---|---|"]
    for s, b in best:
        out.append(f"| {s} | {pct(b['saved_cycles'])} | "
                   f"{pct(b['wrong_fraction'])} | {b['image_mae']:.5f} | "
                   f"{pct(b['image_differ'])} |")
    return out


def doc_recommend(rows):
    """The smallest table keeping 90% of the unbounded table's saved cycles, one column per
    precision when it was swept, and what one more bit or way buys."""
    varied = varied_params(rows)
    smallest = smallest_tables(rows, varied)
    out = []
    if smallest:
        col = "precision" if "precision" in varied else None
        cols = sorted({o[col] for o, _, _ in smallest}, key=int) if col else [None]
        rest = [n for n in smallest[0][0] if n != col
                and len({o[n] for o, _, _ in smallest}) > 1]
        rowkey = {}
        for o, u, best in smallest:
            rowkey.setdefault((u["scene"],) + tuple(o[n] for n in rest), {})[o.get(col)] = (u, best)
        what = "mode" if rest == ["mode"] else "configuration"
        heads = " | ".join(f"P = {c}" for c in cols) if col else "smallest table"
        out += [f"| scene | {what} | {heads} |", "|---|---|" + "---|" * len(cols)]

        def cell(ub):
            if ub is None:
                return "-"
            u, best = ub
            if best is None:
                return ("none saves anything" if u["saved_cycles"] <= 0
                        else f"none of the swept tables (unbounded {pct(u['saved_cycles'])})")
            return (f"{best['table']}, {best['table_bytes'] / 1e3:.1f} KB: "
                    f"{pct(best['saved_cycles'])} of {pct(u['saved_cycles'])}")

        for kk, by in rowkey.items():
            out.append(f"| {kk[0]} | {' '.join(kk[1:]) or '-'} | "
                       + " | ".join(cell(by.get(c)) for c in cols) + " |")
        out.append("")
    out += delta_lines(rows)
    return out


def doc_blocks(rows):
    """The page's generated blocks (name -> Markdown) that these rows can fill."""
    blocks = {"sweep-pareto": doc_pareto(rows), "sweep-latency": doc_latency(rows),
              "sweep-delay": doc_delay(rows), "sweep-spec": doc_spec(rows),
              "sweep-recommend": doc_recommend(rows)}
    return {n: "\n".join(b) for n, b in blocks.items() if b}


def write_doc(path, rows):
    """Rewrites the sweep-* blocks of the page PATH that ROWS fill; every block must be marked in
    it. Returns the names of the blocks written."""
    path = pathlib.Path(path)
    if simulated_on(rows):
        raise BadInput("--doc: the page's sweep-* blocks are in cost-model cycles; rows in "
                       "simulated time go in a --report")
    if not path.is_file():
        raise BadInput(f"--doc {path}: no such file")
    text = path.read_text()
    missing = [n for n in DOC_BLOCKS if any(m not in text for m in markers(n))]
    if missing:
        raise BadInput(f"--doc {path}: no {', '.join(missing)} block (<!-- BEGIN NAME --> ... "
                       "<!-- END NAME -->)")
    blocks = doc_blocks(rows)
    update_blocks(path, blocks)
    return list(blocks)


def output_problem(path, folder):
    """Why PATH cannot be written (a file) or made (a folder), or None. Missing folders above it
    are created, so the nearest existing one must be a writable folder."""
    if path == "-":
        return "standard output is not supported for this option"
    p = pathlib.Path(path)
    if p.exists():
        if folder and not p.is_dir():
            return f"'{path}' is a file, not a folder"
        if not folder and p.is_dir():
            return f"'{path}' is a folder, not a file"
        if not os.access(p, os.W_OK | (os.X_OK if folder else 0)):
            return f"'{path}' is not writable"
        return None
    up = p.absolute().parent
    while not up.exists():
        up = up.parent
    if not up.is_dir():
        return f"'{up}' is not a folder"
    if not os.access(up, os.W_OK | os.X_OK):
        return f"the folder '{up}' is not writable"
    return None


def check_outputs(args):
    """Every output option, checked before any work (BadInput names the option, path and why)."""
    for opt, folder in (("csv", False), ("report", False), ("plots", True), ("images", True)):
        path = getattr(args, opt)
        if path is not None:
            why = output_problem(path, folder)
            if why:
                raise BadInput(f"--{opt} {path}: {why}")


def main():
    ap = argparse.ArgumentParser(prog="hrpp sweep", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*", help="glTF scenes (.glb)")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=V1,V2,...",
                    help="parameter values to sweep; names: " + ", ".join(PARAMS)
                    + "; preset takes the names `hrpp predict --help` lists (rtl-primary, "
                    "rtl-NAME, micro21, study2019) or FILE.json, passed as --preset, the other "
                    "swept parameters override its values")
    ap.add_argument("--res", default="64x64", help="image resolution WxH (default 64x64)")
    ap.add_argument("--spp", help="samples per pixel (same as --param spp=N)")
    ap.add_argument("--csv", help="CSV file to write (required unless --from-csv)")
    ap.add_argument("--plots", help="directory for the PNG plots")
    ap.add_argument("--report", help="markdown report to write (plots need --plots)")
    ap.add_argument("--doc", help="rewrite the sweep-* blocks of this page (docs/results.md) "
                                  "with summaries of the report's tables")
    ap.add_argument("--images", help="directory for each closest-spec run's exact | speculative | "
                                     "difference picture")
    ap.add_argument("--from-csv", nargs="+", help="plot and report these CSVs; run nothing")
    ap.add_argument("--timing", choices=("cost-model", "simulate"), default="cost-model",
                    help="the time axis: cost-model (hrpp predict's additive cost model, "
                         "docs/cost_model.md; the default) or simulate (hrpp simulate's cycles "
                         "on RT units with caches and warps, docs/timing_model.md; update_delay "
                         "and latency cannot be swept)")
    ap.add_argument("--gpu", help="--timing simulate: GPU configuration, mobile (default), "
                                  "desktop or a JSON file")
    ap.add_argument("--oracle", action="store_true",
                    help="--timing simulate: also simulate the oracle (columns oracle_speedup, "
                         "fraction_of_oracle; a third simulation of every configuration)")
    ap.add_argument("--no-timing", action="store_true",
                    help="do not measure CPU times (the CSV is then reproducible byte for byte)")
    ap.add_argument("--hrpp", default=str(ROOT / "build" / "hrpp"), help="the hrpp binary")
    ap.add_argument("--command", help=argparse.SUPPRESS)  # shown in the report
    study.add_arguments(ap)  # --workers, --scheduler, --no-dask, --resume: the journal is
    # CSV.journal.jsonl
    args = ap.parse_args()
    command = args.command or "hrpp sweep " + " ".join(sys.argv[1:])
    try:
        check_outputs(args)
        if args.from_csv:
            if args.scenes or args.param or args.csv or args.resume:
                raise BadInput("--from-csv runs nothing: no scenes, --param, --csv or --resume")
            if not (args.plots or args.report or args.doc):
                raise BadInput("--from-csv needs an output: --plots DIR, --report FILE or "
                               "--doc PAGE")
            for c in args.from_csv:
                if not os.path.isfile(c):
                    raise BadInput(f"--from-csv {c}: no such file")
            rows = read_csv(args.from_csv)
        else:
            if not args.scenes:
                raise BadInput("no scene given")
            if not args.csv:
                raise BadInput("--csv FILE is required")
            if args.timing == "simulate":
                if args.images:
                    raise BadInput("--images: hrpp simulate draws no pictures; use "
                                   "--timing cost-model")
                args.gpu = args.gpu or "mobile"
                if args.gpu not in ("mobile", "desktop"):
                    if not os.path.isfile(args.gpu):
                        raise BadInput(f"--gpu {args.gpu}: not mobile, desktop or a file")
                    args.gpu = os.path.abspath(args.gpu)  # workers may run elsewhere
            elif args.gpu or args.oracle:
                raise BadInput("--gpu and --oracle need --timing simulate")
            for s in args.scenes:
                if not os.path.isfile(s):
                    raise BadInput(f"{s}: no such scene file")
            params = list(args.param)
            if args.spp:
                if any(p.split("=")[0].strip() == "spp" for p in params):
                    raise BadInput("give spp either as --spp or as --param spp=...")
                params.append(f"spp={args.spp}")
            w, _, h = args.res.partition("x")
            if not (w.isdigit() and h.isdigit() and int(w) > 0 and int(h) > 0):
                raise BadInput(f"--res must be WIDTHxHEIGHT, got {args.res!r}")
            if not os.access(args.hrpp, os.X_OK):
                raise BadInput(f"{args.hrpp}: not an executable (build it: make build)")
            stems = [pathlib.Path(s).stem for s in args.scenes]
            twice = sorted({s for s in stems if stems.count(s) > 1})
            if twice:
                raise BadInput(f"two scenes named {twice[0]} (the CSV names scenes by file name)")
            grid = parse_params(params, args.timing)
            scenes = [os.path.abspath(s) for s in args.scenes]
            configs = expand(grid, check_presets(grid, args.hrpp, scenes[0]))
            simulated = args.timing == "simulate"
            sw = Sweep(args.hrpp, scenes, grid, configs, args.res, args.timing, args.gpu,
                       args.oracle, cpu_times=not args.no_timing and not simulated,
                       images=os.path.abspath(args.images) if args.images else None)
            tasks = sw.tasks()
            with study.Study("hrpp sweep", args.csv + ".journal.jsonl",
                             sw.identity(study.tool_version(args.hrpp)), args) as st:
                rows = sw.rows(tasks, st.run(tasks, summary=sw.summary))
                write_csv(args.csv, rows, simulated=simulated)
                st.complete()
            print(f"sweep: wrote {args.csv} ({len(rows)} rows, {len(configs)} configurations x "
                  f"{len(scenes)} scenes)", file=sys.stderr)
            rows = read_csv([args.csv])
    except (BadInput, study.StudyError) as e:
        print(f"hrpp sweep: {e}", file=sys.stderr)
        return 2
    plots = plot_all(rows, args.plots) if args.plots else []
    for p in plots:
        print(f"sweep: wrote {p}", file=sys.stderr)
    if args.report:
        report(rows, plots, args.report, command)
        print(f"sweep: wrote {args.report}", file=sys.stderr)
    if args.doc:
        try:
            names = write_doc(args.doc, rows)
        except BadInput as e:
            print(f"hrpp sweep: {e}", file=sys.stderr)
            return 2
        print(f"sweep: wrote {', '.join(names) or 'no'} blocks of {args.doc}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
