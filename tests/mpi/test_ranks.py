#!/usr/bin/python3
"""`conserve run` on N MPI ranks (issue 56) against the same run on one
process: conservation, contact whose slaves and master facets lie on
different ranks (every constraint method), SIGTERM/SIGUSR1 and restart,
bad input, determinism, and the .pvtu output in VTK's reader and meshio.

Usage: /usr/bin/python3 tests/mpi/test_ranks.py CONSERVE MPIEXEC N
(only /usr/bin/python3 has Debian's python3-vtk9 and python3-meshio).
"""
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))
import compare_histories  # noqa: E402

CONSERVE = MPIEXEC = None
RANKS = 1
ROOT = pathlib.Path(__file__).resolve().parents[2]
BARS = ROOT / "examples" / "validation" / "bars_2d.toml"
BALL = ROOT / "examples" / "ball" / "ball_on_plane.toml"
FLIGHT = ROOT / "examples" / "ball" / "ball_flight.toml"
ENV = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
# Under the sanitizers (scripts/sanitize.sh): OpenMPI's plug-ins, started by
# a launcher, leave allocations at exit that LeakSanitizer reports from
# modules already unloaded; conserve's own leaks are checked by the
# single-process tests, so here only ASan's and UBSan's errors count.
if "ASAN_OPTIONS" in ENV:
    ENV["ASAN_OPTIONS"] += ":detect_leaks=0"
AGREE = 1e-9  # E, L, J and gaps against the one-process run, relative (scripts/compare_histories.py)


def command(ranks, *args):
    """ranks = 0: the process alone, without a launcher (the reference)."""
    launcher = [MPIEXEC, "-q", "-n", str(ranks)] if ranks > 0 else []
    return launcher + [CONSERVE, *map(str, args)]


def run(ranks, scenario, out, *extra, check=True):
    p = subprocess.run(command(ranks, "run", scenario, "-o", out, "-q", *extra), env=ENV, capture_output=True,
                       text=True, timeout=600)
    if check and p.returncode != 0:
        raise AssertionError(f"exit {p.returncode}: {p.stderr}")
    return p


history = compare_histories.history


def summary(out):
    return json.loads((pathlib.Path(out) / "summary.json").read_text())


