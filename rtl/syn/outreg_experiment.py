#!/usr/bin/env python3
"""The block RAMs' own output registers, measured (docs/microarchitecture.md, "The table alone is
below 95%"): a configuration through `synth_ecp5` as `make synth` runs it, then every flip-flop
that takes a DP16KD data output moved into the block RAM's output register (REGMODE OUTREG),
then nextpnr-ecp5 per speed grade and placer seed, beside the same netlist without the move.

  .venv/bin/python rtl/syn/outreg_experiment.py [--config primary] [--speeds 6,8] [--seeds 1,2]
      [--ceiling]

--ceiling measures the configuration's ceiling instead (rtl/syn/hrpp_syn_ceiling.sv as
`make synth` sizes it: the bare block RAM whose output register, with no reset, moves the same
way). With its output register moved the ceiling keeps no path out of the RAM, and nextpnr checks
no minimum cycle of the RAM itself, so its figure bounds nothing (docs/microarchitecture.md).

Yosys 0.70 maps the table's registered reads to a DP16KD (NOREG) and a TRELLIS_FF per output bit
and does not absorb the flip-flop into the RAM; the move is made on Yosys's JSON netlist. A DO bit
is moved only when its one load is a TRELLIS_FF's data input with the RAM's clock, no clock
enable (CE constant 1) and an asynchronous reset to 0 (the table's L3 / T2 registers) or no reset
(the ceiling's: LSR constant 0), and a RAM is changed only when every used DO bit qualifies, with
one reset net, which becomes the RAM's RSTA / RSTB (RESETMODE ASYNC; OCEA / OCEB 1). Timing only:
the netlist is not simulated (Yosys's DP16KD has no simulation model), so it is a measurement, not
a build. Results in out/outreg/ (CONFIG.json, or CONFIG-ceiling.json, keeps every speed grade and
seed run so far).
"""
from __future__ import annotations

import argparse
import collections
import json
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "rtl" / "syn"))
import synth  # noqa: E402
from flow import NEXTPNR, YOSYS, FlowError, run_tool, rtl_files  # noqa: E402

OUT = Path("out/outreg")  # relative to ROOT (yowasp)


def absorb(netlist: dict) -> tuple[int, int]:
    """Moves the qualifying flip-flops into their DP16KD's output registers, in place; returns
    (RAMs changed, RAMs left)."""
    mod = next(m for m in netlist["modules"].values() if m.get("attributes", {}).get("top"))
    cells = mod["cells"]
    loads = collections.defaultdict(list)
    for n, c in cells.items():
        for p, bits in c["connections"].items():
            if c["port_directions"][p] == "input":
                for b in bits:
                    loads[b].append((n, p))
    for pn, p in mod["ports"].items():
        for b in p["bits"]:
            loads[b].append((None, pn))
    done = left = 0
    for c in [c for c in cells.values() if c["type"] == "DP16KD"]:
        clk = c["connections"]["CLKB"]
        moves, resets, ok = [], set(), True
        for p, bits in c["connections"].items():
            if not p.startswith("DO") or not loads[bits[0]]:
                continue
            ld = loads[bits[0]]
            ff = cells.get(ld[0][0]) if len(ld) == 1 and ld[0][0] else None
            pr = ff["parameters"] if ff else {}
            no_reset = bool(ff) and ff["connections"].get("LSR") == ["0"]
            if not ff or ff["type"] != "TRELLIS_FF" or ld[0][1] != "DI" or \
                    ff["connections"]["CLK"] != clk or pr.get("CEMUX", "").strip() != "1" or \
                    pr.get("CLKMUX") != "CLK" or not (no_reset or (
                        pr.get("REGSET") == "RESET" and pr.get("SRMODE") == "ASYNC" and
                        pr.get("LSRMUX") == "LSR")):
                ok = False
                break
            resets.add(ff["connections"]["LSR"][0])
            moves.append((p, ld[0][0]))
        if not ok or len(resets) != 1 or not moves:
            left += 1
            continue
        rst = resets.pop()
        for p, ffn in moves:
            c["connections"][p] = cells[ffn]["connections"]["Q"]
            del cells[ffn]
        c["parameters"].update(REGMODE_A="OUTREG", REGMODE_B="OUTREG", RESETMODE="ASYNC")
        c["connections"].update(OCEA=["1"], OCEB=["1"], RSTA=[rst], RSTB=[rst])
        done += 1
    return done, left


