"""Writes the peer cube (bench/cube/febio_cube.msh and febio_cube.toml's
set-up) as a CalculiX input deck: the cube as C3D4, SVK (`*ELASTIC` under
NLGEOM), the plane z = 0 as a fixed slab of C3D8, frictionless penalty
contact, gravity, the initial velocity, `*DYNAMIC` with ccx's defaults
(HHT alpha = -0.05, automatic increments from 1e-3 s).

    /usr/bin/python3 cube_to_ccx.py MSH OUT.inp [--contact nts|sts] [--end T]

Also writes OUT.json: the cube nodes' lumped masses and heights, from
which ccx_results.py sums gravity's potential and finds the lowest node.
"""
import argparse
import json

import meshio
import numpy as np

E, NU, RHO, G = 4.0e6, 0.45, 1000.0, 9.81
V0 = (0.5, 0.0, -1.0)
# FEBio's automatic penalty 3E/h on this mesh, as the peer README's runs.
PENALTY = 7.8e8

parser = argparse.ArgumentParser()
parser.add_argument("msh")
parser.add_argument("out")
parser.add_argument("--contact", choices=["nts", "sts"], default="nts")
parser.add_argument("--end", type=float, default=0.6)
args = parser.parse_args()

mesh = meshio.read(args.msh)
x = mesh.points
tets = mesh.cells_dict["tetra"]
a, b, c, d = (x[tets[:, i]] for i in range(4))
volume = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6.0
if (volume <= 0.0).any():
    raise SystemExit(f"{args.msh}: {int((volume <= 0).sum())} tetrahedra not positively oriented")

# Boundary faces (each in one tet only), as C3D4 faces S1..S4.
faces = {1: (0, 1, 2), 2: (0, 3, 1), 3: (1, 3, 2), 4: (2, 3, 0)}
count = {}
for e, t in enumerate(tets):
    for s, f in faces.items():
        key = tuple(sorted(t[list(f)]))
        count.setdefault(key, []).append((e, s))
boundary = [v[0] for v in count.values() if len(v) == 1]

# Lumped masses (a quarter of each tet's): Σ m_i z_i is then the exact
# first moment of the mass for linear tetrahedra, so gravity's potential
# follows from the nodes' displacements (ccx_results.py).
lumped = np.zeros(len(x))
np.add.at(lumped, tets.ravel(), np.repeat(volume * RHO / 4.0, 4))

n_cube = len(x)
# The slab: 4 x 4 C3D8 over 2 m x 2 m, 0.1 m thick, top at z = 0.
slab_nodes, slab_elems = [], []
nx, side, thick = 4, 2.0, 0.1
ids = {}
for k, z in enumerate((-thick, 0.0)):
    for j in range(nx + 1):
        for i in range(nx + 1):
            ids[(i, j, k)] = n_cube + len(slab_nodes) + 1
            slab_nodes.append((-side / 2 + side * i / nx, -side / 2 + side * j / nx, z))
for j in range(nx):
    for i in range(nx):
        c8 = [ids[(i, j, 0)], ids[(i + 1, j, 0)], ids[(i + 1, j + 1, 0)], ids[(i, j + 1, 0)],
              ids[(i, j, 1)], ids[(i + 1, j, 1)], ids[(i + 1, j + 1, 1)], ids[(i, j + 1, 1)]]
        slab_elems.append(c8)
n_tet = len(tets)


def lines(values, per=8):
    values = [str(v) for v in values]
    return "\n".join(", ".join(values[i:i + per]) for i in range(0, len(values), per))


out = []
out.append("*HEADING\nconserve peer benchmark: the bouncing cube (bench/cube/README.md)")
out.append("*NODE, NSET=NALL")
out += [f"{i + 1}, {p[0]:.13e}, {p[1]:.13e}, {p[2]:.13e}" for i, p in enumerate(x)]
out += [f"{n_cube + i + 1}, {p[0]:.13e}, {p[1]:.13e}, {p[2]:.13e}" for i, p in enumerate(slab_nodes)]
out.append("*ELEMENT, TYPE=C3D4, ELSET=ECUBE")
out += [f"{e + 1}, " + ", ".join(str(n + 1) for n in t) for e, t in enumerate(tets)]
out.append("*ELEMENT, TYPE=C3D8, ELSET=ESLAB")
out += [f"{n_tet + e + 1}, " + ", ".join(str(n) for n in c8) for e, c8 in enumerate(slab_elems)]
out.append("*NSET, NSET=NCUBE, GENERATE\n1, {}, 1".format(n_cube))
out.append("*NSET, NSET=NSLAB, GENERATE\n{}, {}, 1".format(n_cube + 1, n_cube + len(slab_nodes)))
out.append("*SURFACE, NAME=SCUBE, TYPE=ELEMENT")
out += [f"{e + 1}, S{s}" for e, s in boundary]
out.append("*SURFACE, NAME=SSLAB, TYPE=ELEMENT")
out += [f"{n_tet + e + 1}, S2" for e in range(len(slab_elems))]
out.append(f"*MATERIAL, NAME=MCUBE\n*ELASTIC\n{E:g}, {NU:g}\n*DENSITY\n{RHO:g}")
out.append("*MATERIAL, NAME=MSLAB\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7800.")
out.append("*SOLID SECTION, ELSET=ECUBE, MATERIAL=MCUBE")
out.append("*SOLID SECTION, ELSET=ESLAB, MATERIAL=MSLAB")
out.append("*SURFACE INTERACTION, NAME=SI")
if args.contact == "nts":
    out.append(f"*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n{PENALTY:g}")
    out.append("*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE\nSCUBE, SSLAB")
else:
    out.append(f"*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n{PENALTY:g}")
    out.append("*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE\nSCUBE, SSLAB")
out.append("*BOUNDARY\nNSLAB, 1, 3")
out.append(f"*INITIAL CONDITIONS, TYPE=VELOCITY\nNCUBE, 1, {V0[0]:g}\nNCUBE, 2, {V0[1]:g}\nNCUBE, 3, {V0[2]:g}")
out.append("*STEP, NLGEOM, INC=1000000")
out.append(f"*DYNAMIC\n1e-3, {args.end:g}")
out.append(f"*DLOAD\nECUBE, GRAV, {G:g}, 0., 0., -1.")
out.append("*EL PRINT, ELSET=ECUBE, TOTALS=ONLY\nELSE, ELKE")
out.append("*NODE PRINT, NSET=NCUBE\nU")
out.append("*CONTACT PRINT\nCDIS")
out.append("*END STEP")
with open(args.out, "w") as f:
    f.write("\n".join(out) + "\n")
total = {"g": G, "v0": V0, "contact": args.contact, "end": args.end, "slave_faces": len(boundary),
         "mass": lumped.tolist(), "z": x[:, 2].tolist()}
with open(args.out.rsplit(".", 1)[0] + ".json", "w") as f:
    json.dump(total, f, indent=1)
print(f"{args.out}: {n_cube} + {len(slab_nodes)} nodes, {n_tet} C3D4 + {len(slab_elems)} C3D8, "
      f"{len(boundary)} slave faces, mass {lumped.sum():.6g} kg")
