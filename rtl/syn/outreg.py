"""The block RAMs' own output registers (REGMODE OUTREG) for the ECP5 netlist of the flow.

Every block-RAM read in the RTL goes straight into a register (docs/microarchitecture.md,
"Pipelines"). Yosys 0.70 maps such a read to a DP16KD without its output register (NOREG) and one
TRELLIS_FF per data bit in the fabric, and has no pass that moves the flip-flops into the RAM; on
ECP5 the route from the RAM to those flip-flops is what limits the clock. move() makes that move
on Yosys's JSON netlist, after synth_ecp5 and before nextpnr: it changes no cycle (the output
register is loaded from the RAM's read latch on the clock, as the flip-flop was), which `make
synth-check` checks by simulating the moved netlist (rtl/syn/sim/dp16kd_sim.v) against the cycle
model.

A RAM's flip-flops move when every used data output (DOA*, DOB*) has one load, the data input of
a TRELLIS_FF with the RAM's read clock (CLKB), all of them with the same clock enable (none, or
one net: only with clock_enables) and the same reset (none, or one asynchronous reset to 0), and
the RAM's own resets (RSTA, RSTB) are unused. The RAM then takes REGMODE OUTREG on both ports, the
clock enable as OCEA / OCEB (high without one) and the reset as RSTA / RSTB (RESETMODE and
ASYNC_RESET_RELEASE ASYNC, like the flip-flops' reset); the flip-flops are removed and the RAM
drives their outputs. Any other RAM is left as it is and named in the result.

Clock-enabled flip-flops behind a block RAM are the key store's: the skip controller's P0 / F0
without the key store's read register (KeyStoreReg), its J key registers with it. The flow moves
them only with KeyStoreReg (synth.py passes clock_enables): J's key registers are there to be the
RAM's output register; P0 / F0 moved measured lower (docs/microarchitecture.md, "Clock speed":
P0's fields then start at the RAM, far from the update queue they feed).
"""
from __future__ import annotations

import collections

# Parameter values in Yosys's JSON netlist: strings are written as they are, numbers in binary.
ASYNC = "ASYNC"


def _ff_control(ff: dict, clock_enables: bool) -> tuple[str, str] | None:
    """(clock enable, reset) nets of a TRELLIS_FF the move can take ("1": none; "0": none), or
    None (a flip-flop with a clock enable unless clock_enables, an inverted clock, a set or a
    synchronous reset: see the module's docstring)."""
    p, c = ff["parameters"], ff["connections"]
    cemux = str(p.get("CEMUX", "1")).strip()
    if p.get("CLKMUX", "CLK") != "CLK" or cemux not in (("1", "CE") if clock_enables else ("1",)):
        return None
    ce = "1" if cemux == "1" else c["CE"][0]
    lsr = c.get("LSR", ["0"])[0]
    if lsr == "0":
        return ce, "0"
    if p.get("REGSET") == "RESET" and p.get("SRMODE") == ASYNC and \
            p.get("LSRMUX", "LSR") == "LSR" and str(p.get("LSRMODE", "LSR")).strip() == "LSR":
        return ce, lsr
    return None


def move(netlist: dict, clock_enables: bool = False) -> dict:
    """Moves the qualifying flip-flops into their DP16KD's output registers, in place (with a
    clock enable too when clock_enables). Returns {"rams": DP16KD cells, "moved": RAMs changed,
    "ffs": flip-flops removed, "left": the names of the RAMs left as they were}."""
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
    rams = [n for n, c in cells.items() if c["type"] == "DP16KD"]
    out = {"rams": len(rams), "moved": 0, "ffs": 0, "left": []}
    for name in rams:
        c = cells[name]
        conn = c["connections"]
        clk = conn["CLKB"]
        moves, resets = [], set()
        ok = conn["RSTB"] == ["0"] and conn["RSTA"] == ["0"]
        for p, bits in conn.items():
            if not ok:
                break
            if not p.startswith("DO") or not loads[bits[0]]:
                continue
            ld = loads[bits[0]]
            ff = cells.get(ld[0][0]) if len(ld) == 1 and ld[0][0] else None
            ctl = _ff_control(ff, clock_enables) if ff and ff["type"] == "TRELLIS_FF" and \
                ld[0][1] == "DI" and ff["connections"]["CLK"] == clk else None
            if ctl is None:
                ok = False
                break
            resets.add(ctl)
            moves.append((p, ld[0][0]))
        if not ok or len(resets) != 1 or not moves:
            out["left"].append(name)
            continue
        ce, rst = resets.pop()
        for p, ffn in moves:
            conn[p] = cells[ffn]["connections"]["Q"]
            del cells[ffn]
        c["parameters"].update(REGMODE_A="OUTREG", REGMODE_B="OUTREG")
        if rst != "0":
            c["parameters"].update(RESETMODE=ASYNC, ASYNC_RESET_RELEASE=ASYNC)
        conn.update(OCEA=[ce], OCEB=[ce], RSTA=[rst], RSTB=[rst])
        out["moved"] += 1
        out["ffs"] += len(moves)
    return out
