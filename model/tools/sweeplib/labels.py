"""Configurations and figures in words, for the plots, the report and the page's blocks."""
import pathlib

from .tasks import PARAMS, PRESET_SET, is_preset_file

# Parameters that mean nothing for the other hash variant.
UNUSED = {"faithful": ("origin_bits", "dir_bits", "dir_code"),
          "improved": ("precision", "exp_bits"), "micro21": ("precision", "exp_bits", "dir_code")}


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


def varied_params(rows):
    """The parameters that take more than one value: among the rows of one preset (a parameter
    that differs only between presets is the presets' doing, and their names say it)."""
    by = {}
    for r in rows:
        by.setdefault(r["preset"], []).append(r)
    return [n for n in PARAMS if len({r[n] for r in rows}) > 1 and (
        n == "preset" or any(len({r[n] for r in v}) > 1 for v in by.values()))]


def simulated_on(rows):
    """The GPU of simulated rows ('mobile', ...), None for the cost model's (read_csv admits one
    time axis per set of rows)."""
    return rows[0]["gpu"] if rows and rows[0]["timing"] == "simulate" else None


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
