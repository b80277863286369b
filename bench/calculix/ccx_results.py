"""Reads a CalculiX run of the peer cube (cube_to_ccx.py's deck): energies
and the lowest node at each printed time from JOB.dat, increments and
iterations from JOB.sta. Prints one JSON line:
time reached, increments, iterations, energy error (largest over the run,
at the end and at the last time out of contact, of E = ccx's kinetic +
strain energy + gravity's potential, against the initial E), largest
penetration of a cube node below the plane z = 0, and the contact
intervals.

    /usr/bin/python3 ccx_results.py JOB
"""
import json
import re
import sys

import numpy as np

job = sys.argv[1]
deck = json.load(open(job + ".json"))
mass, z0, g = np.array(deck["mass"]), np.array(deck["z"]), deck["g"]
v0 = np.array(deck["v0"])
e0 = 0.5 * mass.sum() * v0.dot(v0) + g * mass.dot(z0)

times, kinetic, strain, lowest, moment = [], {}, {}, {}, {}
with open(job + ".dat") as f:
    lines = f.read().splitlines()
header = re.compile(r"\s*(total internal energy|total kinetic energy|displacements \(vx,vy,vz\)) for set \S+ and time\s+(\S+)")
i = 0
while i < len(lines):
    m = header.match(lines[i])
    if not m:
        i += 1
        continue
    what, t = m.group(1), float(m.group(2))
    i += 1
    while i < len(lines) and not lines[i].strip():
        i += 1
    if what.startswith("total"):
        (kinetic if "kinetic" in what else strain)[t] = float(lines[i])
        i += 1
        continue
    uz = np.zeros(len(z0))
    while i < len(lines) and lines[i].strip():
        node, _, _, w = lines[i].split()
        uz[int(node) - 1] = float(w)
        i += 1
    z = z0 + uz
    lowest[t] = z.min()
    moment[t] = mass.dot(z)
common = sorted(set(kinetic) & set(strain) & set(moment))
energy = np.array([kinetic[t] + strain[t] + g * moment[t] for t in common])
error = (energy - e0) / e0
contact, start = [], None
for t in sorted(lowest):
    if lowest[t] < 0.0 and start is None:
        start = t
    if lowest[t] >= 0.0 and start is not None:
        contact.append([start, t])
        start = None
if start is not None:
    contact.append([start, None])
# Out of contact the penalty springs hold no energy: the error there is
# the scheme's alone. The last printed time with no node below the plane.
flight = [k for k, t in enumerate(common) if lowest[t] >= 0.0]

sta = [l.split() for l in open(job + ".sta").read().splitlines()[2:] if l.split()]
increments = len(sta)
iterations = sum(int(r[3]) for r in sta)
print(json.dumps({
    "reached": common[-1] if common else 0.0,
    "increments": increments,
    "last_increments": [float(r[6]) for r in sta[-3:]],
    "iterations": iterations,
    "error_end": float(error[-1]) if len(error) else None,
    "error_max": float(error[np.argmax(np.abs(error))]) if len(error) else None,
    "flight_time": common[flight[-1]] if flight else None,
    "error_flight": float(error[flight[-1]]) if flight else None,
    "penetration": float(max(0.0, -min(lowest.values()))) if lowest else None,
    "contact": contact,
}))
