#!/usr/bin/env python3
"""The shared Python helpers (pyhrpp/): atomic writing, the docs-block rewriting, the RTL
configurations' loader and running a tool for its JSON report.

  pyhrpp_test.py        (ctest: pyhrpp.unit)
"""
import contextlib
import io
import json
import os
import pathlib
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from pyhrpp import rtl_config  # noqa: E402
from pyhrpp.docs import replace_block, update_blocks  # noqa: E402
from pyhrpp.files import commit_tmp, tmp_path, write_atomic, write_json_atomic  # noqa: E402
from pyhrpp.tools import ToolFailed, run_json  # noqa: E402


class Files(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory(prefix="pyhrpp-")
        self.d = pathlib.Path(self.dir.name)

    def tearDown(self):
        self.dir.cleanup()

    def test_writes_text_bytes_and_json_without_leaving_the_temporary(self):
        write_atomic(self.d / "a.txt", "text\n")
        write_atomic(str(self.d / "b.bin"), b"\x00\xff")
        write_json_atomic(self.d / "c.json", {"x": [1, 2]}, indent=1)
        self.assertEqual((self.d / "a.txt").read_text(), "text\n")
        self.assertEqual((self.d / "b.bin").read_bytes(), b"\x00\xff")
        self.assertEqual((self.d / "c.json").read_text(), '{\n "x": [\n  1,\n  2\n ]\n}\n')
        self.assertEqual(sorted(os.listdir(self.d)), ["a.txt", "b.bin", "c.json"])
        self.assertEqual(tmp_path(self.d / "a.txt"), self.d / "a.txt.tmp")

    def test_a_failed_write_leaves_the_target_as_it_was_and_no_temporary(self):
        target = self.d / "out.md"
        target.write_text("old\n")
        with self.assertRaises(UnicodeEncodeError):  # fails after the temporary was opened
            write_atomic(target, "new \udcff\n")
        self.assertEqual(target.read_text(), "old\n")
        self.assertEqual(os.listdir(self.d), ["out.md"])

    def test_an_unwritable_target_raises_naming_the_file(self):
        target = self.d / "no" / "such" / "out.json"
        with self.assertRaises(FileNotFoundError) as e:
            write_atomic(target, "x")
        self.assertIn("out.json.tmp", str(e.exception))

    def test_a_failed_rename_removes_the_temporary(self):
        target = self.d / "dir"
        (target / "inside").mkdir(parents=True)  # a non-empty directory cannot be replaced
        with self.assertRaises(OSError):
            write_atomic(target, "x")
        self.assertFalse(tmp_path(target).exists())
        tmp_path(target).write_text("y")
        with self.assertRaises(OSError):
            commit_tmp(target)
        self.assertFalse(tmp_path(target).exists())


DOC = "# Results\n\nintro\n\n<!-- BEGIN a -->\nold a\n<!-- END a -->\n\nmiddle\n\n" \
      "<!-- BEGIN b -->\nold b\nmore\n<!-- END b -->\ntail\n"


class DocsBlock(unittest.TestCase):
    def test_replaces_only_the_block(self):
        self.assertEqual(replace_block(DOC, "a", "new a"), DOC.replace("old a", "new a"))
        self.assertEqual(replace_block(DOC, "b", "x\ny\n"), DOC.replace("old b\nmore", "x\ny"))

    def test_appends_a_missing_block_under_its_heading(self):
        self.assertEqual(replace_block("# R\n\n", "c", "body\n", "## C"),
                         "# R\n\n## C\n\n<!-- BEGIN c -->\nbody\n<!-- END c -->\n")
        self.assertEqual(replace_block("# R\n", "c", "body"),
                         "# R\n\n<!-- BEGIN c -->\nbody\n<!-- END c -->\n")

    def test_update_blocks_rewrites_the_file(self):
        with tempfile.TemporaryDirectory(prefix="pyhrpp-") as d:
            doc = pathlib.Path(d) / "results.md"
            doc.write_text(DOC)
            update_blocks(doc, {"a": "A", "b": "B"})
            self.assertEqual(doc.read_text(), DOC.replace("old a", "A").replace("old b\nmore", "B"))
            missing = pathlib.Path(d) / "new.md"
            update_blocks(missing, {"s": "S\n"}, {"s": "## S"}, default_text="# Results\n")
            self.assertEqual(missing.read_text(),
                             "# Results\n\n## S\n\n<!-- BEGIN s -->\nS\n<!-- END s -->\n")
            self.assertEqual(sorted(os.listdir(d)), ["new.md", "results.md"])


class RtlConfig(unittest.TestCase):
    """The loader of rtl/config/hrpp_configs.json on small hand-made files."""

    LAT = {"hash_stages": 3, "lookup_stages": 4, "update_stages": 9, "decision_latency": 2}
    BASE = {"variant": "improved", "precision": 6, "exp_bits": 3, "origin_bits": 5,
            "dir_bits": 3, "combine": "concat", "sets": 128, "ways": 8, "nodes_per_entry": 2,
            "node_id_width": 20, "tag_bits": 8, "id_width": 16, "pred_fifo_depth": 16,
            "skip_fifo_depth": 8, "update_queue_depth": 8, "key_store_bram": False,
            "inject_fault": False}

    def load(self, configs, latencies=None, bank_depth=2048):
        with tempfile.TemporaryDirectory(prefix="pyhrpp-") as d:
            path = pathlib.Path(d) / "c.json"
            path.write_text(json.dumps({"latencies": latencies or self.LAT,
                                        "table_bank_depth": bank_depth,
                                        "configurations": configs}))
            return rtl_config.load(path)

    def test_derived_latencies_and_a_base(self):
        data = self.load({"default": self.BASE,
                          "small": {"base": "default", "sets": 64, "variant": "faithful"}})
        lat = data["latencies"]
        self.assertEqual((lat["prediction_latency"], lat["update_write_latency"],
                          lat["update_landing"]), (10, 11, 6))
        small = rtl_config.config("small", data)
        self.assertEqual((small["sets"], small["ways"], small["variant"]), (64, 8, "faithful"))
        p = rtl_config.hrpp_top_params(small)
        self.assertEqual((p["Variant"], p["Combine"], p["NumSets"], p["InjectFault"]),
                         ("hrpp_pkg::HashFaithful", "hrpp_pkg::CombineConcat", 64, "1'b0"))
        self.assertEqual(rtl_config.hrpp_top_params(small, enums="int")["Variant"], "1'b0")
        self.assertEqual(rtl_config.predict_args(small, ("hash",)),
                         ["--hash", "faithful", "--precision", "6", "--exp-bits", "3",
                          "--combine", "concat"])
        # A key store in block RAM: one cycle more of decision and update latency.
        bram = dict(small, key_store_bram=True)
        self.assertEqual(rtl_config.hrpp_top_params(bram)["KeyStoreBram"], "1'b1")
        lb = rtl_config.latencies(bram, data)
        self.assertEqual((lb["prediction_latency"], lb["decision_latency"],
                          lb["update_write_latency"], lb["update_landing"]), (10, 3, 12, 7))
        self.assertEqual(rtl_config.latencies(small, data)["decision_latency"], 2)
        # Its read register (J): one cycle more again.
        reg = dict(bram, key_store_reg=True)
        self.assertEqual(rtl_config.hrpp_top_params(reg)["KeyStoreReg"], "1'b1")
        lr = rtl_config.latencies(reg, data)
        self.assertEqual((lr["prediction_latency"], lr["decision_latency"],
                          lr["update_write_latency"], lr["update_landing"]),
                         (10, 4, lb["update_write_latency"] + 1, lb["update_landing"] + 1))
        # A table of more sets than a RAM bank holds (RAM banks, L3b): one cycle more of lookup
        # and prediction latency, none of the update's.
        banked = dict(small, sets=4096)
        lk = rtl_config.latencies(banked, data)
        self.assertEqual((lk["lookup_stages"], lk["prediction_latency"], lk["decision_latency"],
                          lk["update_landing"]), (5, 11, 2, 6))
        self.assertEqual(rtl_config.latencies(dict(small, sets=2048), data)["lookup_stages"], 4)

    def test_errors(self):
        bad = [({"small": self.BASE}, "no configuration named default"),
               ({"default": {**self.BASE, "sets": 100}}, "sets must be a power of two"),
               ({"default": {**self.BASE, "colour": 1}}, "unknown ['colour']"),
               ({"default": {**self.BASE, "variant": "x"}}, "variant must be one of"),
               ({"default": {**self.BASE, "key_store_bram": 1}},
                "key_store_bram must be true or false"),
               ({"a": {"base": "default"}, "default": self.BASE}, "base default is not defined"),
               ({"default": {**self.BASE, "confidence_bits": 2}},
                "confidence_bits must be 0 or 1, got 2"),
               ({"default": {**self.BASE, "confidence_bits": True}},
                "confidence_bits must be 0 or 1"),
               ({"default": {**self.BASE, "confidence_bits": 1, "lanes": 2}},
                "confidence_bits is not available with lanes > 1"),
               ({"default": {**self.BASE, "key_store_bram": False, "key_store_reg": True}},
                "key_store_reg needs key_store_bram")]
        for configs, message in bad:
            with self.assertRaises(rtl_config.ConfigError) as e:
                self.load(configs)
            self.assertIn(message, str(e.exception))
        with self.assertRaises(rtl_config.ConfigError):
            self.load({"default": self.BASE}, {**self.LAT, "hash_stages": 0})
        for depth in (0, 3000, True, "2048", None):
            with self.assertRaises(rtl_config.ConfigError) as e:
                self.load({"default": self.BASE}, bank_depth=depth)
            self.assertIn("table_bank_depth must be a power of two", str(e.exception))
        with self.assertRaises(rtl_config.ConfigError) as e:
            self.load({"default": {**self.BASE, "sets": 4096, "lanes": 2}})
        self.assertIn("more than 2048 sets (the table_bank_depth) is not available with lanes",
                      str(e.exception))
        with self.assertRaises(rtl_config.ConfigError) as e:
            rtl_config.config("nope", self.load({"default": self.BASE}))
        self.assertIn("unknown configuration 'nope'", str(e.exception))

    def test_dir_code(self):
        """dir_code: "grid" when absent (every existing configuration); "oct" reaches DirCode,
        the `hrpp predict` options and the description; only with the improved hash, 1..8 bits."""
        data = self.load({"default": self.BASE,
                          "oct": {"base": "default", "dir_code": "oct", "origin_bits": 3}})
        default, octc = (rtl_config.config(n, data) for n in ("default", "oct"))
        self.assertEqual((default["dir_code"], octc["dir_code"]), ("grid", "oct"))
        self.assertEqual(rtl_config.hrpp_top_params(default)["DirCode"], "hrpp_pkg::DirGrid")
        self.assertEqual(rtl_config.hrpp_top_params(octc, enums="int")["DirCode"], "1'b1")
        self.assertNotIn("--dir-code", rtl_config.predict_args(default, ("hash",)))
        self.assertEqual(rtl_config.predict_args(octc, ("hash",)),
                         ["--hash", "improved", "--origin-bits", "3", "--dir-bits", "3",
                          "--dir-code", "oct", "--combine", "concat"])
        self.assertIn("o3/d3 oct concat", rtl_config.describe(octc))
        for bad, message in (({"dir_code": "cube"}, "dir_code must be one of"),
                             ({"dir_code": "oct", "variant": "faithful"}, "needs the improved"),
                             ({"dir_code": "oct", "dir_bits": 9}, "dir_bits 1..8")):
            with self.assertRaises(rtl_config.ConfigError) as e:
                self.load({"default": {**self.BASE, **bad}})
            self.assertIn(message, str(e.exception))

    def test_confidence_bits(self):
        data = self.load({"default": self.BASE, "conf": {"base": "default", "confidence_bits": 1}})
        default, conf = rtl_config.config("default", data), rtl_config.config("conf", data)
        self.assertEqual(default["confidence_bits"], 0)  # absent: 0
        self.assertEqual(rtl_config.hrpp_top_params(default)["ConfBits"], 0)
        self.assertEqual(rtl_config.hrpp_top_params(conf)["ConfBits"], 1)
        # The hrpp predict options: only with the bit, so every other configuration's are as before.
        self.assertNotIn("--confidence-bits", rtl_config.predict_args(default))
        self.assertEqual(rtl_config.predict_args(conf, ("table",))[-4:],
                         ["--confidence-bits", "1", "--confidence-threshold", "1"])

    def test_predict_kinds(self):
        """predict_kinds: "all" when absent; "any-hit" reaches the predict options (with the
        "kinds" part) and the description, not the RTL's parameters."""
        data = self.load({"default": self.BASE,
                          "sec": {"base": "default", "predict_kinds": "any-hit"}})
        default, sec = (rtl_config.config(n, data) for n in ("default", "sec"))
        self.assertEqual((default["predict_kinds"], sec["predict_kinds"]), ("all", "any-hit"))
        self.assertEqual(rtl_config.hrpp_top_params(default), rtl_config.hrpp_top_params(sec))
        self.assertNotIn("--predict-kinds", rtl_config.predict_args(default, ("kinds",)))
        self.assertEqual(rtl_config.predict_args(sec, ("kinds",)), ["--predict-kinds", "any-hit"])
        self.assertNotIn("--predict-kinds", rtl_config.predict_args(sec))
        self.assertIn("any-hit rays only", rtl_config.describe(sec))
        with self.assertRaises(rtl_config.ConfigError) as e:
            self.load({"default": {**self.BASE, "predict_kinds": "shadow"}})
        self.assertIn("predict_kinds must be", str(e.exception))

    def test_the_project_file_loads(self):
        data = rtl_config.load()
        self.assertIn("default", data["configurations"])
        # large (4,096 sets) is the configuration whose table is built of RAM banks.
        self.assertEqual(rtl_config.latencies(data["configurations"]["large"], data)
                         ["lookup_stages"], 5)
        self.assertEqual(rtl_config.latencies(data["configurations"]["default"], data)
                         ["lookup_stages"], 4)


class Tools(unittest.TestCase):
    def test_run_json_reads_the_report_or_raises_with_code_and_stderr(self):
        with tempfile.TemporaryDirectory(prefix="pyhrpp-") as d:
            out = pathlib.Path(d) / "r.json"
            write = f"import json; json.dump({{'x': 1}}, open({str(out)!r}, 'w'))"
            self.assertEqual(run_json([sys.executable, "-c", write], out), {"x": 1})
            fail = "import sys; sys.stderr.write('bad input'); sys.exit(2)"
            with self.assertRaises(ToolFailed) as e:
                run_json([sys.executable, "-c", fail], pathlib.Path(d) / "none.json")
            self.assertEqual(e.exception.returncode, 2)
            self.assertTrue(str(e.exception).endswith(" exited 2:\nbad input"), str(e.exception))


class SimStudy(unittest.TestCase):
    """model/tools/sim_study.py, the runs of make sim-results, design-study and port-rate as
    tasks of the study driver: --resume runs a run again when its command or the contents of its
    --preset file changed; a configuration that cannot run, and (port_rate) a run without rays of
    its kinds, are finished runs; the "Made by" command leaves out where the runs went."""

    # A stand-in for hrpp: counts its runs in argv[1]; exits as --rc says (with --say on
    # stderr), else writes its report where --json says.
    TOOL = ("import json, sys, pathlib; c = pathlib.Path(sys.argv[1]); "
            "c.write_text(str(int(c.read_text()) + 1) if c.exists() else '1'); "
            "a = sys.argv; rc = int(a[a.index('--rc') + 1]) if '--rc' in a else 0; "
            "sys.stderr.write(a[a.index('--say') + 1] + '\\n') if rc else "
            "json.dump({'speedup': 1.0}, open(a[a.index('--json') + 1], 'w')); sys.exit(rc)")

    def setUp(self):
        sys.path.insert(0, str(ROOT / "model" / "tools"))
        import sim_study
        self.sim_study = sim_study
        self.dir = tempfile.TemporaryDirectory(prefix="pyhrpp-")
        self.d = pathlib.Path(self.dir.name)
        self.count = self.d / "count"

    def tearDown(self):
        self.dir.cleanup()

    def run_study(self, *extra, resume=True, no_rays=False):
        """One run of the stand-in in a study with --no-dask: ({key: report}, runs so far)."""
        import argparse
        from pyhrpp import study
        cmd = [sys.executable, "-c", self.TOOL, self.count, "--preset", self.d / "p.json",
               "--json", "{json}", *extra]
        args = argparse.Namespace(workers=1, scheduler=None, no_dask=True, resume=resume)
        with study.Study("t", self.d / "journal.jsonl", {}, args, quiet=True) as st:
            rep = self.sim_study.reports(st, [self.sim_study.task(("k", 1), cmd,
                                                                  self.d / "r.json", no_rays)])
            st.complete()
        return rep[("k", "1")], int(self.count.read_text())

    def test_resume_reruns_a_run_whose_command_or_preset_changed(self):
        preset = self.d / "p.json"
        preset.write_text('{"a": 1}')
        self.assertEqual(self.run_study(resume=False), ({"speedup": 1.0}, 1))
        self.assertEqual(json.loads((self.d / "r.json").read_text()), {"speedup": 1.0})
        self.assertEqual(self.run_study(), ({"speedup": 1.0}, 1))  # the same: kept
        preset.write_text('{"a": 2}')
        self.assertEqual(self.run_study()[1], 2)  # the preset file changed: runs again
        self.assertEqual(self.run_study("--seed", "2")[1], 3)  # the command changed
        self.assertEqual(self.run_study("--seed", "2")[1], 3)

    def test_finished_runs_without_a_report(self):
        (self.d / "p.json").write_text("{}")
        bvh = "hrpp simulate: configuration primary: 20-bit node ids name at most 1048576"
        self.assertEqual(self.run_study("--rc", "2", "--say", bvh, resume=False)[0],
                         {"unsupported": bvh})
        no_rays = "hrpp simulate: no rays of the kinds 'shadow' in the workload"
        self.assertIsNone(self.run_study("--rc", "2", "--say", no_rays, no_rays=True)[0])
        err = io.StringIO()
        with self.assertRaises(SystemExit) as e, contextlib.redirect_stderr(err):
            self.run_study("--rc", "2", "--say", no_rays, resume=False)  # not finished here
        self.assertEqual(e.exception.code, 2)
        with self.assertRaises(SystemExit) as e, contextlib.redirect_stderr(err):
            self.run_study("--rc", "2", "--say", "bad input", resume=False,
                           no_rays=True)  # another error
        self.assertEqual(e.exception.code, 2)
        self.assertIn(" exited 2:\nbad input\nt: stopped; ", err.getvalue())

    def test_made_by_leaves_out_where_the_runs_went(self):
        self.assertEqual(self.sim_study.made_by(
            ["t.py", "--jobs", "2", "--res", "8x8", "--no-dask", "--workers=3", "--resume",
             "--scheduler", "tcp://h:1", "--resume-any-build", "--shared", ""]),
            "t.py --res 8x8 --shared ")


class DesignStudySpec(unittest.TestCase):
    """model/tools/design_study.py: a spec's skip_kinds leaves those ray kinds out on that GPU
    only, and names a kind that does not exist."""

    def test_skip_kinds(self):
        sys.path.insert(0, str(ROOT / "model" / "tools"))
        import argparse
        import design_study
        with tempfile.TemporaryDirectory(prefix="pyhrpp-") as d:
            d = pathlib.Path(d)
            spec = {"baseline": "a", "winner": "a", "skip_kinds": {"desktop": ["primary"]},
                    "designs": [{"name": "a", "about": "", "options": {"preset": "micro21"}}]}
            (d / "s.json").write_text(json.dumps(spec))
            spec, designs = design_study.load_designs(d / "s.json")
            args = argparse.Namespace(hrpp="hrpp", gpu="mobile,desktop", res="8x8", kinds=None)
            tasks = design_study.tasks_for(args, spec, [("shared", pathlib.Path("x.glb"))],
                                           designs, d)
            kinds = {(t.key[0], t.key[3]) for t in tasks}
            self.assertIn(("mobile", "primary"), kinds)
            self.assertNotIn(("desktop", "primary"), kinds)
            self.assertIn(("desktop", "ao"), kinds)
            self.assertEqual(len(tasks), 4 + 3)
            args.kinds = ["primary", "ao"]  # --kinds: those, less skip_kinds
            tasks = design_study.tasks_for(args, spec, [("shared", pathlib.Path("x.glb"))],
                                           designs, d)
            self.assertEqual(sorted((t.key[0], t.key[3]) for t in tasks),
                             [("desktop", "ao"), ("mobile", "ao"), ("mobile", "primary")])
            spec["skip_kinds"] = {"desktop": ["primry"]}
            (d / "s.json").write_text(json.dumps(spec))
            with self.assertRaises(SystemExit) as e:
                design_study.load_designs(d / "s.json")
            self.assertIn("primry", str(e.exception))


if __name__ == "__main__":
    unittest.main(verbosity=2)
