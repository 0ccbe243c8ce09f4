"""The sweep's runs: the sweepable parameters and their grid, presets, the `hrpp predict` and
`hrpp simulate` command of a configuration, the runs as tasks of the study driver
(pyhrpp/study.py) with the sweep's identity, the rows of a run's report, and the CSV."""
import csv
import difflib
import io
import itertools
import json
import os
import pathlib
import re
import subprocess

from pyhrpp import study
from pyhrpp.files import write_atomic

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


def tool_args(cfg, swept, left_out):
    """The tool's options for a configuration: every parameter, or with a preset the preset and
    the parameters SWEPT beside it (the others are the preset's); LEFT_OUT(name, value): a
    parameter the tool is not given."""
    args = []
    for name, (opt, default) in PARAMS.items():
        v = cfg[name]
        if name == "preset":
            args += [opt, v] if v else []
            continue
        if cfg["preset"] and name in PRESET_SET and name not in swept:
            continue
        if left_out(name, v) or not applies(name, cfg):
            continue
        args += [opt, v]
    return args


def predict_args(cfg, swept=()):
    """hrpp predict's options for a configuration (tool_args). The latency, when given, sets the
    update delay (from the RTL's cycle model)."""
    return tool_args(cfg, swept, lambda name, v: (
        name in ("tag_bits", "latency") and v in ("full", "none")
        or name == "update_delay" and cfg["latency"] != "none"))


def simulate_args(cfg, swept=()):
    """hrpp simulate's options for a configuration: predict_args without the update delay and
    the pipeline latency (parse_params refuses sweeping them; their defaults add nothing)."""
    return tool_args(cfg, swept, lambda name, v: (
        name in NOT_SIMULATED or name == "tag_bits" and v == "full"))


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
