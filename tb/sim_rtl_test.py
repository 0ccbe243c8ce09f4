#!/usr/bin/env python3
"""`hrpp simulate --rtl`: the Verilated RTL in every RT unit, compared with the cycle model on
every cycle (tb/rtl_port.h).

  sim_rtl_test.py HRPP SCENE OUTDIR CONFIG [ARGS...]     (ctest: sim.rtl.default, sim.rtl.mutant)

A correct configuration (e.g. default): `hrpp simulate SCENE ARGS --preset rtl-CONFIG --rtl` exits
0 with 0 mismatches, and its report equals the same command's without --rtl in everything but the
timings and the RTL's own fields: cycles, baseline_cycles, the predictor's counters, the memory
system's, per kind. The mutant (an injected fault, rtl/config/hrpp_configs.json): the run must fail
(exit 1), with mismatches counted in the report and the first one printed.
"""
import json
import pathlib
import subprocess
import sys

# Keys that differ between the runs by design: the timings, the --rtl flag and its fields, and
# the preset's timing line (it names the RTL). WALL_CLOCK: every run's own wall-clock figures, at
# any depth.
IGNORED = {"seconds", "rtl", "rtl_mismatches", "rtl_first_mismatch", "tool"}
WALL_CLOCK = {"run_seconds", "rays_per_second"}


def run(cmd: list[str]) -> subprocess.CompletedProcess:
    print("$", " ".join(cmd), flush=True)
    p = subprocess.run(cmd, capture_output=True, text=True)
    sys.stdout.write(p.stdout)
    sys.stderr.write(p.stderr)
    return p


def differences(a, b, path: str = "") -> list[str]:
    """The dotted paths where a and b differ (keys in IGNORED left out at the top level)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in sorted(set(a) | set(b)):
            if (not path and k in IGNORED) or k in WALL_CLOCK:
                continue
            if path == "preset." and k == "timing":
                continue
            if k not in a or k not in b:
                out.append(f"{path}{k}: only in {'the --rtl run' if k in b else 'the model run'}")
                continue
            out += differences(a[k], b[k], f"{path}{k}.")
        return out
    return [] if a == b else [f"{path.rstrip('.')}: {a!r} (cycle model) != {b!r} (--rtl)"]


def main() -> int:
    if len(sys.argv) < 5:
        print(__doc__)
        return 2
    hrpp, scene, outdir, config, args = sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3]), \
        sys.argv[4], sys.argv[5:]
    outdir.mkdir(parents=True, exist_ok=True)
    base = [hrpp, "simulate", scene, *args, "--preset", f"rtl-{config}"]
    rtl_json = outdir / f"sim_rtl_{config}.json"
    rtl_json.unlink(missing_ok=True)
    r = run([*base, "--rtl", "--json", str(rtl_json)])
    errors = []
    if config == "mutant":
        if r.returncode != 1:
            errors.append(f"the mutant with --rtl exited {r.returncode}, expected 1")
        if "MISMATCH" not in r.stderr:
            errors.append("no MISMATCH printed")
        if not rtl_json.exists():
            errors.append("no report written")
        else:
            j = json.loads(rtl_json.read_text())
            if not j.get("rtl_mismatches"):
                errors.append(f"rtl_mismatches = {j.get('rtl_mismatches')!r}, expected > 0")
            if not j.get("rtl_first_mismatch"):
                errors.append("no rtl_first_mismatch in the report")
    else:
        if r.returncode != 0:
            errors.append(f"--rtl exited {r.returncode}")
        model_json = outdir / f"sim_model_{config}.json"
        model_json.unlink(missing_ok=True)
        m = run([*base, "--json", str(model_json)])
        if m.returncode != 0:
            errors.append(f"the cycle-model run exited {m.returncode}")
        if not errors:
            jr = json.loads(rtl_json.read_text())
            jm = json.loads(model_json.read_text())
            if jr.get("rtl") is not True or jr.get("rtl_mismatches") != 0:
                errors.append(f"--rtl report: rtl {jr.get('rtl')!r}, rtl_mismatches "
                              f"{jr.get('rtl_mismatches')!r} (expected true, 0)")
            if jr["predictor"]["lookups"] == 0:
                errors.append("the predictor took no rays: nothing was compared")
            errors += differences(jm, jr)
            print(f"cycles {jr['cycles']} (baseline {jr['baseline_cycles']}), "
                  f"{jr['predictor']['lookups']} lookups, {jr['rtl_mismatches']} mismatches")
    for e in errors:
        print("FAIL:", e)
    if not errors:
        print("PASS")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
