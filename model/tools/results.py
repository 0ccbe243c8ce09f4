#!/usr/bin/env python3
"""Regenerates the predictor tables of docs/results.md (run by `make results`).

For every shared scene it runs `build/hrpp predict` in the original study's Table 1
configuration (1024x1024, 8 spp, faithful hash with precision 6, unbounded table) and in the
finite-table configurations, writes every JSON report to out/results/, and replaces the text
between the `<!-- BEGIN name -->` / `<!-- END name -->` markers of docs/results.md.

Each run is a task of the study driver (pyhrpp/study.py): --workers N runs at a time on a local
Dask cluster (--jobs is the same option), --scheduler ADDRESS on a running one, --no-dask one
after another; the journal (--out)/journal.jsonl lets --resume continue an interrupted run.
A run that fails stops it (exit code 1; 2 when hrpp said bad input): an exact mode that answered
differently from the baseline walk (exact_mismatches, hrpp's exit code 1) fails `make results`.
"""
import argparse
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp import rtl_config as hrpp_config  # noqa: E402  (rtl/config/hrpp_configs.json)
from pyhrpp import study  # noqa: E402
from pyhrpp.docs import update_blocks  # noqa: E402

# The original study (Demoullin, Gubran, Aamodt 2019, Table 1): hit-any / closest-hit savings
# and the unbounded table sizes it reported.
STUDY = {
    "teapot": ("4%", "69%", "16 MB / 2 MB"),
    "killeroo": ("48%", "52%", "10.8 MB / 84 MB"),
    "happy_buddha": ("23%", "41%", "18 MB / 18 MB"),
}

# The study's hash; the RTL `primary` configuration's hash and finite table (the default
# configuration before issue 17's winner; the published tables are its).
RTL_PRIMARY = hrpp_config.config("primary")
FAITHFUL = ["--hash", "faithful", "--precision", "6", "--exp-bits", "3", "--combine", "xor"]
IMPROVED = hrpp_config.predict_args(RTL_PRIMARY, ("hash",))
UNBOUNDED = ["--table", "unbounded", "--nodes-per-entry", "2"]
FINITE = hrpp_config.predict_args(RTL_PRIMARY, ("table",))

# name -> predict arguments
RUNS = {
    "unbounded-anyhit": FAITHFUL + UNBOUNDED + ["--mode", "anyhit"],
    "unbounded-spec": FAITHFUL + UNBOUNDED + ["--mode", "closest-spec"],
    "unbounded-exact": FAITHFUL + UNBOUNDED + ["--mode", "closest-exact"],
    "finite-faithful-anyhit": FAITHFUL + FINITE + ["--mode", "anyhit"],
    "finite-faithful-spec": FAITHFUL + FINITE + ["--mode", "closest-spec"],
    "finite-improved-anyhit": IMPROVED + FINITE + ["--mode", "anyhit"],
    "finite-improved-spec": IMPROVED + FINITE + ["--mode", "closest-spec"],
}


def tasks(scenes, res, spp, out):
    """One `hrpp predict` run per scene and configuration of RUNS, its report OUT/SCENE-NAME.json
    (an exact mode answering differently from the baseline walk exits 1: a failed run)."""
    hrpp = ROOT / "build" / "hrpp"
    return [study.Task(key=(pathlib.Path(scene).stem, name),
                       cmd=[hrpp, "predict", scene, "--res", res, "--spp", spp,
                            "--timing", "cost-model", "--json", "{json}"] + RUNS[name],
                       files={"json": out / f"{pathlib.Path(scene).stem}-{name}.json"})
            for scene in scenes for name in RUNS]


def pct(x):
    return f"{100 * x:.1f}%"


def kind(data, k, key="skipped_interior_fraction"):
    bk = data.get("by_kind", {})
    return pct(bk[k][key]) if k in bk else "-"


def mb(n):
    return f"{n / 1e6:.1f} MB" if n >= 1e5 else f"{n / 1e3:.1f} KB"


