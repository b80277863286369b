#!/usr/bin/python3
"""scripts/contact_episodes.py on output folders whose contact history is
known: synthetic VTU series written with VTK (exact figures), bad folders
(one line, exit 1), and a real `conserve run` output.

Usage: /usr/bin/python3 tests/cli/test_contact_episodes.py CONSERVE_BINARY
"""
import json
import math
import pathlib
import subprocess
import sys
import tempfile
import unittest

import numpy
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

CONSERVE = None  # set from the command line
ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "contact_episodes.py"
NAN = math.nan


def write_series(folder, forces_by_step, first_step=0):
    """vtu/step_NNNNNN.vtu with the field contact_normal_force, one per step."""
    (folder / "vtu").mkdir(parents=True)
    for k, forces in enumerate(forces_by_step):
        grid = vtkUnstructuredGrid()
        points = vtkPoints()
        for a in range(len(forces)):
            points.InsertNextPoint(float(a), 0.0, 0.0)
        grid.SetPoints(points)
        field = numpy_to_vtk(numpy.array(forces, dtype=float), deep=True)
        field.SetName("contact_normal_force")
        grid.GetPointData().AddArray(field)
        writer = vtkXMLUnstructuredGridWriter()
        writer.SetFileName(str(folder / "vtu" / f"step_{first_step + k:06d}.vtu"))
        writer.SetInputData(grid)
        writer.Write()


def episodes(folder, *extra):
    return subprocess.run(["/usr/bin/python3", str(SCRIPT), str(folder), *extra], capture_output=True, text=True,
                          check=False)


class Synthetic(unittest.TestCase):
    def test_bounces_returns_and_release_forces(self):
        # Three nodes. Bounce 1 (steps 1-4): node 0 lands, node 1 lands,
        # node 0 lifts (force 1 before, mean 2) and comes back, both lift
        # (forces 4 and 2, mean 3). Bounce 2 (step 6): node 2 lands and lifts
        # (force 5, alone).
        series = [
            [NAN, NAN, NAN],
            [2.0, NAN, NAN],
            [1.0, 3.0, NAN],
            [NAN, 3.0, NAN],
            [4.0, 2.0, NAN],
            [NAN, NAN, NAN],
            [NAN, NAN, 5.0],
            [NAN, NAN, NAN],
        ]
        with tempfile.TemporaryDirectory() as tmp:
            folder = pathlib.Path(tmp)
            write_series(folder, series)
            done = episodes(folder, "--json")
            self.assertEqual(done.returncode, 0, done.stderr)
            s = json.loads(done.stdout)
        self.assertEqual(s["steps"], 7)
        self.assertEqual(s["bounces"], [
            {"steps": 4, "nodes": 2, "activations": 3, "releases": 3},
            {"steps": 1, "nodes": 1, "activations": 1, "releases": 1},
        ])
        self.assertEqual((s["node_episodes"], s["activations"], s["returns"], s["releases"]), (3, 4, 1, 4))
        # releases measured: 1/2, 4/3, 2/3, 5/5
        self.assertAlmostEqual(s["release_force_max"], 4.0 / 3.0, places=12)
        self.assertAlmostEqual(s["release_force_median"], 1.0, places=12)
        self.assertEqual(s["loaded_releases"], 4)
        # node 0 was active in steps 1-2, then in step 4 alone (a landing);
        # node 1 in steps 2-4; node 2 in step 6 alone (a landing)
        self.assertEqual([(r["step"], r["node"], r["steps_active"]) for r in s["loaded"]],
                         [(3, 0, 2), (5, 0, 1), (5, 1, 3), (7, 2, 1)])
        self.assertEqual(s["loaded_landings"], 2)

    def test_text_report_names_the_figures(self):
        with tempfile.TemporaryDirectory() as tmp:
            folder = pathlib.Path(tmp)
            write_series(folder, [[NAN, NAN], [1.0, 1.0], [NAN, 1.0]])
            done = episodes(folder)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("1 bounces", done.stdout)
        self.assertIn("returns 0", done.stdout)
        self.assertIn("releases 1,", done.stdout)
        self.assertIn("of which landings (active one step) 1", done.stdout)
        self.assertNotIn("  step ", done.stdout)

    def test_list_prints_each_loaded_release(self):
        with tempfile.TemporaryDirectory() as tmp:
            folder = pathlib.Path(tmp)
            write_series(folder, [[NAN, NAN], [1.0, 1.0], [1.0, 3.0], [NAN, 3.0]])
            done = episodes(folder, "--list")
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("  step 3, node 0: active 2 steps, force before / mean 0.5", done.stdout)


class BadFolders(unittest.TestCase):
    def assert_one_line_error(self, done, needle):
        self.assertEqual(done.returncode, 1)
        self.assertEqual(done.stdout, "")
        lines = done.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, done.stderr)
        self.assertTrue(lines[0].startswith("contact_episodes.py: error: "), lines[0])
        self.assertIn(needle, lines[0])

    def test_no_vtu_folder(self):
        with tempfile.TemporaryDirectory() as tmp:
            self.assert_one_line_error(episodes(tmp), "no vtu/ folder")

    def test_steps_not_consecutive(self):
        with tempfile.TemporaryDirectory() as tmp:
            folder = pathlib.Path(tmp)
            write_series(folder, [[NAN], [1.0], [NAN]])
            (folder / "vtu" / "step_000001.vtu").unlink()
            self.assert_one_line_error(episodes(folder), "vtu_every=1")

    def test_no_contact_field(self):
        with tempfile.TemporaryDirectory() as tmp:
            folder = pathlib.Path(tmp)
            write_series(folder, [[NAN], [1.0]])
            # a field of another name instead
            for p in (folder / "vtu").iterdir():
                p.write_text(p.read_text().replace("contact_normal_force", "displacement"))
            self.assert_one_line_error(episodes(folder), "no contact_normal_force")


class RealRun(unittest.TestCase):
    def test_a_run_with_every_step_written(self):
        # A disc thrown at a rigid segment: it lands, bounces and leaves.
        text = """dimension = 2
[time]
step = 2e-3
end = 0.12
[[body]]
name = "disc"
translate = [0.0, 0.31]
velocity = [0.0, -1.0]
[body.material]
young = 1.0e7
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "disc"
radius = 0.3
size = 0.1
[[body]]
name = "ground"
rigid = true
[body.mesh]
generator = "segment"
lx = 2.0
size = 0.5
[[contact]]
slave = "disc"
master = "ground"
kind = "frictionless"
"""
        with tempfile.TemporaryDirectory() as tmp:
            folder = pathlib.Path(tmp)
            (folder / "s.toml").write_text(text)
            run = subprocess.run([CONSERVE, "run", "s.toml", "-q", "-o", "out", "--set", "output.vtu_every=1"],
                                 cwd=folder, capture_output=True, text=True, check=False)
            self.assertEqual(run.returncode, 0, run.stderr)
            summary = json.loads((folder / "out" / "summary.json").read_text())
            done = episodes(folder / "out", "--json")
            self.assertEqual(done.returncode, 0, done.stderr)
            s = json.loads(done.stdout)
        self.assertEqual(s["steps"], summary["steps"])
        self.assertGreater(s["activations"], 0)  # there was contact to measure
        # Activations and releases within a single step are invisible in the VTU series.
        self.assertLessEqual(s["activations"], summary["activations"])
        self.assertLessEqual(s["releases"], summary["releases"])


if __name__ == "__main__":
    CONSERVE = str(pathlib.Path(sys.argv.pop(1)).resolve())
    unittest.main()
