#!/usr/bin/python3
"""Renders snapshots of a conserve run's deformed configuration to PNGs,
headlessly with matplotlib (like the paper's Figures 3, 8 and 13).

Usage: /usr/bin/python3 scripts/render_snapshots.py OUT_DIR
           [--steps N N ...] [--count K] [--color body|speed|stress]
           [--view ELEV AZIM] [--frame auto|fixed|follow] [--out DIR]

OUT_DIR is a run's output folder (with solution.pvd and vtu/). Without
--steps, K (default 6) snapshots evenly spaced over the written VTU files
are drawn. Writes DIR/snapshot_NNNNNN.png per step and DIR/snapshots.png
(all of them side by side); DIR defaults to OUT_DIR/snapshots.

3D: the boundary triangles of the tetrahedra (faces used by one cell) and
the triangles of bare rigid surfaces, with back faces culled, coloured by
body, by |velocity| (speed, the default) or by the von Mises stress (stress,
the VTU field von_mises) of the cell under the face. 2D: the triangles (tripcolor) and bare
rigid segments. Rigid bare surfaces are clipped to the frame.
"""
import argparse
import pathlib
import re
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader  # noqa: E402

VTK_LINE, VTK_TRIANGLE, VTK_TETRA = 3, 5, 10


# --------------------------------------------------------------------------
# Reading


def read_vtu(path):
    """A VTU file through VTK's own reader (raw, base64 or compressed): its
    points, cells (connectivity, the end offset of each cell, VTK types)
    and fields."""
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    if reader.GetErrorCode() != 0 or grid is None or grid.GetPoints() is None:
        sys.exit(f"render_snapshots: {path}: not a VTK UnstructuredGrid VTK can read")
    cells = grid.GetCells()

    def fields(data):
        return {data.GetArrayName(k): vtk_to_numpy(data.GetArray(k)) for k in range(data.GetNumberOfArrays())}

    return {"points": vtk_to_numpy(grid.GetPoints().GetData()).astype(float),
            "connectivity": vtk_to_numpy(cells.GetConnectivityArray()),
            "offsets": vtk_to_numpy(cells.GetOffsetsArray())[1:],  # VTK's start with 0
            "types": vtk_to_numpy(grid.GetCellTypesArray()),
            "point_data": fields(grid.GetPointData()),
            "cell_data": fields(grid.GetCellData())}


def read_pvd(run_dir):
    pvd = run_dir / "solution.pvd"
    if pvd.exists():
        root = ET.parse(pvd).getroot()
        entries = [(float(d.get("timestep")), run_dir / d.get("file")) for d in root.iter("DataSet")]
    else:
        entries = [(float("nan"), p) for p in sorted((run_dir / "vtu").glob("step_*.vtu"))]
    out = []
    for t, p in entries:
        m = re.search(r"step_(\d+)\.vtu$", p.name)
        if m:
            out.append((int(m.group(1)), t, p))
    if not out:
        sys.exit(f"render_snapshots: no VTU files under {run_dir} (solution.pvd or vtu/step_*.vtu)")
    return out


# --------------------------------------------------------------------------
# Geometry


def cells_of_type(g, vtk_type):
    """(cell indices, node lists) of the cells of one VTK type."""
    conn, offsets, types = g["connectivity"], g["offsets"], g["types"]
    idx = np.nonzero(types == vtk_type)[0]
    if len(idx) == 0:
        return idx, np.zeros((0, 0), dtype=np.int64)
    starts = np.concatenate([[0], offsets[:-1]])
    n = {VTK_LINE: 2, VTK_TRIANGLE: 3, VTK_TETRA: 4}[vtk_type]
    nodes = conn[starts[idx][:, None] + np.arange(n)[None, :]]
    return idx, nodes


def tet_boundary(tets):
    """Faces used by one tet, oriented outwards; returns (faces, owner)."""
    local = np.array([[1, 2, 3, 0], [0, 3, 2, 1], [0, 1, 3, 2], [0, 2, 1, 3]])  # face + opposite node
    faces = np.concatenate([tets[:, l[:3]] for l in local])
    opposite = np.concatenate([tets[:, l[3]] for l in local])
    owner = np.tile(np.arange(len(tets)), 4)
    s = np.sort(faces, axis=1)
    n = int(tets.max()) + 1
    key = (s[:, 0] * n + s[:, 1]) * n + s[:, 2]
    _, inv, counts = np.unique(key, return_inverse=True, return_counts=True)
    keep = counts[inv] == 1
    return faces[keep], opposite[keep], owner[keep]


