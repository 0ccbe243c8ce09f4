#!/usr/bin/env python3
"""The shared Python helpers (pyhrpp/): atomic writing and the docs-block rewriting.

  pyhrpp_test.py        (ctest: pyhrpp.unit)
"""
import os
import pathlib
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from pyhrpp.docs import replace_block, update_blocks  # noqa: E402
from pyhrpp.files import commit_tmp, tmp_path, write_atomic, write_json_atomic  # noqa: E402


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


if __name__ == "__main__":
    unittest.main(verbosity=2)
