#!/usr/bin/python3
"""ParaView's own reader (VTK's vtkXMLUnstructuredGridReader) and meshio on
what `conserve run` writes: a deformable body above a rigid bare surface
(2D: a disc above a `segment`, 3D: a box above a `square`), so that the
rigid body's facets must be there as cells (issue 11), plus the contact
state debug files.

Usage: /usr/bin/python3 tests/cli/test_real_readers.py CONSERVE_BINARY
(only /usr/bin/python3 has Debian's python3-vtk9 and python3-meshio).
"""
import math
import pathlib
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET

import meshio
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

CONSERVE = None  # set from the command line
VTK_VERTEX, VTK_LINE, VTK_TRIANGLE, VTK_TETRA = 1, 3, 5, 10
VTK_QUADRATIC_TETRA = 24

SCENARIOS = pathlib.Path(__file__).resolve().parents[1] / "data" / "scenarios"
# test_rigid.cpp's scenarios; the disc's also gets a contact pair (so that
# contact-state files are written) and VTU output every 2 steps
DISC_ON_SEGMENT = (SCENARIOS / "rigid_disc_and_sliding_segment.toml").read_text() + """[output]
vtu_every = 2
contact_state = true
[[contact]]
slave = "disc"
master = "ground"
kind = "frictionless"
"""
# A stiff block sliding at 1 m/s on a rigid floor under gravity, Coulomb
# friction μ: it stops at 0.34 s.
BLOCK_ON_FLOOR = """dimension = 2
[time]
step = 1e-3
end = 0.4
[loads]
gravity = [0.0, -9.81]
[output]
vtu_every = 25
[[body]]
name = "block"
velocity = [1.0, 0.0]
[body.material]
young = 1.0e9
poisson = 0.3
density = 1000.0
[body.mesh]
generator = "rectangle"
lx = 0.1
ly = 0.05
size = 0.025
[[body]]
name = "floor"
rigid = true
translate = [0.5, -0.05]
[body.mesh]
generator = "rectangle"
lx = 2.0
ly = 0.05
size = 0.25
[[contact]]
slave = "block:ymin"
master = "floor:ymax"
kind = "coulomb"
friction = {mu}
"""
BOX_ON_SQUARE = (SCENARIOS / "rigid_box_and_rising_square.toml").read_text()


def run(folder, text):
    """Runs the scenario `text` in `folder`; returns the output folder."""
    (folder / "s.toml").write_text(text)
    done = subprocess.run([CONSERVE, "run", "s.toml", "-q", "-o", "out"], cwd=folder, capture_output=True,
                          text=True, check=False)
    if done.returncode != 0:
        raise AssertionError(f"conserve run failed ({done.returncode}): {done.stderr}")
    return folder / "out"


def pvd_files(out):
    """(time, VTU file) of every data set solution.pvd lists, in order."""
    root = ET.parse(out / "solution.pvd").getroot()
    return [(float(d.get("timestep")), out / d.get("file")) for d in root.iter("DataSet")]


def read_vtk(path):
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    if reader.GetErrorCode() != 0 or grid is None or grid.GetNumberOfPoints() == 0:
        raise AssertionError(f"VTK could not read {path}")
    return grid


def cell_types(grid):
    return [grid.GetCellType(i) for i in range(grid.GetNumberOfCells())]


def cell_bounds(grid, type_):
    """(min, max) over the points of the cells of one VTK type: what a
    Surface representation shows (unlike the bounds of all points)."""
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for i in range(grid.GetNumberOfCells()):
        if grid.GetCellType(i) != type_:
            continue
        b = grid.GetCell(i).GetBounds()
        for k in range(3):
            lo[k], hi[k] = min(lo[k], b[2 * k]), max(hi[k], b[2 * k + 1])
    return lo, hi