def convex_hull_2d(q):
    """Indices of the convex hull of 2D points, counter-clockwise."""
    order = np.lexsort((q[:, 1], q[:, 0]))

    def half(idx):
        h = []
        for i in idx:
            while len(h) >= 2 and np.cross(q[h[-1]] - q[h[-2]], q[i] - q[h[-2]]) <= 0:
                h.pop()
            h.append(i)
        return h

    lower, upper = half(order), half(order[::-1])
    return np.array(lower[:-1] + upper[:-1])


def flat_hull(points, dim):
    """The polygon (3D) or segment (2D) spanned by points without cells, or
    None if they are not flat."""
    c = points.mean(axis=0)
    _, sv, vt = np.linalg.svd(points - c)
    size = max(sv[0], 1e-300)
    if dim == 2:
        if sv[1] > 1e-9 * size:
            return None
        t = (points - c) @ vt[0]
        return np.array([c + t.min() * vt[0], c + t.max() * vt[0]])
    if len(points) < 3 or sv[2] > 1e-9 * size:
        return None
    q = np.stack([(points - c) @ vt[0], (points - c) @ vt[1]], axis=1)
    return points[convex_hull_2d(q)]


def clip_polygon(poly, lo, hi):
    """Sutherland-Hodgman clip of a polygon (k x 3) to the box [lo, hi]."""
    for axis in range(3):
        for bound, sign in ((lo[axis], 1.0), (hi[axis], -1.0)):
            if len(poly) == 0:
                return poly
            d = sign * (poly[:, axis] - bound)
            out = []
            for i in range(len(poly)):
                a, b, da, db = poly[i], poly[(i + 1) % len(poly)], d[i], d[(i + 1) % len(poly)]
                if da >= 0:
                    out.append(a)
                if (da >= 0) != (db >= 0):
                    out.append(a + (b - a) * (da / (da - db)))
            poly = np.array(out)
    return poly


# --------------------------------------------------------------------------
# One snapshot


class Scene:
    """Boundary geometry of one VTU, coloured."""

    def __init__(self, g, color):
        self.points = g["points"]
        body = g["cell_data"].get("body")
        vel = g["point_data"].get("velocity")
        stress = g["cell_data"].get("von_mises")
        tet_idx, tets = cells_of_type(g, VTK_TETRA)
        tri_idx, tris = cells_of_type(g, VTK_TRIANGLE)
        line_idx, lines = cells_of_type(g, VTK_LINE)
        self.dim = 3 if len(tets) else 2
        if self.dim == 2 and len(tris) and np.abs(self.points[:, 2]).max() > 0:
            self.dim = 3  # only bare triangles in 3D space
        if self.dim == 3:
            if len(tets):
                self.faces, self.opposite, owner = tet_boundary(tets)
                owner_cell = tet_idx[owner]
            else:  # only bare surfaces
                self.faces, self.opposite, owner_cell = np.zeros((0, 3), int), np.zeros(0, int), np.zeros(0, int)
            self.bare = tris  # bare rigid surfaces (3D)
            self.bare_cells = tri_idx
        else:
            self.faces, self.opposite, owner_cell = tris, None, tri_idx
            self.bare = lines
            self.bare_cells = line_idx
        self.owner = owner_cell
        # Output of conserve before it wrote the facets of bare rigid
        # surfaces as cells has their points only: draw the convex hull of
        # those points when they lie in a plane (3D) or the segment through
        # them when they lie on a line (2D).
        used = np.zeros(len(self.points), dtype=bool)
        used[g["connectivity"]] = True
        free = self.points[~used]
        self.free_polygon = None
        if len(free) >= 2:
            self.free_polygon = flat_hull(free, self.dim)
        self.body = body
        self.deformable_nodes = np.unique(self.faces) if len(self.faces) else np.arange(len(self.points))
        if color == "body" or (color == "speed" and vel is None) or (color == "stress" and stress is None):
            self.values = body[owner_cell] if body is not None else np.zeros(len(owner_cell))
            self.kind = "body"
        elif color == "speed":
            speed = np.linalg.norm(vel, axis=1)
            self.values = speed[self.faces].mean(axis=1)
            self.kind = "speed"
        else:
            self.values = stress[owner_cell]
            self.kind = "stress"

    def extent(self):
        p = self.points[self.deformable_nodes]
        return p.min(axis=0), p.max(axis=0)


def colour_map(kind, vmin, vmax, nbodies):
    if kind == "body":
        cmap = plt.get_cmap("tab10")
        return cmap, matplotlib.colors.Normalize(vmin=-0.5, vmax=9.5), None
    label = "|velocity| [m/s]" if kind == "speed" else "von Mises Cauchy stress [Pa]"
    return plt.get_cmap("viridis"), matplotlib.colors.Normalize(vmin=vmin, vmax=max(vmax, vmin + 1e-300)), label