def table1(stems, r, cmd):
    lines = [
        f"Regenerate with `{cmd}`. Skipped = 1 - HRPP interior-node tests (wasted predicted "
        "tests included) / baseline interior-node tests, over all rays of the workload "
        "(primary, shadow, ambient occlusion); per-kind figures in `out/results/*.json`.",
        "",
        "Any-hit mode answers primary rays as any-hit queries: its wrong answers are the primary "
        "rays whose answer is not their closest hit (the any-hit walk alone, without prediction, "
        "in brackets).",
        "",
        "| scene | study hit-any | ours any-hit (primary / shadow / AO; primary rays answered "
        "wrong) | study closest-hit "
        "| ours closest-spec (wrong answers) | ours closest-exact | study table | ours table "
        "(entries) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for s in stems:
        a, sp, ex = r[(s, "unbounded-anyhit")], r[(s, "unbounded-spec")], r[(s, "unbounded-exact")]
        st = STUDY.get(s, ("-", "-", "-"))
        wrong = sp["wrong_results"] / max(1, sp["rays"])
        lines.append(
            f"| {s} | {st[0]} | {pct(a['skipped_interior_fraction'])} ({kind(a, 'primary')} / "
            f"{kind(a, 'shadow')} / {kind(a, 'ao')}; {primary_wrong(a)}) | {st[1]} | "
            f"{pct(sp['skipped_interior_fraction'])} ({pct(wrong)}) | "
            f"{pct(ex['skipped_interior_fraction'])} | {st[2]} | "
            f"{mb(a['table_bytes'])} / {mb(sp['table_bytes'])} ({a['table_entries']:,}) |")
    mean = lambda name: sum(r[(s, name)]["skipped_interior_fraction"] for s in stems) / len(stems)
    lines += ["", f"Mean over these scenes: any-hit {pct(mean('unbounded-anyhit'))}, "
                  f"closest-spec {pct(mean('unbounded-spec'))}, closest-exact "
                  f"{pct(mean('unbounded-exact'))} (the study: 40% on average)."]
    return "\n".join(lines)


def primary_wrong(j):
    """Primary rays answered wrong (not their closest hit) in any-hit mode, and in brackets those
    the any-hit walk from the root answers wrong too."""
    p = j["by_kind"]["primary"]
    n = max(1, p["rays"])
    return f"{pct(p['wrong_results'] / n)} ({pct(p['baseline_wrong_results'] / n)})"


def finite(stems, r, cmd):
    lines = [
        f"Regenerate with `{cmd}`. Finite table: {RTL_PRIMARY['sets']} sets x "
        f"{RTL_PRIMARY['ways']} ways, {RTL_PRIMARY['nodes_per_entry']} node ids per entry, "
        f"{RTL_PRIMARY['tag_bits']}-bit stored tags, LRU; its size in bytes is counted from the "
        "field widths "
        "(docs/hash.md). Kept = finite skipped / unbounded skipped (same hash, same K = 2).",
        "",
        "| scene | mode | unbounded (faithful) | 8 KB faithful | kept | 8 KB improved | "
        "improved shadow / AO (faithful shadow / AO) | table bytes faithful / improved |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for s in stems:
        for mode in ("anyhit", "spec"):
            u = r[(s, f"unbounded-{mode}")]
            f = r[(s, f"finite-faithful-{mode}")]
            i = r[(s, f"finite-improved-{mode}")]
            us, fs = u["skipped_interior_fraction"], f["skipped_interior_fraction"]
            kept = pct(fs / us) if us > 0 else "-"
            lines.append(
                f"| {s} | {'any-hit' if mode == 'anyhit' else 'closest-spec'} | {pct(us)} | "
                f"{pct(fs)} | {kept} | {pct(i['skipped_interior_fraction'])} | "
                f"{kind(i, 'shadow')} / {kind(i, 'ao')} ({kind(f, 'shadow')} / {kind(f, 'ao')}) | "
                f"{f['table_bytes']:,} / {i['table_bytes']:,} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"))
    ap.add_argument("--res", default="1024x1024")
    ap.add_argument("--spp", type=int, default=8)
    ap.add_argument("--out", default=str(ROOT / "out" / "results"))
    ap.add_argument("--doc", default=str(ROOT / "docs" / "results.md"))
    ap.add_argument("--tables-only", action="store_true",
                    help="rewrite the tables from the reports already in --out; run nothing")
    study.add_arguments(ap)
    args = ap.parse_args()
    scenes = sorted(str(p) for p in (pathlib.Path(args.shared) / "scenes").glob("*.glb"))
    if not scenes:
        sys.exit(f"results: no scenes in {args.shared}/scenes (the shared folder is needed)")
    stems = [pathlib.Path(s).stem for s in scenes]
    out = pathlib.Path(args.out)
    cmd = "make results" if (args.res, args.spp) == ("1024x1024", 8) else \
        f".venv/bin/python model/tools/results.py --res {args.res} --spp {args.spp}"
    doc = pathlib.Path(args.doc)

    def write(r):
        update_blocks(doc, {"table1": table1(stems, r, cmd), "finite": finite(stems, r, cmd)})
        print(f"results: updated {doc}")

    if args.tables_only:  # the reports of an earlier run in --out
        write({(stem, name): json.loads((out / f"{stem}-{name}.json").read_text())
               for stem in stems for name in RUNS})
        return 0

    def run():
        ts = tasks(scenes, args.res, args.spp, out)
        identity = {"hrpp": study.tool_version(ROOT / "build" / "hrpp"), "res": args.res,
                    "spp": args.spp}
        with study.Study("results", out / "journal.jsonl", identity, args) as st:
            res = st.run(ts, summary=lambda t, r:
                         f"{100 * r.report['skipped_interior_fraction']:.2f}% skipped")
            write({t.key: r.report for t, r in zip(ts, res)})
            st.complete()
        return 0
    return study.main_errors("results", run)


if __name__ == "__main__":
    sys.exit(main())
