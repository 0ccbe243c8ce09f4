#!/usr/bin/env python3
"""The command lines of all four binaries (hrpp, tb_hrpp, tb_hash, hrpp_bench) behave alike
(model/include/hrpp/util/cli.h): every usage error exits 2, a misspelt option or subcommand gets
"did you mean ...?", --version prints the project version and the git commit built from on one line
(exit 0), `tb_hash --help` prints help instead of running, and tb_hrpp checks its --trace output
before any simulation.

  cli_errors.py HRPP TB_HRPP TB_HASH HRPP_BENCH SOURCE_DIR

Exit status 0 when every case passes, 1 otherwise. ctest runs it as `tool.cli`.
"""
import os
import re
import subprocess
import sys
import tempfile
import time


def git_head(source_dir):
    """The full commit hash of the checkout in source_dir, or None when it is not the top of one."""
    try:
        top = subprocess.run(["git", "rev-parse", "--show-toplevel"], cwd=source_dir,
                             capture_output=True, text=True, timeout=30)
        if top.returncode != 0 or \
                os.path.realpath(top.stdout.strip()) != os.path.realpath(source_dir):
            return None
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=source_dir,
                              capture_output=True, text=True, timeout=30)
        return head.stdout.strip() if head.returncode == 0 else None
    except (OSError, subprocess.TimeoutExpired):
        return None


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    hrpp, tb_hrpp, tb_hash, bench, source = sys.argv[1:]
    scene = os.path.join(source, "scenes", "spd_balls.glb")
    tools = {"hrpp": hrpp, "tb_hrpp": tb_hrpp, "tb_hash": tb_hash, "hrpp_bench": bench}
    head = git_head(source)
    failures = 0
    tmp = tempfile.mkdtemp(prefix="hrpp_cli_")

    def run(argv, code, stderr_re=None, stdout_re=None, limit=10.0, name=None, check=None,
            cwd=None):
        nonlocal failures
        name = name or " ".join(os.path.basename(a) if i == 0 else a for i, a in enumerate(argv))
        t0 = time.monotonic()
        try:
            p = subprocess.run(argv, capture_output=True, text=True, timeout=limit * 3, cwd=cwd)
        except subprocess.TimeoutExpired:
            print("FAIL %s: no exit within %.0f s" % (name, limit * 3))
            failures += 1
            return
        dt = time.monotonic() - t0
        problems = []
        if p.returncode != code:
            problems.append("exit %d, expected %d" % (p.returncode, code))
        if stderr_re and not re.search(stderr_re, p.stderr):
            problems.append("stderr does not match %r" % stderr_re)
        if stdout_re and not re.search(stdout_re, p.stdout):
            problems.append("stdout does not match %r" % stdout_re)
        if dt > limit:
            problems.append("took %.1f s (limit %.0f s)" % (dt, limit))
        if check:
            problems += check(p)
        if problems:
            failures += 1
            print("FAIL %s: %s\n  stdout: %s\n  stderr: %s" % (
                name, "; ".join(problems), p.stdout.strip()[-600:], p.stderr.strip()[-600:]))
        else:
            print("ok   %s" % name)

    # --version: one line, the project version and the commit (HEAD's hash when built from this
    # checkout, "-dirty" when it had changes; "unknown" outside a git checkout).
    for tool, path in tools.items():
        def version_check(p, tool=tool):
            m = re.fullmatch(r"%s (\d+\.\d+\.\d+) \(commit (\S+)\)\n" % tool, p.stdout)
            if not m:
                return ["not one line 'TOOL VERSION (commit COMMIT)': %r" % p.stdout]
            commit = m.group(2)
            if head is None:
                return [] if commit == "unknown" else ["commit %s outside a git checkout" % commit]
            h = re.sub(r"-dirty$", "", commit).split("-g")[-1]
            if not (re.fullmatch(r"[0-9a-f]{7,40}", h) and head.startswith(h)):
                return ["commit %s is not the checkout's HEAD %s (rebuild?)" % (commit, head)]
            return []
        run([path, "--version"], 0, check=version_check, limit=5)

    # A misspelt option or subcommand: exit 2 and a suggestion (before: exit 2 without one for
    # hrpp and hrpp_bench, CLI11's 109 for tb_hrpp; tb_hash ran the test).
    run([hrpp, "predict", scene, "--sede", "3"], 2, r"unknown option --sede: did you mean --seed\?")
    run([hrpp, "predcit", scene], 2, r"unknown argument predcit: did you mean predict\?")
    run([hrpp, "render", scene, "--res=8x8", "--depht=2"], 2,
        r"unknown option --depht: did you mean --depth\?")
    run([tb_hrpp, "--scene", scene, "--sede", "3"], 2, r"unknown option --sede: did you mean --seed\?")
    run([tb_hrpp, "--scen", scene], 2, r"unknown option --scen: did you mean --scene\?")
    run([tb_hash, "--versoin"], 2, r"unknown option --versoin: did you mean --version\?", limit=2)
    run([bench, "--reeps", "3"], 2, r"unknown option --reeps: did you mean --reps\?", limit=5)
    # Nothing close: no suggestion, still exit 2.
    run([tb_hrpp, "--scene", scene, "--frobnicate"], 2, r"not expected: --frobnicate",
        check=lambda p: ["a suggestion for --frobnicate"] if "did you mean" in p.stderr else [])

    # Every other kind of usage error exits 2 too (tb_hrpp: CLI11's 105-109 before).
    run([tb_hrpp, "--scene", scene, "--rays", "0"], 2, r"--rays")            # validation (105)
    run([tb_hrpp, "--rays", "10"], 2, r"--scene,--stream,--latency")           # required (106)
    run([tb_hrpp, "--scene", scene, "--config", "huge"], 2, r"--config")      # not a member
    run([tb_hrpp, "--scene", scene, "--seed", "x"], 2, r"--seed")             # conversion
    run([tb_hrpp, "--scene", scene, "--scene", scene], 2, r"--scene")         # given twice
    run([tb_hash, "many"], 2, r"count", limit=2)
    run([tb_hash, "10", "20"], 2, r"not expected: 20", limit=2)
    run([bench, "--reps", "0"], 2, r"--reps", limit=5)

    # tb_hash --help prints help and does not run the test; a count still runs it.
    run([tb_hash, "--help"], 0, stdout_re=r"Usage:.*tb_hash.*\[count\]", limit=2,
        check=lambda p: ["ran the test"] if "mismatches" in p.stdout else [])
    run([tb_hash, "1000"], 0, stdout_re=r"hash: \d+ vectors x 13 configurations, 0 mismatches",
        limit=20)
    for tool in ("hrpp", "tb_hrpp", "hrpp_bench"):
        run([tools[tool], "--help"], 0, stdout_re=r"--version", limit=5)
    # --help shows the predictor options' defaults (the golden model's, before any preset).
    for sub in ("predict", "render", "simulate"):
        run([hrpp, sub, "--help"], 0, limit=5, name="hrpp %s --help: defaults" % sub,
            check=lambda p: [
                "no default shown for " + opt for opt, rx in (
                    ("--hash", r"--hash TEXT:\{[^}]*\}=faithful"),
                    ("--precision", r"--precision INT:[^\n]*=6"),
                    ("--table", r"--table TEXT=unbounded"),
                    ("--mode", r"--mode TEXT:\{[^}]*\}=closest-exact"),
                    ("--go-up", r"--go-up UINT:[^\n]*=0"),
                    ("--nodes-per-entry", r"--nodes-per-entry UINT:[^\n]*=1"),
                    ("--spp", r"--spp INT:[^\n]*=1"),
                    ("--seed", r"--seed UINT=1"),
                    ("--preset", r"--preset TEXT:\{[^}]*rtl-primary[^}]*\}\|FILE\.json\s+[^\n]*"
                                 r"Default: rtl-default unless a hash or table option is given")) +
                    ((("--timing", r"--timing TEXT:\{simulate,cost-model\}=simulate"),
                      ("--gpu", r"--gpu TEXT=mobile")) if sub != "simulate" else ()) +
                    ((("--update-delay", r"--update-delay UINT=0"),) if sub == "predict" else ())
                if not re.search(rx, p.stdout)])

    # --ao-distance inf: unbounded AO rays (tfar = +inf) are valid, recorded as "inf" in the JSON,
    # and hit at least as often as the default 5%-of-the-diagonal rays (here strictly more). With
    # --preset micro21 only the AO rays (any hit) are offered to the predictor.
    import json
    ao_hits = {}
    for dist in ("0", "inf"):
        out = os.path.join(tmp, "ao_%s.json" % dist)

        def ao_check(p, out=out, dist=dist):
            try:
                j = json.load(open(out))
            except (OSError, ValueError) as e:
                return ["no JSON: %s" % e]
            ao, prim = j["by_kind"]["ao"], j["by_kind"]["primary"]
            ao_hits[dist] = ao["baseline_hits"]
            problems = []
            want = "inf" if dist == "inf" else None
            if want and j["workload"]["ao_distance"] != want:
                problems.append("ao_distance %r, expected %r" % (j["workload"]["ao_distance"], want))
            if dist == "0" and not isinstance(j["workload"]["ao_distance"], float):
                problems.append("ao_distance %r is not a number" % j["workload"]["ao_distance"])
            if ao["rays"] == 0 or ao["invalid_rays"] != 0:
                problems.append("AO rays %d, invalid %d" % (ao["rays"], ao["invalid_rays"]))
            if j["config"]["hash"] != "micro21" or j["config"]["predict_kinds"] != "any-hit":
                problems.append("config %r is not micro21's" % j["config"])
            if prim["unoffered_rays"] != prim["rays"] or prim["table_updates"] != 0:
                problems.append("primary rays reached the predictor: %r" % prim)
            if ao["unoffered_rays"] != 0:
                problems.append("AO rays not offered: %d" % ao["unoffered_rays"])
            return problems
        run([hrpp, "predict", scene, "--res", "16x16", "--effects", "ao", "--ao-distance", dist,
             "--preset", "micro21", "--json", out], 0, stdout_re=r"any-hit rays only",
            check=ao_check, limit=20)
    if len(ao_hits) == 2 and not ao_hits["inf"] > ao_hits["0"]:
        print("FAIL unbounded AO rays hit %d times, bounded ones %d" % (ao_hits["inf"], ao_hits["0"]))
        failures += 1

    # --json -: the JSON alone on standard output, the text report on standard error (before: a
    # file named '-').
    def json_on_stdout(text_re):
        def check(p):
            problems = []
            try:
                j = json.loads(p.stdout)
                if not isinstance(j, dict) or "scene" not in j:
                    problems.append("stdout is JSON but not the report: %r" % p.stdout[:200])
            except ValueError as e:
                problems.append("stdout is not the JSON alone (%s): %r" % (e, p.stdout[:200]))
            if not re.search(text_re, p.stderr):
                problems.append("the text report is not on stderr (%r)" % text_re)
            if os.path.exists(os.path.join(tmp, "-")):
                problems.append("wrote a file named '-'")
                os.remove(os.path.join(tmp, "-"))
            return problems
        return check
    run([hrpp, "predict", scene, "--res", "8x8", "--json", "-"], 0, limit=20, cwd=tmp,
        check=json_on_stdout(r"cost model .* cycles per ray"))
    run([hrpp, "info", scene, "--json", "-"], 0, limit=20, cwd=tmp,
        check=json_on_stdout(r"triangles +\d+"))
    run([hrpp, "simulate", scene, "--res", "8x8", "--no-per-kind", "--json", "-"], 0, limit=30,
        cwd=tmp, check=json_on_stdout(r"speed-up"))

    # Self-describing JSON (issue 20): every report names the tool, its version and commit, the
    # command line (shell-quoted: it runs again as it is) and when it ran; what was not measured
    # is null; the hash's P is config.precision_bits beside the prediction precision.
    import datetime
    import shlex
    odd = os.path.join(tmp, "it's a folder")
    os.makedirs(odd, exist_ok=True)

    def tool_problems(j, argv):
        t = j.get("tool")
        if not isinstance(t, dict):
            return ["no tool object"]
        problems = []
        if t.get("name") != "hrpp":
            problems.append("tool.name %r" % t.get("name"))
        if not re.fullmatch(r"\d+\.\d+\.\d+", str(t.get("version"))):
            problems.append("tool.version %r" % t.get("version"))
        c = str(t.get("git_commit"))
        if head and not head.startswith(re.sub(r"-dirty$", "", c).split("-g")[-1]):
            problems.append("tool.git_commit %r is not HEAD %s" % (c, head))
        if shlex.split(t.get("command_line") or "") != argv:
            problems.append("tool.command_line %r, expected %r" % (t.get("command_line"),
                                                                   shlex.join(argv)))
        try:
            ts = datetime.datetime.strptime(t.get("timestamp", ""), "%Y-%m-%dT%H:%M:%SZ")
            age = datetime.datetime.utcnow() - ts
            if not datetime.timedelta(seconds=-5) <= age <= datetime.timedelta(minutes=5):
                problems.append("tool.timestamp %s is not now (UTC)" % t["timestamp"])
        except ValueError:
            problems.append("tool.timestamp %r is not UTC ISO 8601" % t.get("timestamp"))
        return problems

    def json_report(path, more=None):
        def check(p, path=path):
            try:
                j = json.load(open(path))
            except (OSError, ValueError) as e:
                return ["no JSON: %s" % e]
            return tool_problems(j, p.args) + (more(j) if more else [])
        return check

    def predict_keys(table, measured):
        def more(j):
            problems = []
            cfg = j["config"]
            if "precision" in cfg or cfg.get("precision_bits") != 6:
                problems.append("config: precision %r, precision_bits %r" % (
                    cfg.get("precision"), cfg.get("precision_bits")))
            if not isinstance(j.get("precision"), float):
                problems.append("top-level precision (TP / (TP + FP)) %r" % j.get("precision"))
            if cfg.get("pipeline_latency", 0) is not None:
                problems.append("pipeline_latency %r for none given" % cfg.get("pipeline_latency"))
            for where, x in [("", j)] + [("by_kind." + k, v) for k, v in j["by_kind"].items()]:
                for key in ("baseline_ns", "hrpp_ns"):
                    if measured != isinstance(x.get(key, 0), int) or \
                            (not measured and x.get(key, 0) is not None):
                        problems.append("%s%s %r (measured: %s)" % (where, key, x.get(key),
                                                                   measured))
            if j.get("table_unbounded") is not (table == "unbounded") or \
                    not isinstance(j.get("table_bytes"), int):
                problems.append("table %s: table_unbounded %r, table_bytes %r" % (
                    table, j.get("table_unbounded"), j.get("table_bytes")))
            return problems
        return more

    pj = os.path.join(odd, "p.json")
    run([hrpp, "predict", scene, "--res", "8x8", "--hash", "faithful", "--table", "unbounded",
         "--json", pj], 0, limit=20,
        name="predict --json: tool, precision_bits, null times, table_unbounded",
        check=json_report(pj, predict_keys("unbounded", False)))
    run([hrpp, "predict", scene, "--res", "8x8", "--table", "64x4", "--measure-time", "--json",
         pj], 0, limit=20, name="predict --json --measure-time --table 64x4",
        check=json_report(pj, predict_keys("64x4", True)))

    # Named configurations (issue 20): the default of predict is rtl-default; --preset FILE.json
    # (option names as keys, "preset" the named preset it starts from) with the command line over
    # it; its errors name the file, the key and a suggestion.
    def preset_check(name, base, table, go_up, mode, file=None):
        def more(j):
            want = {"name": name, "base": base, "file": file}
            got = (j.get("preset"), j["config"].get("table"), j["config"].get("go_up"),
                   j["config"].get("mode"))
            tbl = got[1] if isinstance(got[1], str) else "%sx%s" % (
                got[1].get("sets"), got[1].get("ways")) if isinstance(got[1], dict) else got[1]
            if got[0] != want or tbl != table or got[2] != go_up or got[3] != mode:
                return ["preset %r table %r go_up %r mode %r; expected %r %r %r %r" % (
                    got[0], tbl, got[2], got[3], want, table, go_up, mode)]
            return []
        return more
    T = ["--timing", "cost-model"]
    run([hrpp, "predict", scene, "--res", "8x8", "--json", pj] + T, 0, limit=20,
        name="predict: the default is rtl-default",
        check=json_report(pj, preset_check("rtl-default", "rtl-default", "128x4", 0,
                                           "closest-exact")))
    pf = os.path.join(odd, "mine.json")
    with open(pf, "w") as f:
        f.write('{"name": "mine", "preset": "micro21", "go_up": 1, "mode": "closest-spec"}')
    run([hrpp, "predict", scene, "--res", "8x8", "--preset", pf, "--json", pj] + T, 0,
        limit=20, name="predict --preset FILE.json: its values over its base preset's",
        check=json_report(pj, preset_check("mine", "micro21", "256x4", 1, "closest-spec", pf)))
    run([hrpp, "predict", scene, "--res", "8x8", "--preset", pf, "--go-up", "2", "--table",
         "64x4", "--json", pj] + T, 0, limit=20,
        name="predict --preset FILE.json: the command line over the file",
        check=json_report(pj, preset_check("mine", "micro21", "64x4", 2, "closest-spec", pf)))
    for body, err in (
            ('{"gp_up": 1}', r'unknown key "gp_up"; did you mean go_up\?'),
            ('{"preset": "rtl-defualt"}', r"\"preset\": 'rtl-defualt' is not a preset; did you mean rtl-default\?"),
            ('{"go_up": 99}', r'"go_up": .*99'),
            ('{"go_up": "one"}', r'"go_up" must be an integer'),
            ('{"table": 4}', r'"table" must be a string'),
            ('[1, 2]', r"not a JSON object"),
            ('{"go_up": 1', r"not valid JSON"),
            ('{"hash": "improved", "precision": 4}',
             r"--precision \(--preset .*mine\.json\) applies only to the faithful hash.*uses "
             r"--hash improved \(--preset ")):
        with open(pf, "w") as f:
            f.write(body)
        run([hrpp, "predict", scene, "--res", "8x8", "--preset", pf], 2,
            r"hrpp predict: (--preset .*mine\.json: )?" + err,
            name="predict --preset FILE.json: " + body)
    run([hrpp, "predict", scene, "--res", "8x8", "--preset", os.path.join(odd, "none.json")], 2,
        r"--preset .*none\.json: cannot read it: No such file", name="predict --preset missing.json")
    run([hrpp, "simulate", scene, "--res", "8x8", "--preset", "rtl-defualt"], 2,
        r"did you mean rtl-default\?", name="simulate --preset misspelt")

    # info --json holds everything its text shows (issue 20: it lacked the camera, the lights and
    # the materials): the camera's vectors, each light and each material by name.
    def info_complete(p):
        try:
            j = json.load(open(ij))
        except (OSError, ValueError) as e:
            return ["no JSON: %s" % e]
        problems = []
        text = p.stdout
        cam = j.get("camera")
        if not isinstance(cam, dict):
            return ["camera %r" % cam]
        for key in ("eye", "target", "up"):
            m = re.search(r"\s%s \(([^)]*)\)" % key, text)
            want = [float(x) for x in m.group(1).split(",")] if m else None
            if want is None or any(abs(a - b) > 1e-3 * max(1, abs(b))
                                   for a, b in zip(cam.get(key, []), want)):
                problems.append("camera.%s %r, text %r" % (key, cam.get(key), want))
        m = re.search(r"lights +(\d+) punctual, (\d+) emissive", text)
        lights = j.get("lights")
        if not m or not isinstance(lights, list) or len(lights) != int(m.group(1)) or \
                j.get("emissive_triangles") != int(m.group(2)):
            problems.append("lights %r against %r" % (lights, m and m.group(0)))
        else:
            for l in lights:
                if not re.search(r"\n +%s +%s +intensity" % (re.escape(l["name"]), l["type"]),
                                 text):
                    problems.append("light %r not in the text" % l)
        mats = j.get("materials")
        m = re.search(r"materials +(\d+)", text)
        if not m or not isinstance(mats, list) or len(mats) != int(m.group(1)):
            problems.append("materials %r against %r" % (mats, m and m.group(0)))
        else:
            for x in mats:
                if not re.search(r"\n +%s +base .*, %d triangles" % (re.escape(x["name"]),
                                                                       x["triangles"]), text):
                    problems.append("material %r not in the text" % x)
        return problems
    ij = os.path.join(odd, "info.json")
    apartment = os.path.join(source, "..", "shared", "scenes", "dream_apartment.glb")
    for sc in [os.path.join(source, "scenes", "cornell_box.glb")] + \
            ([apartment] if os.path.exists(apartment) else []):
        run([hrpp, "info", sc, "--json", ij], 0, limit=30, check=info_complete,
            name="info --json: complete (%s)" % os.path.basename(sc))

    # Time first (issue 20): the report's first result line is the simulated time on RT units,
    # with its verdict in words, then the cost model's; the JSON's "time" says which and how.
    def time_first(timing):
        def check(p):
            lines = [l for l in p.stdout.splitlines() if l.startswith("  ") and
                     not l.startswith("    ") and ":" in l]
            i = next((k for k, l in enumerate(lines) if "cycles" in l), None)
            problems = []
            pred = next((k for k, l in enumerate(lines) if l.startswith("  predictor ")), None)
            if pred is None or i is None or pred > i:
                problems.append("no configuration line before the time")
            first = lines[i] if i is not None else ""
            want = "  time on mobile RT units" if timing == "simulate" else \
                "  time by the cost model"
            if not first.startswith(want) or not re.search(
                    r"speed-up \d+\.\d+x: (saves|COSTS) \d+\.\d% time|no change in time", first):
                problems.append("the first result line %r" % first)
            if re.search(r"skipped", "\n".join(lines[:i + 1] if i is not None else lines)):
                problems.append("skipped work before the time")
            j = json.load(open(pj))
            t = j.get("time", {})
            if t.get("timing") != timing:
                problems.append("time.timing %r" % t.get("timing"))
            elif (timing == "simulate" and t.get("gpu") != "mobile") or \
                    t["baseline_cycles"] <= 0 or \
                    abs(t["speedup"] - t["baseline_cycles"] / t["cycles"]) > 1e-9 or \
                    (t["speedup"] < 1) != ("COSTS" in first):
                problems.append("time %r against %r" % (t, first))
            return problems
        return check
    # At 16x16 the primary configuration saves time on spd_balls and costs time on the Cornell box.
    cornell = os.path.join(source, "scenes", "cornell_box.glb")
    for sc, verdict in ((scene, "saves"), (cornell, "COSTS")):
        run([hrpp, "predict", sc, "--res", "16x16", "--preset", "rtl-primary", "--json", pj], 0,
            limit=30,
            stdout_re=r"\n  time on mobile RT units.*: " + verdict,
            name="predict: leads with the simulated time (%s: %s)" % (os.path.basename(sc),
                                                                        verdict),
            check=time_first("simulate"))
    run([hrpp, "predict", scene, "--res", "16x16", "--json", pj, "--timing", "cost-model"], 0,
        limit=20, name="predict --timing cost-model: leads with the cost model's time",
        check=time_first("cost-model"))
    run([hrpp, "predict", scene, "--res", "8x8", "--timing", "cost-model", "--gpu", "desktop"],
        2, r"--gpu applies only to --timing simulate", name="predict --gpu with cost-model")
    run([hrpp, "predict", scene, "--res", "8x8", "--gpu", "laptop"], 2,
        r"hrpp predict: --gpu laptop: .*known: desktop, micro21-sim, mobile", name="predict --gpu unknown")
    for argv, path in (
            (["info", scene], "i.json"), (["check-embree", scene, "--rays", "100"], "c.json"),
            (["simulate", scene, "--res", "8x8", "--no-per-kind"], "s.json"),
            (["trace", scene, "--res", "8x8", "--out", os.path.join(tmp, "t.rays")], "t.json")):
        path = os.path.join(odd, path)
        run([hrpp] + argv + ["--json", path], 0, limit=30, check=json_report(path),
            name="%s --json: tool object" % argv[0])
    rdir = os.path.join(odd, "render")
    run([hrpp, "render", scene, "--res", "8x8", "--out", rdir], 0, limit=30,
        check=json_report(os.path.join(rdir, "render.json")),
        name="render: render.json's tool object")

    # render writes all pictures of one run or none: a second run into the same folder replaces
    # the earlier render whole (a stale file goes with it), and no staging folder is left.
    with open(os.path.join(rdir, "stale.png"), "w") as f:
        f.write("from an earlier run")

    def replaced(p):
        left = sorted(os.listdir(odd))
        problems = []
        if os.path.exists(os.path.join(rdir, "stale.png")):
            problems.append("the earlier run's stale.png is still there")
        if not os.path.exists(os.path.join(rdir, "shaded.png")):
            problems.append("no shaded.png")
        problems += ["left behind: " + n for n in left if ".rendering" in n or ".old-" in n]
        return problems
    run([hrpp, "render", scene, "--res", "8x8", "--out", rdir], 0, limit=30, check=replaced,
        name="render: a run replaces an earlier render whole")

    # SIGINT / SIGTERM during a long run: the unfinished output's temporary file is removed, one
    # line says so, exit 130 / 143 (before: killed by the signal, a PATH.tmp of hundreds of MB
    # left behind).
    import shutil
    import signal

    def report(name, problems):
        nonlocal failures
        if problems:
            failures += 1
            print("FAIL %s: %s" % (name, "; ".join(problems)))
        else:
            print("ok   %s" % name)

    def signal_and_wait(p, sig):
        """Sends SIG to the process P and returns its standard output and error."""
        p.send_signal(sig)
        try:
            return p.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            p.kill()
            return p.communicate()

    def first_progress_line(argv, sub):
        """Starts ARGV with standard output to a file and standard error piped; returns its first
        standard-error line, the seconds it took, and what standard output held by then. The
        run is then killed (SIGINT)."""
        os.makedirs(sub, exist_ok=True)
        out_path = os.path.join(sub, "stdout.txt")
        with open(out_path, "w") as out_f:
            p = subprocess.Popen(argv, stdout=out_f, stderr=subprocess.PIPE, text=True)
            t0 = time.monotonic()
            line = p.stderr.readline()
            dt = time.monotonic() - t0
            stdout_then = open(out_path).read()
            signal_and_wait(p, signal.SIGINT)
        shutil.rmtree(sub, ignore_errors=True)
        return line, dt, stdout_then

    def progress_problems(label, unit, line, dt):
        """A progress line "LABEL: 42.0% of N UNIT, RATE UNIT/s, T left" after about 2 s."""
        if not re.fullmatch(r"%s: +\d+\.\d%% of \d+ %s, [\d.]+ (M )?\S.*/s, "
                            r"(\d+ s|\d+ min \d+ s|\d+ h \d+ min) left\n" % (label, unit), line):
            return ["first stderr line %r is not a progress line" % line]
        if dt < 1.5:
            return ["a progress line after %.1f s (expected none in the first 2 s)" % dt]
        return []
    for cmd, sig, code, word in (("trace", signal.SIGINT, 130, "interrupted"),
                                 ("trace", signal.SIGTERM, 143, "terminated"),
                                 ("predict", signal.SIGINT, 130, "interrupted")):
        name = "%s interrupted by %s" % (cmd, sig.name)
        sub = os.path.join(tmp, "sig_%s_%s" % (cmd, sig.name))
        os.makedirs(sub)
        out = os.path.join(sub, "big.rays" if cmd == "trace" else "p.json")
        p = subprocess.Popen([hrpp, cmd, scene, "--res", "2048x2048", "--spp", "4",
                              "--out" if cmd == "trace" else "--json", out],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        t0 = time.monotonic()
        if cmd == "trace":  # until the stream is being written
            while not os.path.exists(out + ".tmp") and p.poll() is None and \
                    time.monotonic() - t0 < 60:
                time.sleep(0.05)
        time.sleep(0.3 if cmd == "trace" else 2.0)  # well into the run
        started = p.poll() is None and (cmd != "trace" or os.path.exists(out + ".tmp"))
        stdout, stderr = signal_and_wait(p, sig)
        problems = [] if started else ["the run ended (or wrote no %s.tmp) before the signal" % out]
        if p.returncode != code:
            problems.append("exit %d, expected %d" % (p.returncode, code))
        want = "hrpp: %s (%s): unfinished outputs removed\n" % (word, sig.name)
        if not stderr.endswith(want) or stderr.count("hrpp: ") != 1:  # after progress lines
            problems.append("stderr %r, expected the one line %r" % (stderr[-300:], want))
        if os.listdir(sub):
            problems.append("left %s" % os.listdir(sub))
        if cmd == "predict" and "predictor rtl-default:" not in stdout:
            problems.append("the configuration was not printed before the run")
        shutil.rmtree(sub, ignore_errors=True)  # hundreds of MB when the .tmp is left
        report(name, problems)

    # render's progress (issue 20): the configuration (scene, workload, predictor) on standard
    # output before the run, then, piped, a progress line every few seconds on standard error
    # with the share done, the rate and the time left (before: silence until the end).
    name = "render: configuration first, then progress lines when piped"
    line, dt, stdout_then = first_progress_line(
        [hrpp, "render", scene, "--res", "2048x2048", "--spp", "2", "--preset", "rtl-primary",
         "--out", os.path.join(tmp, "render_progress", "r")], os.path.join(tmp, "render_progress"))
    problems = progress_problems("render: (shading|predictor)", "(pixels|camera samples)", line,
                                 dt)
    if not re.search(r"render \S*spd_balls\.glb: 2048x2048, 2 spp.*\n(.*\n)*  preset rtl-primary: "
                     r"hash improved .*table 128x8", stdout_then):
        problems.append("the configuration was not printed before the run: %r" % stdout_then[-400:])
    report(name, problems)

    # tb_hrpp: --config takes the RTL configurations by their preset names too; the configuration
    # first, then (piped) progress lines on standard error after about 2 s.
    name = "tb_hrpp --config rtl-primary: configuration first, then progress lines when piped"
    line, dt, stdout_then = first_progress_line(
        [tb_hrpp, "--scene", scene, "--rays", "4000000", "--config", "rtl-primary"],
        os.path.join(tmp, "tb_progress"))
    problems = progress_problems("tb_hrpp", "rays", line, dt)
    if not stdout_then.startswith("tb_hrpp: config primary (improved hash, 128 sets x 8 ways"):
        problems.append("the configuration was not printed before the run: %r" % stdout_then[:300])
    report(name, problems)
    # tb_hrpp interrupted while writing a waveform: the waveform (and the FST writer's own
    # temporary file) removed, one line, exit 130 / 143.
    for sig, code, word in ((signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143,
                                                                  "terminated")):
        name = "tb_hrpp --trace interrupted by %s" % sig.name
        sub = os.path.join(tmp, "tb_sig_%s" % sig.name)
        os.makedirs(sub)
        p = subprocess.Popen([tb_hrpp, "--scene", scene, "--rays", "2000000", "--trace",
                              os.path.join(sub, "w.vcd")], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        t0 = time.monotonic()
        while not os.listdir(sub) and p.poll() is None and time.monotonic() - t0 < 30:
            time.sleep(0.05)
        time.sleep(0.5)
        started = p.poll() is None and bool(os.listdir(sub))
        _, stderr = signal_and_wait(p, sig)
        problems = [] if started else ["the run ended (or wrote nothing) before the signal"]
        if p.returncode != code:
            problems.append("exit %d, expected %d" % (p.returncode, code))
        want = "tb_hrpp: %s (%s): unfinished outputs removed\n" % (word, sig.name)
        if not stderr.endswith(want):
            problems.append("stderr %r, expected the line %r" % (stderr[-300:], want))
        if os.listdir(sub):
            problems.append("left %s" % os.listdir(sub))
        report(name, problems)
    run([tb_hrpp, "--scene", scene, "--rays", "10", "--config", "rtl-defualt"], 2,
        r"did you mean|rtl-primary", name="tb_hrpp --config misspelt")

    # tb_hrpp --trace: checked before any simulation (before: nothing written, PASS, exit 0).
    def nothing_run(p):
        return ["ran before checking its output: %r" % p.stdout[:200]] if p.stdout.strip() else []
    missing = os.path.join(tmp, "no_such_folder")
    run([tb_hrpp, "--scene", scene, "--rays", "2000", "--trace", os.path.join(missing, "w.vcd")],
        2, r"--trace .*w\.vcd: the folder '%s' does not exist" % re.escape(missing),
        check=nothing_run, limit=5, name="tb_hrpp --trace MISSING_FOLDER/w.vcd")
    run([tb_hrpp, "--scene", scene, "--rays", "2000", "--trace", tmp], 2,
        r"--trace .*: '%s' is a folder, not a file" % re.escape(tmp), check=nothing_run, limit=5,
        name="tb_hrpp --trace FOLDER")
    afile = os.path.join(tmp, "a_file")
    open(afile, "w").close()
    run([tb_hrpp, "--scene", scene, "--rays", "2000", "--trace", os.path.join(afile, "w.vcd")], 2,
        r"'%s' is not a folder" % re.escape(afile), check=nothing_run, limit=5,
        name="tb_hrpp --trace FILE/w.vcd")
    vcd = os.path.join(tmp, "w.vcd")

    def vcd_written(p):
        return [] if os.path.isfile(vcd) and os.path.getsize(vcd) > 1000 else ["no waveform written"]
    run([tb_hrpp, "--scene", scene, "--rays", "300", "--config", "small", "--trace", vcd], 0,
        stdout_re=r"\nPASS", check=vcd_written, limit=60, name="tb_hrpp --trace FOLDER/w.vcd")

    print("%s: %d failure(s)" % (os.path.basename(sys.argv[0]), failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