class RealReaders(unittest.TestCase):
    def check_surface(self, grid, volume_type, surface_type, surfaces, body, lo, hi):
        types = cell_types(grid)
        self.assertEqual(types.count(surface_type), surfaces)
        self.assertGreater(types.count(volume_type), 0)
        self.assertEqual(len(types), types.count(surface_type) + types.count(volume_type))
        cells = grid.GetCellData()
        body_field = cells.GetArray("body")
        stress = cells.GetArray("stress")
        mises = cells.GetArray("von_mises")
        energy = cells.GetArray("strain_energy_density")
        self.assertEqual(stress.GetNumberOfComponents(), 6)
        self.assertEqual([stress.GetComponentName(k) for k in range(6)], ["xx", "yy", "zz", "xy", "yz", "xz"])
        for i, t in enumerate(types):
            if t == surface_type:
                self.assertEqual(body_field.GetValue(i), body)
                self.assertTrue(all(math.isnan(stress.GetComponent(i, k)) for k in range(6)))
                self.assertTrue(math.isnan(mises.GetValue(i)))
                self.assertTrue(math.isnan(energy.GetValue(i)))
            else:
                self.assertNotEqual(body_field.GetValue(i), body)
                self.assertTrue(math.isfinite(energy.GetValue(i)))
                self.assertGreaterEqual(mises.GetValue(i), 0.0)
        b_lo, b_hi = cell_bounds(grid, surface_type)
        for k in range(3):
            self.assertAlmostEqual(b_lo[k], lo[k], delta=1e-9)
            self.assertAlmostEqual(b_hi[k], hi[k], delta=1e-9)
        # the surface lies within what the whole grid reports
        g = grid.GetBounds()
        self.assertTrue(g[0] <= b_lo[0] and b_hi[0] <= g[1] and g[2] <= b_lo[1] and b_hi[1] <= g[3])

    def test_segment_is_four_lines_2d(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = run(pathlib.Path(tmp), DISC_ON_SEGMENT)
            files = pvd_files(out)
            self.assertEqual(len(files), 4)  # steps 0, 2, 4 and the last, 5
            for t, f in files:
                with self.subTest(file=f.name):
                    grid = read_vtk(f)
                    # the segment |x| <= 1 at y = 0, moved by 0.25 t along x
                    self.check_surface(grid, VTK_TRIANGLE, VTK_LINE, 4, 1, [-1 + 0.25 * t, 0, 0],
                                       [1 + 0.25 * t, 0, 0])
                    mesh = meshio.read(f)
                    self.assertEqual(len(mesh.cells_dict["line"]), 4)
                    self.assertEqual(len(mesh.cells_dict["triangle"]), grid.GetNumberOfCells() - 4)
            # contact state files: one vertex per slave node of the disc
            states = sorted(out.glob("vtu/contact_*_pair0.vtu"))
            self.assertEqual(len(states), 4)
            for f in states:
                with self.subTest(file=f.name):
                    grid = read_vtk(f)
                    self.assertGreater(grid.GetNumberOfPoints(), 4)
                    self.assertEqual(set(cell_types(grid)), {VTK_VERTEX})
                    self.assertEqual(grid.GetNumberOfCells(), grid.GetNumberOfPoints())
                    for name in ("gap", "normal", "master_facet", "xi", "inside", "slave_node"):
                        self.assertIsNotNone(grid.GetPointData().GetArray(name), name)
                    mesh = meshio.read(f)
                    self.assertEqual(len(mesh.cells_dict["vertex"]), grid.GetNumberOfPoints())

    def test_square_is_eight_triangles_3d(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = run(pathlib.Path(tmp), BOX_ON_SQUARE)
            files = pvd_files(out)
            self.assertEqual(len(files), 5)  # steps 0, 5, 10, 15, 20
            for t, f in files:
                with self.subTest(file=f.name):
                    grid = read_vtk(f)
                    # 2 x 2 squares of two triangles each, |x|, |y| <= 1, z = 0.5 t
                    self.check_surface(grid, VTK_TETRA, VTK_TRIANGLE, 8, 1, [-1, -1, 0.5 * t], [1, 1, 0.5 * t])
                    mesh = meshio.read(f)
                    self.assertEqual(len(mesh.cells_dict["triangle"]), 8)
                    self.assertEqual(len(mesh.cells_dict["tetra"]), grid.GetNumberOfCells() - 8)

    def test_quadratic_tetrahedra_in_vtk_order_3d(self):
        """The box of order 2: VTK reads 10-node tetrahedra (type 24) beside
        the square's triangles, each with VTK's node order (slots 4-9 the
        middles of edges 01, 12, 20, 03, 13, 23: the box's cells are
        straight-sided), and meshio reads them as tetra10."""
        with tempfile.TemporaryDirectory() as tmp:
            text = BOX_ON_SQUARE.replace('size = 0.2\n', 'size = 0.2\norder = 2\n', 1)
            out = run(pathlib.Path(tmp), text)
            _, f = pvd_files(out)[-1]
            grid = read_vtk(f)
            types = cell_types(grid)
            self.assertEqual(set(types), {VTK_QUADRATIC_TETRA, VTK_TRIANGLE})
            self.assertEqual(types.count(VTK_TRIANGLE), 8)
            edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
            for c in range(grid.GetNumberOfCells()):
                if types[c] != VTK_QUADRATIC_TETRA:
                    continue
                ids = grid.GetCell(c).GetPointIds()
                p = [grid.GetPoint(ids.GetId(k)) for k in range(10)]
                for slot, (a, b) in enumerate(edges, start=4):
                    for k in range(3):
                        self.assertAlmostEqual(p[slot][k], 0.5 * (p[a][k] + p[b][k]), delta=1e-6)
            mesh = meshio.read(f)
            self.assertEqual(len(mesh.cells_dict["tetra10"]), types.count(VTK_QUADRATIC_TETRA))

    def test_compressed_and_raw_read_back_identically(self):
        """Every array of a frame, compressed or raw, single or double, read
        by VTK and by meshio: the same values; the contact fields there."""
        import numpy as np
        from vtkmodules.util.numpy_support import vtk_to_numpy
        with tempfile.TemporaryDirectory() as tmp:
            arrays = {}
            for compress in ("true", "false"):
                for precision in ("single", "double"):
                    folder = pathlib.Path(tmp) / f"{compress}_{precision}"
                    folder.mkdir()
                    out = run(folder, DISC_ON_SEGMENT.replace("[output]\n", f"[output]\ncompress = {compress}\n"
                                                              f"precision = \"{precision}\"\n"))
                    last = pvd_files(out)[-1][1]
                    grid = read_vtk(last)
                    mesh = meshio.read(last)
                    found = {}
                    data = grid.GetPointData()
                    for k in range(data.GetNumberOfArrays()):
                        name = data.GetArrayName(k)
                        found[name] = vtk_to_numpy(data.GetArray(k))
                        np.testing.assert_array_equal(found[name].reshape(mesh.point_data[name].shape),
                                                      mesh.point_data[name], err_msg=name)
                    data = grid.GetCellData()
                    for k in range(data.GetNumberOfArrays()):
                        name = data.GetArrayName(k)
                        found[name] = vtk_to_numpy(data.GetArray(k))
                        merged = np.concatenate([np.asarray(b) for b in mesh.cell_data[name]])
                        np.testing.assert_array_equal(found[name].reshape(merged.shape), merged, err_msg=name)
                    found["points"] = vtk_to_numpy(grid.GetPoints().GetData())
                    self.assertEqual(found["points"].dtype, np.float64)
                    self.assertEqual(found["displacement"].dtype, np.float32 if precision == "single" else np.float64)
                    for name in ("contact_normal_force", "contact_pressure", "contact_gap", "contact_status"):
                        self.assertIn(name, found)
                    arrays[(compress, precision)] = found
            for precision in ("single", "double"):
                a, b = arrays[("true", precision)], arrays[("false", precision)]
                self.assertEqual(sorted(a), sorted(b))
                for name in a:
                    np.testing.assert_array_equal(a[name], b[name], err_msg=name)
            # single is double rounded to the nearest Float32
            a, b = arrays[("true", "single")], arrays[("true", "double")]
            for name in a:
                if name != "points":
                    np.testing.assert_array_equal(a[name], b[name].astype(np.float32), err_msg=name)
            status = arrays[("true", "double")]["contact_status"]
            self.assertTrue(np.any(status == 0.0) or np.any(status == 1.0))

    def test_coulomb_traction_on_the_cone_while_slipping(self):
        """A block sliding on a rigid floor with Coulomb friction μ = 0.3: a
        slipping slave's tangential traction is μ times its pressure (its
        friction is on the cone; the output is single precision), against
        the sliding; once the block has stopped its slaves stick, inside
        the cone."""
        import numpy as np
        mu = 0.3
        text = BLOCK_ON_FLOOR.format(mu=mu)
        with tempfile.TemporaryDirectory() as tmp:
            out = run(pathlib.Path(tmp), text)
            slipping = sticking = 0
            for time, path in pvd_files(out):
                mesh = meshio.read(path)
                status = mesh.point_data["contact_status"]
                pressure = mesh.point_data["contact_pressure"]
                traction = mesh.point_data["contact_tangential_traction"]
                velocity = mesh.point_data["velocity"]
                for k in np.flatnonzero(status == 1.0):
                    # (below ε = 2.5e-7 m a step, 2.5e-4 m/s, the friction is regularized)
                    if not (pressure[k] > 0.0 and abs(velocity[k][0]) > 1e-2):
                        continue
                    slipping += 1
                    self.assertAlmostEqual(np.linalg.norm(traction[k]) / (mu * pressure[k]), 1.0, delta=1e-5)
                    self.assertLess(traction[k][0] * velocity[k][0], 0.0)  # against the sliding
                for k in np.flatnonzero(status == 2.0):
                    sticking += 1
                    self.assertLessEqual(np.linalg.norm(traction[k]), mu * abs(pressure[k]) * (1 + 1e-6))
            self.assertGreater(slipping, 10)
            self.assertGreater(sticking, 0)


if __name__ == "__main__":
    CONSERVE = str(pathlib.Path(sys.argv.pop(1)).resolve())
    unittest.main(verbosity=2)
