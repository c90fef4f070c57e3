#!/usr/bin/python3
"""scripts/validation_table.py writes its tables into a document between the validation-table
markers: the marked section is replaced by tables built from the runs' summary.json files, the
text around it is kept byte for byte, and a document without the markers is refused unchanged.

Runs on fixture summary.json files in a temporary directory (no polydem run needed):
  /usr/bin/python3 validation_table_test.py SOURCE_DIR
"""
import json
import pathlib
import subprocess
import sys
import tempfile
import unittest

SOURCE = pathlib.Path(sys.argv.pop(1) if len(sys.argv) > 1 else
                      pathlib.Path(__file__).resolve().parents[2])
SCRIPT = SOURCE / "scripts" / "validation_table.py"
sys.path.insert(0, str(SCRIPT.parent))
import validation_table as vt  # noqa: E402

BEFORE = "# Validation\n\nText above the tables, kept.\n\n"
AFTER = "\nText below the tables, kept too.\n| a table | of its own |\n"
OLD = "| scene | old |\n|---|---|\n| OLD-SCENE | PASS stale 1 |\n"


def check(name, value, expected, ok, unit="rad", kind="rotation"):
    return {"name": name, "kind": kind, "value": value, "expected": expected, "compare": "below",
            "tolerance": expected, "pass": ok, "unit": unit}


def summary(checks, steps=100):
    return {"steps": steps, "wall_seconds": 1.25, "state_hash": "0123456789abcdef",
            "checks": checks}


class WriteSection(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)
        self.runs = self.dir / "runs"
        # Two scenes, a penalty kernel under both models and a potential kernel under
        # sub-contacts only; one run did not finish (a log, no summary.json).
        self.write_run("sub-contacts", "S-REST", "gjk-epa", [check("rotation", 1.5e-16, 1e-6, True)])
        self.write_run("sub-contacts", "S-REST", "fdem", [check("rotation", 2.0e-4, 1e-6, False)])
        self.write_run("sub-contacts", "D-SLIDE", "gjk-epa",
                       [check("drift", 3.0e-7, 1e-5, True, unit="m", kind="drift")])
        log = self.runs / "sub-contacts" / "D-SLIDE" / "fdem.log"
        log.parent.mkdir(parents=True, exist_ok=True)
        log.write_text("starting\nerror: D-SLIDE.toml:12: unknown key 'frobnicate'\n")
        self.write_run("point", "S-REST", "gjk-epa", [check("rotation", 1.2e-3, 1e-6, False)])
        self.write_run("point", "D-SLIDE", "gjk-epa",
                       [check("drift", 4.0e-7, 1e-5, True, unit="m", kind="drift")])
        self.doc = self.dir / "validation.md"
        self.doc.write_text(BEFORE + vt.BEGIN + "\n" + OLD + vt.END + "\n" + AFTER)

    def tearDown(self):
        self.tmp.cleanup()

    def write_run(self, model, scene, kernel, checks):
        d = self.runs / model / scene / kernel
        d.mkdir(parents=True)
        (d / "summary.json").write_text(json.dumps(summary(checks)))

    def tables(self):
        return vt.tables(self.runs, ["gjk-epa", "fdem"], ["S-REST", "D-SLIDE"],
                         ["sub-contacts", "point"], ["fdem"])

    def test_section_replaced_rest_kept(self):
        text, _ = self.tables()
        vt.write_section(self.doc, text)
        new = self.doc.read_text()
        self.assertTrue(new.startswith(BEFORE + vt.BEGIN + "\n"), new)
        self.assertTrue(new.endswith(vt.END + "\n" + AFTER), new)
        section = new[len(BEFORE + vt.BEGIN + "\n"):-len(vt.END + "\n" + AFTER)]
        self.assertEqual(section, text)
        self.assertNotIn("OLD-SCENE", new)
        self.assertIn("| S-REST | PASS rotation 1.5e-16 rad | FAIL rotation 0.0002 rad |", section)
        self.assertIn("| D-SLIDE | PASS drift 3e-07 m | error: error: D-SLIDE.toml:12: unknown key "
                      "'frobnicate' |", section)
        # The point model's table has no column for the potential kernel.
        self.assertIn("contact_model = point:\n\n| scene | gjk-epa |\n", section)
        self.assertIn("| S-REST | FAIL rotation 0.0012 rad |", section)
        self.assertEqual(len(list(self.dir.iterdir())), 2, "no temporary file left")

    def test_rewrite_is_stable(self):
        text, _ = self.tables()
        vt.write_section(self.doc, text)
        once = self.doc.read_text()
        vt.write_section(self.doc, text)
        self.assertEqual(self.doc.read_text(), once)

    def test_document_without_markers_refused_unchanged(self):
        for body in (BEFORE + AFTER, BEFORE + vt.END + "\n" + vt.BEGIN + "\n" + AFTER,
                     BEFORE + vt.BEGIN + "\n" + vt.BEGIN + "\n" + vt.END + "\n" + AFTER):
            self.doc.write_text(body)
            with self.assertRaises(SystemExit) as raised:
                vt.write_section(self.doc, "| new |\n")
            self.assertIn(str(self.doc), str(raised.exception))
            self.assertEqual(self.doc.read_text(), body)

    def test_command_line_writes_doc_and_prints_checks(self):
        run = subprocess.run(
            [sys.executable, str(SCRIPT), str(self.runs), "--kernels", "gjk-epa", "fdem",
             "--scenes", "S-REST", "D-SLIDE", "--models", "sub-contacts", "point",
             "--potential", "fdem", "--doc", str(self.doc)],
            capture_output=True, text=True, check=True)
        text, checks = self.tables()
        self.assertEqual(run.stdout, text + checks)
        self.assertIn("- S-REST / fdem / sub-contacts: 100 steps, 1.2 s wall", run.stdout)
        self.assertEqual(self.doc.read_text(),
                         BEFORE + vt.BEGIN + "\n" + text + vt.END + "\n" + AFTER)

    def test_command_line_refuses_doc_without_markers(self):
        self.doc.write_text(BEFORE + AFTER)
        run = subprocess.run(
            [sys.executable, str(SCRIPT), str(self.runs), "--kernels", "gjk-epa",
             "--scenes", "S-REST", "--doc", str(self.doc)], capture_output=True, text=True)
        self.assertNotEqual(run.returncode, 0)
        self.assertIn("validation-table:begin", run.stderr)
        self.assertEqual(self.doc.read_text(), BEFORE + AFTER)


if __name__ == "__main__":
    unittest.main()