def draw_3d(ax, sc, box, cmap, norm, view, max_faces):
    lo, hi = box
    elev, azim = np.radians(view[0]), np.radians(view[1])
    eye = np.array([np.cos(elev) * np.cos(azim), np.cos(elev) * np.sin(azim), np.sin(elev)])
    P = sc.points
    tri = P[sc.faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    # outward: away from the tet's fourth node
    flip = np.einsum("ij,ij->i", normals, P[sc.opposite] - tri[:, 0]) > 0
    normals[flip] *= -1
    front = np.einsum("ij,j->i", normals, eye) > 0
    tri, vals, normals = tri[front], sc.values[front], normals[front]
    stride = max(1, int(np.ceil(len(tri) / max_faces)))
    if stride > 1:
        tri, vals, normals = tri[::stride], vals[::stride], normals[::stride]
    # simple Lambert shading so that the shape reads in a still image
    unit = normals / np.maximum(np.linalg.norm(normals, axis=1), 1e-300)[:, None]
    light = np.array([0.3, -0.4, 0.87])
    shade = 0.55 + 0.45 * np.clip(np.abs(unit @ light), 0, 1)
    rgba = cmap(norm(vals))
    rgba[:, :3] *= shade[:, None]
    # rigid surfaces first; computed_zorder=False keeps the bodies on top
    if len(sc.bare):
        polys = [clip_polygon(P[f], lo, hi) for f in sc.bare]
        polys = [p for p in polys if len(p) >= 3]
        if polys:
            ax.add_collection3d(Poly3DCollection(polys, facecolors=(0.75, 0.75, 0.75, 0.35),
                                                 edgecolors=(0.3, 0.3, 0.3, 0.6), linewidths=0.5))
    if sc.free_polygon is not None:
        poly = clip_polygon(sc.free_polygon, lo, hi)
        if len(poly) >= 3:
            ax.add_collection3d(Poly3DCollection([poly], facecolors=(0.6, 0.6, 0.6, 0.5),
                                                 edgecolors=(0.3, 0.3, 0.3, 0.8), linewidths=0.8))
    ax.add_collection3d(Poly3DCollection(tri, facecolors=rgba, edgecolors=(0, 0, 0, 0.15), linewidths=0.2))
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(np.maximum(hi - lo, 0.02 * np.max(hi - lo)))
    ax.view_init(view[0], view[1])
    ax.set_xlabel("x [m]", fontsize=7)
    ax.set_ylabel("y [m]", fontsize=7)
    if view[0] > 80:  # from above: z does not show
        ax.set_zticks([])
    else:
        ax.set_zlabel("z [m]", fontsize=7)
    ax.tick_params(labelsize=6)
    return stride


def draw_2d(ax, sc, box, cmap, norm):
    lo, hi = box
    P = sc.points[:, :2]
    ax.add_collection(PolyCollection(P[sc.faces], array=sc.values, cmap=cmap, norm=norm,
                                     edgecolors=(0, 0, 0, 0.25), linewidths=0.2))
    if len(sc.bare):
        ax.add_collection(LineCollection(P[sc.bare], colors="0.3", linewidths=2))
    if sc.free_polygon is not None:
        seg = clip_polygon(np.column_stack([sc.free_polygon[:, :2], [0.0, 0.0]]), np.append(lo[:2], -1), np.append(hi[:2], 1))
        if len(seg) >= 2:
            ax.plot(seg[:, 0], seg[:, 1], color="0.3", lw=2)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]", fontsize=7)
    ax.set_ylabel("y [m]", fontsize=7)
    ax.tick_params(labelsize=6)
    return 1


