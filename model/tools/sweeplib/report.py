"""The Markdown report (--report FILE): the time table first, the plots, the Pareto-optimal
configurations, the pipeline latency, the speculative mode's image error and a recommendation."""
import os
import pathlib

from pyhrpp.files import write_atomic

from .labels import (config_key, config_labels, label, pct, saved_cell, saved_words,
                     simulated_on, table_bytes, varied_params)
from .pareto import groups, pareto_front, with_baselines
from .tasks import KIND_ORDER, PARAMS

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
    dp = 1 if gpu is None else 2  # decimals of cycles per ray (simulated: a few per ray)
    time_is = ("Time is the cost model's cycles per ray (docs/cost_model.md; deterministic), and "
               "the golden model's measured CPU time per ray (noisy, reported only)."
               if gpu is None else
               f"Time is simulated cycles per ray on the `{gpu}` GPU (`hrpp simulate`, "
               "docs/timing_model.md; deterministic): per ray kind from that kind's rays run "
               "alone, \"all\" from the mixed run; not the cost model.")
    lines = ["# HRPP sweep report", "",
             f"Regenerate with `{command}`.", "",
             time_is + " Accuracy: the share of correct answers (closest-spec answers that are "
             "not the closest hit, and in any-hit mode closest-hit rays answered with another "
             "hit, are wrong), prediction precision and recall, net skipped interior-node tests. "
             "Swept: " + (", ".join(varied) or "nothing") + ".", ""]
    lines += time_section(rows, varied, gpu)
    for p in plots:
        lines += [f"![{p.stem}]({os.path.relpath(p, pathlib.Path(path).parent)})", ""]
    lines += ["## Pareto-optimal configurations (cycles per ray vs correct answers)"
              + ("" if gpu is None else f" in simulated time ({gpu})"), "",
              "Per scene, ray kind and query: closest-hit queries (modes closest-exact and "
              "closest-spec) and any-hit queries (shadow and AO rays, and every ray in mode "
              "anyhit, the study's hit-any column) have different baselines and are not compared. "
              "The baseline walk without a predictor is a point too: a front that ends there "
              "says no exact configuration beats it.", ""]
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
                lines.append(f"| {label(p, varied)} | {p['hrpp_cycles_per_ray']:.{dp}f} | - | "
                             "100.00% | - | - | - | 0 | - |")
                continue
            cpu = (f"{p['baseline_ns_per_ray']:.0f} / {p['hrpp_ns_per_ray']:.0f}"
                   if p["hrpp_ns_per_ray"] != "" else "-")
            if gpu is not None:
                cpu = f"{p['speedup']:.3f}x"
            lines.append(
                f"| {label(p, varied)} | {p['hrpp_cycles_per_ray']:.{dp}f} "
                f"({p['baseline_cycles_per_ray']:.{dp}f}) | {saved_cell(p['saved_cycles'])} | "
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
           "from the cycle model, at most 63 with the default 64 ray ids). Both are the cost "
           "model's: `hrpp simulate` has neither to set (its table's staleness follows from the "
           "simulated rays in flight), so these rows are in cost-model cycles.", "",
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
    """(scene, its closest-spec row of all rays with the most saved cycles), by scene, among the
    rows with an image error (hrpp predict's; hrpp simulate draws no pictures)."""
    spec = [r for r in rows if r["kind"] == "all" and r["mode"] == "closest-spec"
            and r["image_mae"] != ""]
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