class Ranks(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = pathlib.Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def assert_same_trajectory(self, one, many):
        """E, L, J and the gaps within AGREE of their scales
        (scripts/compare_histories.py); the active contacts step by step
        the same (a dropped or doubled constraint would change them)."""
        d = compare_histories.compare(one, many)
        self.assertEqual(d["rows"][0], d["rows"][1])
        for quantity in ("E", "L", "J", "gap"):
            self.assertLessEqual(d[quantity], AGREE, quantity)
        self.assertTrue(d["active_contacts_equal"])
        if RANKS == 1:  # under the launcher, the same program as without
            self.assertEqual((pathlib.Path(one) / "history.csv").read_bytes(),
                             (pathlib.Path(many) / "history.csv").read_bytes())

    def assert_conserved(self, out, bound=1e-10):
        s = summary(out)
        self.assertEqual(s["ranks"], RANKS)
        self.assertTrue(s["drift"], "no conserved quantity")
        for name, drift in s["drift"].items():
            self.assertLessEqual(drift, bound, name)

    def test_free_body_conserves_and_follows_one_process(self):
        args = ("--set", "body.ball.mesh.size=0.15", "--steps", 30)
        run(0, FLIGHT, self.dir / "one", *args)
        run(RANKS, FLIGHT, self.dir / "many", *args)
        self.assert_conserved(self.dir / "many")
        self.assert_same_trajectory(self.dir / "one", self.dir / "many")

    def test_contact_across_ranks_every_method(self):
        """On two ranks the bars' slaves (A:xmax) are all on rank 0 and
        their master facets (B:xmin) on rank 1: row_ranges shows the cut.
        Each rank holds its nodes' rows of the tangent alone, so every
        slave's elimination into its master's rows (and the penalty's and
        the multipliers' terms there) crosses the ranks. With exact solves
        (MUMPS on N ranks, UMFPACK alone) Newton takes the same iterations
        step by step: a coupling dropped or counted twice would leave the
        tangent inexact and Newton slower."""
        text = BARS.read_text()
        variants = {
            "paper": (text, ()),
            "persistent": (text, ("--set", "active_set.scheme=persistent")),
            "lagrange": (text.replace('kind = "frictionless"', 'kind = "frictionless"\nmethod = "lagrange"'), ()),
            "penalty": (text.replace('kind = "frictionless"', 'kind = "frictionless"\nmethod = "penalty"'), ()),
        }
        for name, (scenario_text, extra) in variants.items():
            with self.subTest(name):
                scenario = self.dir / f"{name}.toml"
                scenario.write_text(scenario_text)
                args = (*extra, "--steps", 150, "--set", "output.vtu_every=0")
                run(0, scenario, self.dir / f"{name}1", *args)
                run(RANKS, scenario, self.dir / f"{name}N", *args)
                self.assert_conserved(self.dir / f"{name}N")
                self.assert_same_trajectory(self.dir / f"{name}1", self.dir / f"{name}N")
                self.assertGreater(max(history(self.dir / f"{name}N")["active_contacts"]), 0)
                ranges = summary(self.dir / f"{name}N")["row_ranges"]
                if RANKS > 1:
                    self.assertEqual(len(ranges), RANKS + 1)
                    if RANKS == 2:  # the two bars' 504 dofs each (the multipliers' rows after them)
                        self.assertEqual(ranges[:2], [0, 504])
                else:
                    self.assertEqual(ranges, [])
                # 60 steps: contact from step 11 on, activations and sustained contact.
                exact = (*extra, "--steps", 60, "--set", "output.vtu_every=0", "--set", "solver.method=direct",
                         "--set", "solver.modified_newton=false")
                run(0, scenario, self.dir / f"{name}1d", *exact)
                run(RANKS, scenario, self.dir / f"{name}Nd", *exact)
                one, many = history(self.dir / f"{name}1d"), history(self.dir / f"{name}Nd")
                self.assertGreater(max(many["active_contacts"]), 0)
                self.assertEqual(one["newton_iterations"], many["newton_iterations"])

    def test_ball_stick_3d(self):
        args = ("--set", "body.ball.mesh.size=0.12", "--set", "body.ball.translate=[0.0,0.0,0.405]", "--steps", 40,
                "--set", "output.vtu_every=0")
        run(0, BALL, self.dir / "one", *args)
        run(RANKS, BALL, self.dir / "many", *args)
        self.assert_conserved(self.dir / "many")
        self.assert_same_trajectory(self.dir / "one", self.dir / "many")
        self.assertGreater(max(history(self.dir / "many")["active_contacts"]), 0)

    def test_same_ranks_same_bits(self):
        """Run after run the same bits: what a rank adds into another's rows
        is summed after the owner's own, in rank order."""
        args = ("--set", "body.ball.translate=[0.0,0.0,0.405]", "--steps", 45, "--set", "output.vtu_every=0")
        for out in ("a", "b", "c"):
            run(RANKS, BALL, self.dir / out, *args)
        first = (self.dir / "a" / "history.csv").read_bytes()
        for out in ("b", "c"):
            self.assertEqual(first, (self.dir / out / "history.csv").read_bytes(), out)

    def stop_and_restart(self, scenario, args, stop, to_launcher, after=20):
        """Signal `stop` to the ranks (and to the launcher too, which
        forwards SIGUSR1, if `to_launcher`) once `after` steps are written: the
        run ends after the step under way with a checkpoint and exit code 5;
        continuing from it on the same ranks gives the uninterrupted run's
        history byte for byte; on one process, the same trajectory if the
        ranks kept the meshes' numbering ([solver] partition = "ranges"),
        else a refusal in one line naming both rank counts."""
        run(RANKS, scenario, self.dir / "whole", *args)
        out = self.dir / "stopped"
        p = subprocess.Popen(command(RANKS, "run", scenario, "-o", out, "-q", *args), env=ENV,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
        steps = out / "steps.csv"
        deadline = time.time() + 300
        while time.time() < deadline and (not steps.exists() or len(steps.read_text().splitlines()) < after):
            time.sleep(0.05)
        if to_launcher:
            os.killpg(p.pid, stop)
        else:  # the ranks alone, as srun or a batch system's time limit sends it
            children = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True, text=True).stdout.split()
            self.assertEqual(len(children), RANKS)
            for child in children:
                os.kill(int(child), stop)
        _, err = p.communicate(timeout=300)
        self.assertEqual(p.returncode, 5, err)
        self.assertEqual(err.count(f"conserve: stopped by {signal.Signals(stop).name}"), 1, err)
        checkpoints = sorted((out / "checkpoints").glob("ckpt_*.bin"))
        self.assertEqual(len(checkpoints), 1)
        self.assertTrue(summary(out)["stopped"])
        alone = self.dir / "alone"
        shutil.copytree(out, alone)
        run(RANKS, scenario, out, *args, "--restart", checkpoints[0])
        self.assertEqual((self.dir / "whole" / "history.csv").read_bytes(), (out / "history.csv").read_bytes())
        ranges = "solver.partition=ranges" in args
        p = run(0, scenario, alone, *args, "--restart", alone / "checkpoints" / checkpoints[0].name, check=ranges)
        if ranges or RANKS == 1:
            self.assert_same_trajectory(self.dir / "whole", alone)
        else:
            self.assertEqual(p.returncode, 1, p.stderr)
            lines = [l for l in p.stderr.splitlines() if l.startswith("conserve:")]
            self.assertEqual(len(lines), 1, p.stderr)
            self.assertIn(f"written on {RANKS} ranks", lines[0])
            self.assertIn("this run has 1 rank", lines[0])

    def test_sigusr1_to_the_launcher_checkpoint_and_restart(self):
        # A vibrating ball (Newton at work every step) for 2,000 steps: the
        # signal must arrive long before the run's end (300 steps of free
        # flight alone took 0.05 s).
        self.stop_and_restart(FLIGHT, ("--set", "body.ball.mesh.size=0.12", "--set", "output.vtu_every=0", "--set",
                                       "output.checkpoint_every=0", "--set", "time.end=2.0", "--set",
                                       "body.ball.initial_deformation=[[1.01,0.0,0.0],[0.0,0.995,0.0],[0.0,0.0,0.995]]",
                                       "--set", "solver.partition=ranges"), signal.SIGUSR1, True)

    def test_sigterm_to_the_ranks_in_contact_checkpoint_and_restart(self):
        """Stopped while the ball is in contact with the plane (from about step 32)."""
        self.stop_and_restart(BALL, ("--set", "body.ball.mesh.size=0.12", "--set", "body.ball.translate=[0.0,0.0,0.405]",
                                     "--set", "output.vtu_every=0", "--set", "output.checkpoint_every=0", "--set",
                                     "time.end=0.12"), signal.SIGTERM, False, after=45)
        self.assertGreater(max(history(self.dir / "whole")["active_contacts"][30:50]), 0)

    def test_bad_input_one_line_exit_1(self):
        bad = self.dir / "bad.toml"
        bad.write_text("dimension = 2\n[time]\nstep = -1\n")
        p = run(RANKS, bad, self.dir / "out", check=False)
        self.assertEqual(p.returncode, 1)
        lines = [l for l in p.stderr.splitlines() if l.startswith("conserve:")]
        self.assertEqual(len(lines), 1, p.stderr)
        self.assertFalse((self.dir / "out").exists())

    def test_graph_parts_hold_fewer_ghost_nodes(self):
        """The ball split over the ranks: numbered by graph parts (the
        default), its largest rank's ghost nodes are fewer than with
        contiguous ranges of its band, at the same balance of nodes."""
        if RANKS < 2:
            self.skipTest("one rank has no ghost nodes")
        runs = {}
        for partition in ("graph", "ranges"):
            run(RANKS, BALL, self.dir / partition, "--steps", 1, "--set", "output.vtu_every=0", "--set",
                f"solver.partition={partition}")
            runs[partition] = summary(self.dir / partition)
        ghosts = {p: max(s["rank_ghost_nodes"]) for p, s in runs.items()}
        print(f"[ measured ] largest rank's ghost nodes on {RANKS} ranks: {ghosts}")
        self.assertLess(ghosts["graph"], ghosts["ranges"])
        for s in runs.values():
            self.assertEqual(len(s["rank_ghost_nodes"]), RANKS)

    def test_pvtu_in_vtk_and_meshio(self):
        if RANKS < 2:
            self.skipTest("one rank writes .vtu files")
        import meshio
        import numpy
        from vtkmodules.vtkFiltersCore import vtkCellCenters
        from vtkmodules.vtkIOXML import vtkXMLPUnstructuredGridReader, vtkXMLUnstructuredGridReader
        from vtkmodules.util.numpy_support import vtk_to_numpy
        args = ("--steps", 20)
        run(0, BARS, self.dir / "one", *args)
        run(RANKS, BARS, self.dir / "many", *args)
        pvd = (self.dir / "many" / "solution.pvd").read_text()
        self.assertIn("vtu/step_000020.pvtu", pvd)
        serial = vtkXMLUnstructuredGridReader()
        serial.SetFileName(str(self.dir / "one" / "vtu" / "step_000020.vtu"))
        serial.Update()
        parallel = vtkXMLPUnstructuredGridReader()
        parallel.SetFileName(str(self.dir / "many" / "vtu" / "step_000020.pvtu"))
        parallel.Update()
        a, b = serial.GetOutput(), parallel.GetOutput()
        self.assertEqual(a.GetNumberOfCells(), b.GetNumberOfCells())
        self.assertGreaterEqual(b.GetNumberOfPoints(), a.GetNumberOfPoints())  # pieces share their border points

        def centres(grid):
            c = vtkCellCenters()
            c.SetInputData(grid)
            c.Update()
            return vtk_to_numpy(c.GetOutput().GetPoints().GetData())

        # Each rank writes its own cells: the pieces' cells matched to the
        # one process's by their centres, each once.
        ca, cb = centres(a), centres(b)
        distance = ((ca[:, None, :] - cb[None, :, :]) ** 2).sum(axis=2)
        match = distance.argmin(axis=1)
        self.assertLessEqual(numpy.sqrt(distance[numpy.arange(len(ca)), match].max()), 1e-9)
        self.assertEqual(len(set(match.tolist())), len(ca))
        for name in ("stress", "body"):
            x = vtk_to_numpy(a.GetCellData().GetArray(name))
            y = vtk_to_numpy(b.GetCellData().GetArray(name))[match]
            self.assertEqual(x.shape, y.shape)
            self.assertLessEqual(abs(x - y).max(), 1e-6 * abs(x).max(), name)
        self.assertIsNotNone(b.GetPointData().GetArray("displacement"))
        mesh = meshio.read(self.dir / "many" / "vtu" / f"step_000020_{RANKS - 1}.vtu")
        self.assertIn("displacement", mesh.point_data)
        self.assertGreater(sum(len(c.data) for c in mesh.cells), 0)


if __name__ == "__main__":
    CONSERVE, MPIEXEC, RANKS = sys.argv[1], sys.argv[2], int(sys.argv[3])
    unittest.main(argv=[sys.argv[0], "-v", *sys.argv[4:]])