def pnr(tag: str, speed: int, seed: int) -> dict:
    rep = OUT / f"{tag}-pnr{speed}-s{seed}.json"
    run_tool([NEXTPNR, "--85k", "--package", "CABGA381", "--speed", str(speed),
              "--out-of-context", "--freq", "250", "--timing-allow-fail", "--seed", str(seed),
              "--json", str(OUT / f"{tag}.ecp5.json"), "--report", str(rep),
              "-l", str(OUT / f"{tag}-pnr{speed}-s{seed}.log")],
             OUT / f"{tag}-pnr{speed}-s{seed}.stdout", 3600, f"{tag}: nextpnr {speed} {seed}")
    r = json.loads((ROOT / rep).read_text())
    clk = next(iter(r["fmax"]))
    path = r["critical_paths"][0]["path"] if r.get("critical_paths") else []
    return {"fmax_mhz": round(r["fmax"][clk]["achieved"], 1),
            "logic_ns": round(sum(s["delay"] for s in path if s["type"] == "logic"), 2),
            "routing_ns": round(sum(s["delay"] for s in path if s["type"] == "routing"), 2)}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--config", default="primary")
    ap.add_argument("--speeds", default="6,8")
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--ceiling", action="store_true",
                    help="the configuration's ceiling RAM instead of the configuration")
    args = ap.parse_args()
    os.chdir(ROOT)
    (ROOT / OUT).mkdir(parents=True, exist_ok=True)
    cfgs = synth.read_configs()
    if args.config not in cfgs:
        raise FlowError(f"unknown configuration {args.config} ({sorted(cfgs)})")
    p = cfgs[args.config]
    name = f"{args.config}-ceiling" if args.ceiling else args.config
    if args.ceiling:
        top, params, files = "hrpp_syn_ceiling", synth.ceiling_params(p), [synth.CEILING_SV]
    else:
        top, params, files = synth.top_of(p), dict(p), rtl_files()
    base = OUT / name
    (ROOT / f"{base}.ys").write_text(
        f"{synth.read_slang_cmd(top, params, files)}\nhierarchy -check -top {top}\n"
        f"synth_ecp5 -top {top} -json {base}.ecp5.json\n")
    run_tool([YOSYS, "-q", "-l", f"{base}.yosys.log", f"{base}.ys"], Path(f"{base}.stdout"),
             900, f"{name}: yosys")
    net = json.loads((ROOT / f"{base}.ecp5.json").read_text())
    done, left = absorb(net)
    if not done:
        raise FlowError(f"{name}: no DP16KD output could take its flip-flops")
    (ROOT / f"{base}-outreg.ecp5.json").write_text(json.dumps(net))
    print(f"{name}: {done} DP16KD take their output flip-flops, {left} do not")
    summary = ROOT / OUT / f"{name}.json"
    res = json.loads(summary.read_text()) if summary.exists() else {}  # earlier seeds kept
    for tag in (name, f"{name}-outreg"):
        for sp in map(int, args.speeds.split(",")):
            for sd in map(int, args.seeds.split(",")):
                res[f"{tag} speed {sp} seed {sd}"] = r = pnr(tag, sp, sd)
                print(f"{tag}: speed grade {sp}, seed {sd}: {r['fmax_mhz']} MHz "
                      f"(critical path {r['logic_ns']} ns logic, {r['routing_ns']} ns routing)",
                      flush=True)
        summary.write_text(json.dumps(res, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except FlowError as e:
        print(f"outreg_experiment: FAILED: {e}", file=sys.stderr)
        sys.exit(1)
