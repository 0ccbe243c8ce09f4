"""The plots (matplotlib; --plots DIR): time first, every plot naming its scenes, the fixed
configuration and its axes' units; large sweeps on further pages."""
import math
import pathlib
import textwrap

from .labels import (config_key, config_labels, fixed_config, preset_name, simulated_on,
                     time_axis, varied_params)
from .pareto import groups, pareto_front, query, with_baselines
from .report import delay_groups
from .tasks import KIND_ORDER, PARAMS

# The plots' limits: a page holds at most this many scenes (rows or columns of panels), lines
# (configurations) and configurations of the time summary; the rest go on further pages
# (NAME-2.png, ...).
PAGE_SCENES = 3
PAGE_LINES = 12
PAGE_CONFIGS = 40
TABLE_MARKERS = "os^vDPXhp<>"


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
