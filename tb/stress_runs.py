#!/usr/bin/env python3
"""Long reliability runs of tb_hrpp (`make stress`; docs/results.md, "Reliability", hardware):
resets in the middle of the stream, long random stalls on every interface, the synthetic stress
streams (bursts of one set, one key, continuous eviction) and random initial state (X stand-ins)
with several seeds, in every RTL configuration. Each run must print PASS (parity on every cycle,
no SVA firing, every ray exactly one final result, the stress really happened); the totals go to
OUT/summary.json and a table on stdout.

  python3 tb/stress_runs.py --tb build/tb_hrpp --shared ../shared --out out/stress [--jobs 2]
"""
import argparse
import concurrent.futures as cf
import json
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # pyhrpp
from pyhrpp.files import write_json_atomic  # noqa: E402

PARITY = re.compile(r"^parity: (\d+) rays, (\d+) cycles, (\d+) mismatches", re.M)
RESETS = re.compile(r"^resets: (\d+) \((\d+) cycles in reset\), (\d+) hit rays in flight: (\d+) rays", re.M)
STALLS = re.compile(r"^stalls .*?:(.*)$", re.M)
TABLE = re.compile(r"^table: (\d+) updates, (\d+) requests merged, (\d+) evictions, "
                   r"(\d+) cycles of same-set interlock", re.M)


def runs(shared, own):
    """(group, name, args) of every run."""
    big = os.path.join(shared, "scenes", "bunny.glb")
    scene = big if os.path.exists(big) else os.path.join(own, "spd_balls.glb")
    glass = os.path.join(own, "glass_spheres.glb")
    balls = os.path.join(own, "spd_balls.glb")
    modes = {"small": "anyhit", "primary": "closest-exact", "large": "closest-spec",
             "mobile": "anyhit", "primary_x2": "closest-exact", "primary_x4": "closest-spec",
             "oct": "anyhit", "default": "anyhit"}
    every = {"small": 4000, "primary": 5000, "large": 20000, "mobile": 5000, "primary_x2": 5000,
             "primary_x4": 5000, "oct": 5000, "default": 5000}
    out = []
    for cfg, mode in modes.items():
        for seed in (1, 2):
            out.append(("reset", f"reset.{cfg}.s{seed}",
                        ["--scene", scene, "--rays", "1000000", "--config", cfg, "--mode", mode,
                         "--go-up", "1", "--seed", str(seed), "--reset-every", str(every[cfg]),
                         "--reset-max-length", "16"]))
        out.append(("stall", f"stall.{cfg}",
                    ["--scene", glass, "--rays", "400000", "--config", cfg, "--mode", mode,
                     "--seed", "5", "--stall-gap", "3000", "--stall-max", "5000",
                     "--max-latency", "60"]))
        out.append(("stall", f"stall+reset.{cfg}",
                    ["--scene", balls, "--rays", "400000", "--config", cfg, "--mode", mode,
                     "--seed", "6", "--stall-gap", "2000", "--stall-max", "4000",
                     "--reset-every", str(4 * every[cfg])]))
        # evict: not in the large configuration, whose 4096 sets this scene's rays do not all
        # reach (2,724 with 95,445 keys), so its table cannot fill up.
        # spread (each lane its own bank): the multi-lane configurations only.
        lanes = cfg.startswith("primary_x")
        for kind, rays in (("set-burst", 100000 if cfg == "large" else 300000),
                           ("one-key", 300000)) + ((("evict", 300000),) if cfg != "large" else ()) \
                + ((("spread", 300000),) if lanes else ()):
            out.append(("stress", f"{kind}.{cfg}",
                        ["--scene", balls, "--rays", str(rays), "--config", cfg, "--mode", mode,
                         "--stress", kind, "--seed", "7", "--p-ray", "1", "--min-latency", "1",
                         "--max-latency", "4", "--p-ready", "0.95"]))
        for seed in range(1, 9):
            out.append(("xprop", f"xprop.{cfg}.s{seed}",
                        ["--scene", balls, "--rays", "100000", "--config", cfg, "--mode", mode,
                         "--seed", str(seed), "--reset-every", str(every[cfg]),
                         "+verilator+rand+reset+2", f"+verilator+seed+{seed}"]))
    return out


