#!/usr/bin/env python3
"""ctest tb.trace.fst: tb_hrpp --trace writes FST for a .fst name and VCD otherwise.

One short run (configuration small) twice, with --trace OUT/w.fst and --trace OUT/w.vcd. Checks:
both runs pass; the FST's header block (tag 0, length 329, the endian-test double e, at least one
variable and one value-change section; its end time is the VCD's last time stamp and it declares
as many variables as the VCD); the VCD is a VCD (definitions, then value changes), with no
temporary FST left beside it; the FST is smaller than the VCD. Exits 1 on any failure.

    trace_test.py TB_HRPP SCENE OUT_DIR
"""
import math
import os
import re
import shutil
import struct
import subprocess
import sys


def fst_header(path):
    """The FST header block's fields (fstapi.c, fstWriterEmitHdrBytes): big-endian integers."""
    with open(path, "rb") as f:
        b = f.read(329 + 1)
    if len(b) < 330:
        return None
    u64 = lambda off: struct.unpack(">Q", b[off:off + 8])[0]  # noqa: E731
    return {"tag": b[0], "length": u64(1), "start": u64(9), "end": u64(17),
            "endian_test": struct.unpack("<d", b[25:33])[0], "scopes": u64(41), "vars": u64(49),
            "sections": u64(65)}


def main():
    tb, scene, out = sys.argv[1:4]
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    problems = []
    paths = {"fst": os.path.join(out, "w.fst"), "vcd": os.path.join(out, "w.vcd")}
    for kind, path in paths.items():
        cmd = [tb, "--scene", scene, "--rays", "300", "--config", "small", "--seed", "3",
               "--trace", path]
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                           timeout=120)
        if p.returncode != 0 or "\nPASS" not in p.stdout:
            problems.append("%s: exit %d\n%s" % (" ".join(cmd), p.returncode, p.stdout[-2000:]))
        if not os.path.isfile(path) or os.path.getsize(path) == 0:
            problems.append("%s: no %s written" % (path, kind.upper()))
    if problems:
        return report(problems)

    h = fst_header(paths["fst"])
    if h is None:
        return report(["%s: shorter than an FST header" % paths["fst"]])
    if h["tag"] != 0 or h["length"] != 329:
        problems.append("%s: not an FST (tag %d, header length %d; expected 0 and 329)"
                        % (paths["fst"], h["tag"], h["length"]))
    if not math.isclose(h["endian_test"], math.e, rel_tol=1e-15):
        problems.append("FST endian test %r, expected e" % h["endian_test"])
    if h["vars"] == 0 or h["sections"] == 0 or h["end"] <= h["start"]:
        problems.append("FST header: %d variables, %d value-change sections, time %d..%d"
                        % (h["vars"], h["sections"], h["start"], h["end"]))

    with open(paths["vcd"]) as f:
        vcd = f.read()
    head, sep, body = vcd.partition("$enddefinitions $end")
    vcd_vars = len(re.findall(r"^\s*\$var ", head, re.M))
    times = re.findall(r"^#(\d+)", body, re.M)
    if not sep or vcd_vars == 0 or not times:
        problems.append("%s: not a VCD (%d $var, %d time stamps, $enddefinitions %s)"
                        % (paths["vcd"], vcd_vars, len(times), "found" if sep else "missing"))
    else:
        if int(times[-1]) != h["end"]:
            problems.append("VCD ends at #%s, the FST at %d" % (times[-1], h["end"]))
        if vcd_vars != h["vars"]:
            problems.append("VCD declares %d variables, the FST %d" % (vcd_vars, h["vars"]))
    leftovers = [n for n in os.listdir(out) if n not in ("w.fst", "w.vcd")]
    if leftovers:
        problems.append("files left in %s: %s" % (out, leftovers))
    sizes = {k: os.path.getsize(p) for k, p in paths.items()}
    print("FST %d bytes, VCD %d bytes (%.1fx); %d variables, time 0..%d"
          % (sizes["fst"], sizes["vcd"], sizes["vcd"] / max(1, sizes["fst"]), h["vars"], h["end"]))
    if not sizes["fst"] < sizes["vcd"]:
        problems.append("the FST (%d bytes) is not smaller than the VCD (%d bytes)"
                        % (sizes["fst"], sizes["vcd"]))
    return report(problems)


def report(problems):
    for p in problems:
        print("FAIL", p)
    print("tb.trace.fst:", "PASS" if not problems else "%d failure(s)" % len(problems))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
