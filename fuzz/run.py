#!/usr/bin/env python3
"""Runs the libFuzzer targets (fuzz/README.md).

  run.py --smoke --bin-dir build/fuzz --runs N TARGET
      the ctest check: every committed regression input of TARGET (fuzz/regressions/TARGET/),
      then N mutations with seed 1 from the generated seed corpus in a temporary directory.
  run.py --bin-dir build/fuzz --seconds S [--out out/fuzz] [TARGET...]
      `make fuzz`: each target (default: all) for S seconds, with a corpus kept in
      OUT/corpus/TARGET across runs; crashes go to OUT/crashes/TARGET/; the figures (inputs
      tried, corpus size, coverage, crashes) to OUT/summary.json and the standard output.

Exit status: 0 no crash, 1 a target crashed (or a regression input failed), 2 bad usage.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

TARGETS = ["scene", "stream", "hash", "traverse"]
MAX_LEN = {"scene": 65536, "stream": 4096, "hash": 64, "traverse": 1024}
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))  # the pyhrpp package
from pyhrpp.files import write_json_atomic  # noqa: E402


def fail(msg):
    print(f"fuzz/run.py: {msg}", file=sys.stderr)
    sys.exit(2)


def binary(bin_dir, name):
    path = os.path.join(bin_dir, name)
    if not os.access(path, os.X_OK):
        fail(f"{path} not found (build it: cmake --build build --target hrpp_fuzz)")
    return path


def env():
    e = dict(os.environ)
    e.setdefault("ASAN_OPTIONS", "detect_leaks=1:abort_on_error=0")
    e.setdefault("UBSAN_OPTIONS", "print_stacktrace=1:halt_on_error=1")
    return e


def regressions(target):
    d = os.path.join(HERE, "regressions", target)
    if not os.path.isdir(d):
        return []
    return sorted(os.path.join(d, f) for f in os.listdir(d) if not f.startswith("."))


def run_fuzzer(bin_dir, target, corpus_dirs, artifacts, extra):
    cmd = [binary(bin_dir, f"fuzz_{target}"), f"-max_len={MAX_LEN[target]}", "-timeout=20",
           "-rss_limit_mb=2048", "-print_final_stats=1",
           f"-artifact_prefix={artifacts}{os.sep}"] + extra + corpus_dirs
    t0 = time.time()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       errors="replace", env=env())
    secs = time.time() - t0
    out = p.stdout
    stats = {k: int(v) for k, v in re.findall(r"stat::(\w+):\s+(\d+)", out)}
    cov = re.findall(r"cov: (\d+) ft: (\d+)", out)
    return p.returncode, out, secs, stats, cov[-1] if cov else ("0", "0")


def crash_files(d):
    return sorted(f for f in os.listdir(d) if re.match(r"(crash|leak|timeout|oom|slow-unit)-", f))


def smoke(args, target):
    with tempfile.TemporaryDirectory(prefix=f"hrpp-fuzz-{target}-") as tmp:
        seeds = os.path.join(tmp, "seeds")
        subprocess.run([binary(args.bin_dir, "fuzz_seeds"), seeds], check=True,
                       stdout=subprocess.DEVNULL)
        regs = regressions(target)
        if regs:
            code, out, _, _, _ = run_fuzzer(args.bin_dir, target, regs, tmp, [])
            if code != 0:
                print(out[-6000:])
                print(f"fuzz.{target}: FAIL: a regression input of fuzz/regressions/{target}/ fails")
                return 1
            print(f"fuzz.{target}: {len(regs)} regression inputs pass")
        corpus = os.path.join(tmp, "corpus")
        os.mkdir(corpus)
        code, out, secs, stats, cov = run_fuzzer(
            args.bin_dir, target, [corpus, os.path.join(seeds, target)], tmp,
            [f"-runs={args.runs}", "-seed=1"])
        crashes = crash_files(tmp)
        if code != 0 or crashes:
            print(out[-6000:])
            for c in crashes:
                kept = os.path.join(os.getcwd(), f"fuzz-{target}-{c}")
                shutil.copy(os.path.join(tmp, c), kept)
                print(f"fuzz.{target}: crashing input saved as {kept}")
            print(f"fuzz.{target}: FAIL (exit {code})")
            return 1
        print(f"fuzz.{target}: PASS: {stats.get('number_of_executed_units', 0)} inputs, "
              f"coverage {cov[0]} edges / {cov[1]} features, {secs:.1f} s, 0 crashes")
        return 0


def campaign(args, targets):
    out_dir = os.path.abspath(args.out)
    seeds = os.path.join(out_dir, "seeds")
    subprocess.run([binary(args.bin_dir, "fuzz_seeds"), seeds], check=True,
                   stdout=subprocess.DEVNULL)
    summary_path = os.path.join(out_dir, "summary.json")
    summary = {}
    if os.path.exists(summary_path):
        with open(summary_path) as f:
            summary = json.load(f)
    status = 0
    for t in targets:
        corpus = os.path.join(out_dir, "corpus", t)
        crashes_dir = os.path.join(out_dir, "crashes", t)
        os.makedirs(corpus, exist_ok=True)
        os.makedirs(crashes_dir, exist_ok=True)
        before = set(crash_files(crashes_dir))
        print(f"fuzz: {t} for {args.seconds} s ...", file=sys.stderr, flush=True)
        code, out, secs, stats, cov = run_fuzzer(
            args.bin_dir, t, [corpus, os.path.join(seeds, t)], crashes_dir,
            [f"-max_total_time={args.seconds}"])
        new = sorted(set(crash_files(crashes_dir)) - before)
        units = stats.get("number_of_executed_units", 0)
        summary[t] = {"seconds": round(secs, 1), "inputs_tried": units,
                      "corpus_files": len(os.listdir(corpus)), "coverage_edges": int(cov[0]),
                      "features": int(cov[1]), "exit_code": code,
                      "crashes": [os.path.join(crashes_dir, c) for c in new]}
        print(f"fuzz {t}: {units} inputs in {secs:.0f} s, corpus {len(os.listdir(corpus))} files, "
              f"coverage {cov[0]} edges, {len(new)} crashes (exit {code})")
        if code != 0 or new:
            status = 1
            print(out[-4000:])
            for c in new:
                print(f"fuzz {t}: crash input {os.path.join(crashes_dir, c)}: reproduce with "
                      f"{binary(args.bin_dir, 'fuzz_' + t)} FILE; once fixed, commit it to "
                      f"fuzz/regressions/{t}/")
    write_json_atomic(summary_path, summary)
    print(f"fuzz: wrote {summary_path}")
    return status


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--bin-dir", required=True, help="where fuzz_* and fuzz_seeds are (build/fuzz)")
    ap.add_argument("--smoke", action="store_true", help="the short ctest run")
    ap.add_argument("--runs", type=int, default=2000, help="--smoke: mutations to run")
    ap.add_argument("--seconds", type=int, default=60, help="seconds per target")
    ap.add_argument("--out", default="out/fuzz", help="corpora, crashes and summary.json")
    ap.add_argument("targets", nargs="*", help=f"of {', '.join(TARGETS)} (default: all)")
    args = ap.parse_args()
    targets = args.targets or TARGETS
    for t in targets:
        if t not in TARGETS:
            fail(f"unknown target '{t}' (targets: {', '.join(TARGETS)})")
    if args.runs < 1 or args.seconds < 1:
        fail("--runs and --seconds must be at least 1")
    if args.smoke:
        return max(smoke(args, t) for t in targets)
    return campaign(args, targets)


if __name__ == "__main__":
    sys.exit(main())
