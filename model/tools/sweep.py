#!/usr/bin/env python3
"""What accuracy costs in time: sweeps predictor parameters over scenes (docs/cost_model.md).

    hrpp sweep SCENE... --param NAME=V1,V2,... [--param ...] [--res WxH] [--spp N] --csv FILE
               [--timing cost-model | --timing simulate [--gpu mobile|desktop|FILE] [--oracle]]
               [--plots DIR] [--report FILE] [--workers N | --scheduler ADDRESS | --no-dask]
               [--resume]
    hrpp sweep --from-csv FILE... [--plots DIR] [--report FILE] [--doc PAGE [--doc-blocks NAME,...]]
               (one output at least)

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

Pareto fronts use the deterministic cycles of the sweep's time axis (the cost model's, or
simulated), never the noisy CPU times.

--timing simulate takes the time axis from the cycle-level model instead (docs/timing_model.md,
"Sweeps in simulated time"): each task runs `hrpp simulate` with the same predictor and workload
options (on --gpu, mobile by default; without the oracle unless --oracle), and the rows' cycles
per ray and saved cycles are simulated cycles: per ray kind from that kind's rays run alone, the
"all" row from the mixed run. update_delay and latency do not apply (the simulated table's
staleness follows from the simulated occupancy). The CSV then has the extra columns timing, gpu,
speedup, l1_hit_rate, stall_cycles, oracle_speedup and fraction_of_oracle; a cost-model CSV
keeps its columns. CSVs of different timings (or GPUs) are never merged into one report: `make
report` reports the grid's fronts (simulated by default) apart from the latency and update-delay
sweeps (cost model), and --doc-blocks names the blocks of the page each report fills.
"""
import argparse
import os
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp import study  # noqa: E402
from sweeplib.doc import DOC_BLOCKS, write_doc  # noqa: E402
from sweeplib.plots import plot_all  # noqa: E402
from sweeplib.report import report  # noqa: E402
from sweeplib.tasks import (PARAMS, BadInput, Sweep, check_presets, expand,  # noqa: E402
                            parse_params, read_csv, write_csv)


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
    ap.add_argument("--doc-blocks", metavar="NAME,...",
                    help="--doc: only these blocks (" + ", ".join(DOC_BLOCKS) + "), each of "
                         "which the rows must fill (default: every block they fill)")
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
    # --workers, --scheduler, --no-dask, --resume; the study's journal is CSV.journal.jsonl.
    study.add_arguments(ap)
    args = ap.parse_args()
    command = args.command or "hrpp sweep " + " ".join(sys.argv[1:])
    try:
        check_outputs(args)
        blocks = None
        if args.doc_blocks is not None:
            if not args.doc:
                raise BadInput("--doc-blocks needs --doc PAGE")
            blocks = [n.strip() for n in args.doc_blocks.split(",")]
            unknown = [n for n in blocks if n not in DOC_BLOCKS]
            if unknown:
                raise BadInput(f"--doc-blocks: unknown block '{unknown[0]}' (known: "
                               f"{', '.join(DOC_BLOCKS)})")
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
            names = write_doc(args.doc, rows, blocks)
        except BadInput as e:
            print(f"hrpp sweep: {e}", file=sys.stderr)
            return 2
        print(f"sweep: wrote {', '.join(names) or 'no'} blocks of {args.doc}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
