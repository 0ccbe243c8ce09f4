#!/usr/bin/env python3
"""ctest ip.fusesoc.lint: the FuseSoC core hrpp.core checked against the project's definitions,
then its lint target run (`fusesoc --cores-root ROOT run --target=lint`, Verilator -Wall)
without parameters and for every configuration of rtl/config/hrpp_configs.json, its parameters
given as the core's FuseSoC parameters. Everything FuseSoC writes goes below --build-root (a folder of the build).

Checks: the core's package and module filesets list rtl/hrpp.f's files in its order; its
parameters are hrpp_top's (pyhrpp/rtl_config.py's PARAMS); each lint run exits 0 and Verilator
ran on the files of the checkout. Exits 1 on any failure."""
import argparse
import pathlib
import re
import shutil
import subprocess
import sys

import yaml

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp import rtl_config  # noqa: E402  (rtl/config/hrpp_configs.json)

CORE = ROOT / "hrpp.core"
VLNV = "hrpp:hrpp:hrpp"


def check_core(core):
    problems = []
    rtl_f = [ln.strip() for ln in (ROOT / "rtl" / "hrpp.f").read_text().splitlines() if ln.strip()]
    files = core["filesets"]["pkg"]["files"] + core["filesets"]["rtl"]["files"]
    if files != rtl_f:
        problems.append(f"filesets pkg + rtl {files} are not rtl/hrpp.f's files {rtl_f}")
    params = [p for _, p in rtl_config.PARAMS]
    if list(core["parameters"]) != params:
        problems.append(f"parameters {list(core['parameters'])} are not hrpp_top's {params}")
    for t in ("lint", "sim", "synth"):
        if t not in core["targets"]:
            problems.append(f"no target {t}")
    return problems


def lint(fusesoc, build_root, name, params):
    # The enumerations as their encodings (hrpp_tb_top's bit parameters), 1'bN as N.
    args = ["--%s=%s" % (k, str(v).removeprefix("1'b")) for k, v in params.items()]
    out = build_root / name
    shutil.rmtree(out, ignore_errors=True)
    cmd = [fusesoc, "--cores-root", str(ROOT), "run", "--build-root", str(out), "--target=lint",
           VLNV] + args
    print("$", " ".join(cmd), flush=True)
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       cwd=build_root, timeout=300)
    print(p.stdout)
    problems = []
    if p.returncode != 0:
        problems.append(f"{name}: fusesoc exited {p.returncode}")
    vc = list(out.glob("*/lint-verilator/*.vc"))
    if not vc:
        problems.append(f"{name}: no Verilator command file written below {out}")
    else:
        text = vc[0].read_text()
        for arg in args:
            want = "-G" + arg[2:]
            if want not in text.splitlines():
                problems.append(f"{name}: {want} not passed to Verilator")
        if not re.search(r"rtl/hrpp_top\.sv", text):
            problems.append(f"{name}: rtl/hrpp_top.sv not among Verilator's files")
    return problems


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build-root", required=True, type=pathlib.Path)
    ap.add_argument("--fusesoc", default=str(pathlib.Path(sys.executable).parent / "fusesoc"),
                    help="the fusesoc program (default: the one beside this python)")
    a = ap.parse_args()
    if not shutil.which(a.fusesoc):
        print(f"FAIL: no fusesoc program {a.fusesoc} (`make setup` installs it from "
              "requirements.txt)")
        return 1
    a.build_root.mkdir(parents=True, exist_ok=True)
    build_root = a.build_root.resolve()
    problems = check_core(yaml.safe_load(CORE.read_text()))
    problems += lint(a.fusesoc, build_root, "no-parameters", {})  # rtl/hrpp_pkg.sv's defaults
    for name, c in rtl_config.load()["configurations"].items():
        if c["lanes"] != 1:  # hrpp_lanes: not part of the core's parameters (docs/ip.md)
            continue
        problems += lint(a.fusesoc, build_root, name, rtl_config.hrpp_top_params(c, enums="int"))
    for p in problems:
        print("FAIL", p)
    print("ip.fusesoc.lint:", "PASS" if not problems else f"{len(problems)} failure(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
