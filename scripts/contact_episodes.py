#!/usr/bin/python3
"""Contact episodes and releases, node by node, from a run's VTU output.

    /usr/bin/python3 scripts/contact_episodes.py OUTPUT_DIR [--json]

OUTPUT_DIR is a `conserve run -o` folder written with `[output] vtu_every = 1`
(every step is needed to see each activation and release). A slave is active
at a step's end where `contact_normal_force` is a number (NaN elsewhere).

- A *bounce* is a maximal run of steps with at least one active slave.
- In a bounce a node's first activation opens its *episode*; each further
  activation of it in the same bounce is a *return*: it was released and came
  back (chatter, or a faceted surface rolling from node to node).
- Each *release* is measured by the node's force at the end of the step
  before over the mean force of the active slaves then, as `loaded_releases`
  counts it in history.csv (above 1 % is "loaded"). A node whose force falls
  continuously to zero before it lifts carries O(Δt) there; a reversing
  velocity leaves a jump that does not shrink with Δt (docs/validation.md §6).
- A loaded release of a node that was active for one step only is a
  *landing*: the force it is measured by is its landing's impulse over that
  step, which no choice of steps makes small. `--list` prints every loaded
  release with its step, node, steps active and force over the mean.

Activations and releases within one step are not seen here (the program's
own counts in summary.json include them).
"""
import argparse
import json
import math
import re
import sys
from pathlib import Path

try:
    import numpy
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
except ImportError as e:
    print(f"contact_episodes.py: error: {e} (install python3-vtk9 and python3-numpy: scripts/install-deps.sh)",
          file=sys.stderr)
    sys.exit(1)


def fail(message):
    print(f"contact_episodes.py: error: {message}", file=sys.stderr)
    sys.exit(1)


def step_files(directory):
    vtu = Path(directory) / "vtu"
    if not vtu.is_dir():
        fail(f"{directory}: no vtu/ folder (is it a `conserve run -o` output?)")
    files = sorted((int(m.group(1)), p) for p in vtu.glob("step_*.vtu") if (m := re.fullmatch(r"step_(\d+)\.vtu", p.name)))
    if len(files) < 2:
        fail(f"{vtu}: fewer than two step_*.vtu files")
    steps = [s for s, _ in files]
    if steps != list(range(steps[0], steps[0] + len(steps))):
        gap = next(b for a, b in zip(steps, steps[1:]) if b != a + 1)
        fail(f"{vtu}: steps are not consecutive (step {gap} follows a gap); run with --set output.vtu_every=1")
    return [p for _, p in files]


def normal_forces(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    array = reader.GetOutput().GetPointData().GetArray("contact_normal_force")
    if array is None:
        fail(f"{path}: no contact_normal_force field (no [[contact]] in the scenario?)")
    return vtk_to_numpy(array).astype(float)


def measure(files):
    """Bounces, and each release as (step, node, steps active, force / mean)."""
    bounces, releases = [], []
    previous = normal_forces(files[0])
    since = {int(k): 0 for k in (~numpy.isnan(previous)).nonzero()[0]}  # node: step of its activation
    bounce = None
    for step, path in enumerate(files[1:], start=1):
        forces = normal_forces(path)
        if forces.shape != previous.shape:
            fail(f"{path}: {forces.size} nodes, the step before had {previous.size}")
        was, now = ~numpy.isnan(previous), ~numpy.isnan(forces)
        active_before = previous[was]
        mean = float(active_before.mean()) if active_before.size else 0.0
        released = [int(k) for k in (was & ~now).nonzero()[0]]
        for k in released:
            releases.append((step, k, step - since.pop(k), previous[k] / mean if mean > 0.0 else math.nan))
        for k in (now & ~was).nonzero()[0]:
            since[int(k)] = step
        if now.any() and bounce is None:
            bounce = {"steps": 0, "activations": {}, "releases": 0}
        if bounce is not None:
            bounce["releases"] += len(released)
            if now.any():
                bounce["steps"] += 1
                for k in (now & ~was).nonzero()[0]:
                    bounce["activations"][int(k)] = bounce["activations"].get(int(k), 0) + 1
            else:
                bounces.append(bounce)
                bounce = None
        previous = forces
    if bounce is not None:
        bounces.append(bounce)
    return bounces, releases


def summarise(files, bounces, releases):
    episodes = sum(len(b["activations"]) for b in bounces)
    activations = sum(sum(b["activations"].values()) for b in bounces)
    measured = sorted(r[3] for r in releases if not math.isnan(r[3]))
    loaded = [r for r in releases if r[3] > 0.01]
    return {
        "steps": len(files) - 1,
        "bounces": [
            {"steps": b["steps"], "nodes": len(b["activations"]), "activations": sum(b["activations"].values()),
             "releases": b["releases"]} for b in bounces
        ],
        "node_episodes": episodes,
        "activations": activations,
        "returns": activations - episodes,
        "releases": len(releases),
        "loaded_releases": len(loaded),
        "loaded_landings": sum(1 for r in loaded if r[2] == 1),
        "loaded": [{"step": r[0], "node": r[1], "steps_active": r[2], "force_over_mean": r[3]} for r in loaded],
        "release_force_median": measured[len(measured) // 2] if measured else None,
        "release_force_max": measured[-1] if measured else None,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output_dir")
    parser.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    parser.add_argument("--list", action="store_true", help="print every loaded release")
    args = parser.parse_args()
    files = step_files(args.output_dir)
    s = summarise(files, *measure(files))
    if args.json:
        print(json.dumps(s))
        return
    print(f"{s['steps']} steps, {len(s['bounces'])} bounces (steps, nodes, activations, releases):")
    for b in s["bounces"]:
        print(f"  {b['steps']}, {b['nodes']}, {b['activations']}, {b['releases']}")
    print(f"node episodes {s['node_episodes']}, activations {s['activations']}, returns {s['returns']}")
    if s["releases"]:
        print(f"releases {s['releases']}, loaded (> 1 % of the mean force before) {s['loaded_releases']}, "
              f"of which landings (active one step) {s['loaded_landings']}; "
              f"force before / mean: median {s['release_force_median']:.3g}, largest {s['release_force_max']:.3g}")
        if args.list:
            for r in s["loaded"]:
                print(f"  step {r['step']}, node {r['node']}: active {r['steps_active']} steps, "
                      f"force before / mean {r['force_over_mean']:.3g}")
    else:
        print("no releases")


if __name__ == "__main__":
    main()
