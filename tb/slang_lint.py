#!/usr/bin/env python3
"""Strict SystemVerilog check of rtl/ with slang (pyslang), for every configuration the
testbench builds. Prints slang's diagnostics and exits 1 on any error or warning."""
import pathlib
import sys

import pyslang

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # the pyhrpp package
from pyhrpp import rtl_config as hrpp_config  # noqa: E402  (rtl/config/hrpp_configs.json)

FILES = [str(ROOT / line.strip()) for line in (ROOT / "rtl" / "hrpp.f").read_text().splitlines()
         if line.strip()]
# The top (hrpp_top, or hrpp_lanes for more than one lane) and its parameters of every
# configuration; slang takes the enumerations by name.
CONFIGS = {name: (hrpp_config.top_module(c),
                  " ".join(f"-G{k}={v}" for k, v in hrpp_config.top_params(c).items()))
           for name, c in hrpp_config.load()["configurations"].items()}


def check(name, top_and_params):
    top, params = top_and_params
    driver = pyslang.driver.Driver()
    driver.addStandardArgs()
    params = params.replace("1'b1", "1").replace("1'b0", "0")  # slang's command line quotes '
    cmd = f"slang --top {top} {params} " + " ".join(FILES)
    ok = driver.parseCommandLine(cmd, pyslang.driver.CommandLineOptions())
    ok = ok and driver.processOptions() and driver.parseAllSources()
    if not ok:
        return False
    comp = driver.createCompilation()
    driver.reportCompilation(comp, True)  # prints the diagnostics
    errors, warnings = driver.diagEngine.numErrors, driver.diagEngine.numWarnings
    print(f"slang {name}: {errors} errors, {warnings} warnings")
    return errors == 0 and warnings == 0


def main():
    results = [check(n, p) for n, p in CONFIGS.items()]
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
