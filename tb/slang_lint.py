#!/usr/bin/env python3
"""Strict SystemVerilog check of rtl/ with slang (pyslang), for every configuration the
testbench builds. Prints slang's diagnostics and exits 1 on any error or warning."""
import pathlib
import sys

import pyslang

ROOT = pathlib.Path(__file__).resolve().parents[1]
FILES = [str(ROOT / line.strip()) for line in (ROOT / "rtl" / "hrpp.f").read_text().splitlines()
         if line.strip()]
# Keep in sync with tb/CMakeLists.txt.
CONFIGS = {
    "default": "-GVariant=1'b1 -GOriginBits=5 -GDirBits=3 -GCombine=1'b1 -GNumSets=128 -GNumWays=8 "
               "-GNodesPerEntry=2 -GTagBits=8 -GIdWidth=6 -GNodeIdWidth=20",
    "small": "-GVariant=1'b0 -GPrecision=6 -GExpBits=3 -GCombine=1'b0 -GNumSets=64 -GNumWays=2 "
             "-GNodesPerEntry=1 -GTagBits=12 -GIdWidth=4 -GNodeIdWidth=20",
    "large": "-GVariant=1'b0 -GPrecision=6 -GExpBits=3 -GCombine=1'b0 -GNumSets=4096 -GNumWays=4 "
             "-GNodesPerEntry=4 -GTagBits=16 -GIdWidth=8 -GNodeIdWidth=20",
}


def check(name, params):
    driver = pyslang.driver.Driver()
    driver.addStandardArgs()
    params = params.replace("1'b1", "1").replace("1'b0", "0")  # slang's command line quotes '
    cmd = f"slang --top hrpp_top {params} " + " ".join(FILES)
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
