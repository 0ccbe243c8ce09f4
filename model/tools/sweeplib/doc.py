"""docs/results.md's generated blocks (--doc PAGE): summaries of the report's sections, between
`<!-- BEGIN sweep-NAME -->` and `<!-- END sweep-NAME -->` in the page; the page's method and
reading stay around them."""
import pathlib

from pyhrpp.docs import markers, update_blocks

from .labels import pct, preset_name, simulated_on, time_axis, varied_params
from .pareto import groups, pareto_front, with_baselines
from .report import delta_lines, smallest_tables, spec_best
from .tasks import KIND_ORDER, PARAMS, BadInput

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
    most accurate two. Simulated rows say so in the header (`baseline cycles/ray (simulated,
    mobile GPU)`) and show two decimals: a few cycles per ray, the units' throughput (the cost
    model's hundreds of cycles per ray show none)."""
    gpu = simulated_on(rows)
    axis, dp = ("", 0) if gpu is None else (f" ({time_axis(gpu)})", 2)
    out = [f"| scene | kind | query | baseline cycles/ray{axis} | Pareto front: configuration "
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
                 f"({p['hrpp_cycles_per_ray']:.{dp}f}, {pct(p['accuracy'])})"
                 for p, n in entries]
        if len(cells) > 6:
            cells = cells[:3] + [f"... {len(cells) - 5} more ..."] + cells[-2:]
        base = " / ".join(f"{b:.{dp}f}"
                          for b in sorted({p["baseline_cycles_per_ray"] for p in pts}))
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


def write_doc(path, rows, names=None):
    """Rewrites the sweep-* blocks of the page PATH that ROWS fill, or only the blocks NAMES
    (each of which the rows must fill: e.g. the fronts from a simulated grid, the latency blocks
    from cost-model sweeps); every block it may write must be marked in the page. Returns the
    names of the blocks written."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise BadInput(f"--doc {path}: no such file")
    text = path.read_text()
    missing = [n for n in names or DOC_BLOCKS if any(m not in text for m in markers(n))]
    if missing:
        raise BadInput(f"--doc {path}: no {', '.join(missing)} block (<!-- BEGIN NAME --> ... "
                       "<!-- END NAME -->)")
    blocks = doc_blocks(rows)
    if names:
        empty = [n for n in names if n not in blocks]
        if empty:
            raise BadInput(f"--doc-blocks: these rows fill no {', '.join(empty)} block")
        blocks = {n: b for n, b in blocks.items() if n in names}
    update_blocks(path, blocks)
    return list(blocks)