def run_one(tb, group, name, args):
    t = time.time()
    p = subprocess.run([tb] + args, capture_output=True, text=True)
    r = {"group": group, "name": name, "args": args, "exit": p.returncode,
         "seconds": round(time.time() - t, 1), "pass": p.returncode == 0 and "\nPASS" in p.stdout}
    if m := PARITY.search(p.stdout):
        r.update(rays=int(m[1]), cycles=int(m[2]), mismatches=int(m[3]))
    if m := RESETS.search(p.stdout):
        r.update(resets=int(m[1]), reset_cycles=int(m[2]), resets_hitting_rays=int(m[3]),
                 rays_dropped=int(m[4]))
    if m := STALLS.search(p.stdout):
        ports = [x.split() for x in m[1].split(";")]
        r["stalls"] = {x[0]: [int(v.strip(",")) for v in x[1:]] for x in ports}
    if m := TABLE.search(p.stdout):
        r.update(updates=int(m[1]), merged_requests=int(m[2]), evictions=int(m[3]),
                 interlock_cycles=int(m[4]))
    elif r["pass"]:  # the totals would silently miss this run's table statistics
        r["pass"] = False
        p = subprocess.CompletedProcess(p.args, p.returncode, "no 'table:' line in:\n" + p.stdout,
                                        p.stderr)
    if not r["pass"]:
        r["output"] = (p.stdout + p.stderr)[-3000:]
    return r


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tb", default="build/tb_hrpp")
    ap.add_argument("--shared", default="../shared")
    ap.add_argument("--own", default="scenes")
    ap.add_argument("--out", default="out/stress")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default="", help="run only names containing this")
    a = ap.parse_args()
    todo = [r for r in runs(a.shared, a.own) if a.only in r[1]]
    t0 = time.time()
    with cf.ThreadPoolExecutor(a.jobs) as ex:
        results = list(ex.map(lambda r: run_one(a.tb, *r), todo))
    for r in results:
        print(f"{'PASS' if r['pass'] else 'FAIL'} {r['name']:24s} {r.get('rays', 0):>8} rays "
              f"{r.get('cycles', 0):>10} cycles {r.get('mismatches', '?')} mismatches "
              f"{r['seconds']:>6} s", flush=True)
        if not r["pass"]:
            print(r.get("output", ""))
    tot = {"runs": len(results), "failed": sum(not r["pass"] for r in results),
           "wall_seconds": round(time.time() - t0, 1)}
    for key in ("rays", "cycles", "mismatches", "resets", "reset_cycles", "rays_dropped",
                "updates", "merged_requests", "evictions", "interlock_cycles"):
        tot[key] = sum(r.get(key, 0) for r in results)
    stalls = [s for r in results for s in r.get("stalls", {}).values()]
    tot["stalls"] = sum(s[0] for s in stalls)
    tot["stall_cycles"] = sum(s[1] for s in stalls)
    tot["longest_stall"] = max((s[2] for s in stalls), default=0)
    tot["stall_blocked_cycles"] = sum(s[3] for s in stalls)
    groups = {}
    for r in results:
        g = groups.setdefault(r["group"], {"runs": 0, "rays": 0, "cycles": 0, "mismatches": 0,
                                           "resets": 0, "failed": 0})
        g["runs"] += 1
        g["failed"] += not r["pass"]
        for k in ("rays", "cycles", "mismatches", "resets"):
            g[k] += r.get(k, 0)
    os.makedirs(a.out, exist_ok=True)
    write_json_atomic(os.path.join(a.out, "summary.json"),
                      {"total": tot, "groups": groups, "runs": results}, indent=1, newline=False)
    print("| group | runs | rays | cycles | resets | mismatches | failed |")
    print("|---|---|---|---|---|---|---|")
    for name, g in groups.items():
        print(f"| {name} | {g['runs']} | {g['rays']:,} | {g['cycles']:,} | {g['resets']:,} | "
              f"{g['mismatches']} | {g['failed']} |")
    print("total:", json.dumps(tot))
    return 1 if tot["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
