#!/usr/bin/env python3
"""Outputs are written to a temporary name and renamed when complete, so a killed or failed run
never leaves a half-written file that looks complete. For each writer of the `hrpp` tool (ray
stream, the JSON reports of info / predict / trace, render's PNGs and render.json):

  killed:  the run is killed mid-write (RLIMIT_FSIZE below the output's size: the kernel sends
           SIGXFSZ at the write that crosses it): the output does not exist under its name;
  failed:  the same with SIGXFSZ ignored, so the write fails with EFBIG: exit code 2, a message
           naming the file, and neither the output nor its temporary file is left;
  SIGKILL: `hrpp trace` killed with SIGKILL while writing a large stream: no stream under its
           name, and the temporary file is refused by `hrpp predict --stream`.

  atomic_outputs.py HRPP_BINARY SOURCE_DIR        (ctest: tool.atomic_outputs)
"""
import os
import resource
import signal
import subprocess
import sys
import tempfile
import time

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL " + what)


def limited(limit, ignore_sigxfsz):
    def pre():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN if ignore_sigxfsz else signal.SIG_DFL)
    return pre


def png_complete(path):
    with open(path, "rb") as f:
        data = f.read()
    return data.startswith(b"\x89PNG") and data[-12:-4] == b"\0\0\0\0IEND"


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    tool, src = sys.argv[1], sys.argv[2]
    scene = os.path.join(src, "scenes", "cornell_box.glb")
    with tempfile.TemporaryDirectory(prefix="hrpp-atomic-") as d:
        def out(name):
            return os.path.join(d, name)

        # (command, outputs that must not appear, file-size limit in bytes)
        cases = [
            ("trace stream", ["trace", scene, "--res", "64x64", "--out", out("t.rays")],
             [out("t.rays")], 65536),
            ("trace --json", ["trace", scene, "--res", "1x1", "--effects", "none", "--out",
                              out("j.rays"), "--json", out("t.json")], [out("t.json")], 512),
            ("predict --json", ["predict", scene, "--res", "8x8", "--json", out("p.json")],
             [out("p.json")], 1024),
            ("info --json", ["info", scene, "--json", out("i.json")], [out("i.json")], 256),
            ("render", ["render", scene, "--res", "48x48", "--out", out("render")],
             [out("render/render.json")], 4096),
        ]
        for name, args, outputs, limit in cases:
            for ignore in (False, True):
                for f in outputs + [out("render")]:
                    if os.path.isfile(f):
                        os.remove(f)
                p = subprocess.run([tool] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                   text=True, errors="replace", preexec_fn=limited(limit, ignore),
                                   timeout=120)
                how = "failed" if ignore else "killed"
                if ignore:
                    check(p.returncode == 2, f"{name} ({how}): exit code {p.returncode}, expected 2; "
                                             f"stderr: {p.stderr.strip()[-300:]}")
                    check("writ" in p.stderr or "cannot" in p.stderr,
                          f"{name} ({how}): no write error message: {p.stderr.strip()[-300:]}")
                else:
                    check(p.returncode == -signal.SIGXFSZ,
                          f"{name} ({how}): expected death by SIGXFSZ, got exit {p.returncode} "
                          f"(raise the output size or lower the limit)")
                for f in outputs:
                    check(not os.path.exists(f), f"{name} ({how}): {f} exists after the run")
                    if ignore:
                        check(not os.path.exists(f + ".tmp"),
                              f"{name} ({how}): {f}.tmp left behind")
                if name == "render" and os.path.isdir(out("render")):
                    for f in os.listdir(out("render")):
                        if f.endswith(".png"):
                            check(png_complete(out("render/" + f)),
                                  f"render ({how}): {f} exists but is incomplete")
                print(f"{name} ({how}): exit {p.returncode}, no complete-looking output")

        # SIGKILL mid-stream.
        rays = out("big.rays")
        p = subprocess.Popen([tool, "trace", scene, "--res", "512x512", "--spp", "8", "--out", rays],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        t0 = time.time()
        while time.time() - t0 < 60 and p.poll() is None:
            if os.path.exists(rays + ".tmp") and os.path.getsize(rays + ".tmp") > (1 << 20):
                break
            time.sleep(0.02)
        still_running = p.poll() is None
        p.kill()
        p.wait()
        check(still_running, "SIGKILL: the trace ended before it could be killed mid-write")
        check(not os.path.exists(rays), "SIGKILL: the stream exists under its name")
        if os.path.exists(rays + ".tmp"):
            q = subprocess.run([tool, "predict", scene, "--stream", rays + ".tmp"],
                               capture_output=True, text=True)
            check(q.returncode == 2 and "bytes after the 0 records" in q.stderr,
                  f"SIGKILL: the temporary stream was not refused (exit {q.returncode}: "
                  f"{q.stderr.strip()[-200:]})")
        print("trace (SIGKILL mid-write): no stream under its name, the temporary file is refused")
    print(f"tool.atomic_outputs: {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