# --------------------------------------------------------------------------


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("run", type=pathlib.Path, help="output folder of a run (solution.pvd, vtu/)")
    p.add_argument("--steps", type=int, nargs="+", help="steps to draw (nearest written VTU is used)")
    p.add_argument("--count", type=int, default=6, help="number of evenly spaced snapshots without --steps")
    p.add_argument("--color", choices=["body", "speed", "stress"], default="speed")
    p.add_argument("--view", type=float, nargs=2, metavar=("ELEV", "AZIM"),
                   help="3D camera elevation and azimuth [degrees] (default 20 -60; flat scenes: from above)")
    p.add_argument("--frame", choices=["auto", "fixed", "follow"], default="auto",
                   help="fixed: one frame for all snapshots; follow: each snapshot centred on the bodies; "
                        "auto: follow when the bodies travel more than twice their size")
    p.add_argument("--max-faces", type=int, default=60000, help="draw at most this many front faces (decimate)")
    p.add_argument("--out", type=pathlib.Path, help="folder of the PNGs (default RUN/snapshots)")
    args = p.parse_args()

    files = read_pvd(args.run)
    written = np.array([s for s, _, _ in files])
    if args.steps:
        pick = sorted({int(np.abs(written - s).argmin()) for s in args.steps})
    else:
        k = max(1, min(args.count, len(files)))
        pick = sorted(set(np.linspace(0, len(files) - 1, k).round().astype(int).tolist()))
    chosen = [files[i] for i in pick]
    out = args.out or args.run / "snapshots"
    out.mkdir(parents=True, exist_ok=True)

    scenes = [Scene(read_vtu(path), args.color) for _, _, path in chosen]
    dim = scenes[0].dim
    ext = [sc.extent() for sc in scenes]
    size = max(float(np.max(hi - lo)) for lo, hi in ext)
    glo = np.min([lo for lo, _ in ext], axis=0)
    ghi = np.max([hi for _, hi in ext], axis=0)
    frame = args.frame
    if frame == "auto":
        frame = "follow" if np.max(ghi - glo) > 2.0 * size else "fixed"

    span = np.max([hi - lo for lo, hi in ext], axis=0)  # largest extent of the bodies per axis

    def box(i):
        if frame == "follow":  # same box size in every frame, centred on the bodies
            c = 0.5 * (ext[i][0] + ext[i][1])
            lo, hi = c - 0.5 * span, c + 0.5 * span
        else:
            lo, hi = glo.copy(), ghi.copy()
        pad = 0.08 * max(float(np.max(hi - lo)), 1e-12)
        lo, hi = lo - pad, hi + pad
        sc = scenes[i]
        k = 2 if dim == 3 else 1  # show a bare rigid surface just below the bodies (e.g. the plane)
        if len(sc.bare):
            lo[k] = min(lo[k], sc.points[np.unique(sc.bare), k].min() - pad)
        if sc.free_polygon is not None:
            lo[k] = min(lo[k], sc.free_polygon[:, k].min() - pad)
        return lo, hi

    view = args.view
    if view is None:  # flat scenes (discs on a floor) read best from above
        flat = dim == 3 and float((ghi - glo)[2]) < 0.1 * float(np.max(ghi - glo))
        view = [90.0, -90.0] if flat else [20.0, -60.0]

    vals = np.concatenate([sc.values for sc in scenes])
    cmap, norm, label = colour_map(scenes[0].kind, float(vals.min()), float(vals.max()), 0)
    sub = {"projection": "3d", "computed_zorder": False} if dim == 3 else {}
    names = []
    n = len(scenes)
    cols = min(n, 3)
    rows = int(np.ceil(n / cols))
    b0 = box(0)
    aspect = float((b0[1] - b0[0])[1] / max((b0[1] - b0[0])[0], 1e-300)) if view[0] > 80 or dim == 2 else 0.85
    big = plt.figure(figsize=(4.6 * cols, min(4.0, max(1.8, 4.6 * aspect + 0.9)) * rows))
    for i, ((step, t, _), sc) in enumerate(zip(chosen, scenes)):
        title = f"step {step}" + ("" if np.isnan(t) else f", t = {t:.4g} s")
        for fig, ax in ((None, None), (big, big.add_subplot(rows, cols, i + 1, **sub))):
            if fig is None:
                fig = plt.figure(figsize=(6, 5))
                ax = fig.add_subplot(1, 1, 1, **sub)
            stride = draw_3d(ax, sc, box(i), cmap, norm, view, args.max_faces) if dim == 3 else draw_2d(
                ax, sc, box(i), cmap, norm)
            ax.set_title(title + (f" (1 face in {stride})" if stride > 1 else ""), fontsize=9)
            if fig is not big:
                if label:
                    fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax, shrink=0.6, label=label)
                fig.tight_layout()
                name = out / f"snapshot_{step:06d}.png"
                fig.savefig(name, dpi=110)
                plt.close(fig)
                names.append(name)
    if label:
        big.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=big.axes, shrink=0.6, label=label)
    else:
        bodies = sorted({int(v) for sc in scenes for v in np.unique(sc.values)})
        handles = [matplotlib.patches.Patch(color=cmap(norm(b)), label=f"body {b}") for b in bodies]
        big.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8)
    big.savefig(out / "snapshots.png", dpi=100)
    plt.close(big)
    print(f"snapshots: {len(names)} PNGs in {out}/ (snapshot_NNNNNN.png, snapshots.png); frame {frame}, "
          f"colour {scenes[0].kind}")


if __name__ == "__main__":
    main()
