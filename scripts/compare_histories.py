#!/usr/bin/env python3
"""How far two runs of one scenario part (e.g. on 1 and on N MPI ranks):
the largest difference over the rows of history.csv of the energies
(kinetic, strain, potential, total) over E_ref, of L and J over L_ref and
J_ref (the first run's summary.json drift_reference), of the active gaps
over the larger of their largest value and 1e-6 of the model's size; and
whether the active contacts are the same at every step.

Usage: python3 scripts/compare_histories.py RUN_A RUN_B   (prints JSON)
"""
import csv
import json
import math
import pathlib
import sys

GROUPS = {
    "E": ["kinetic", "strain", "potential", "total"],
    "L": ["L_x", "L_y", "L_z"],
    "J": ["J_x", "J_y", "J_z"],
    "gap": ["min_active_gap", "max_active_gap"],
}


def history(run):
    with open(pathlib.Path(run) / "history.csv") as f:
        rows = list(csv.reader(f))
    return {name: [float(r[k]) if r[k] else math.nan for r in rows[1:]] for k, name in enumerate(rows[0])}


def compare(run_a, run_b):
    a, b = history(run_a), history(run_b)
    reference = json.loads((pathlib.Path(run_a) / "summary.json").read_text())["drift_reference"]
    size = reference["angular_momentum"] / reference["momentum"]  # the model's bounding-box diagonal
    gap = max([1e-6 * size] + [abs(v) for c in GROUPS["gap"] for v in a.get(c, []) if not math.isnan(v)])
    scale = {"E": reference["energy"], "L": reference["momentum"], "J": reference["angular_momentum"], "gap": gap}
    out = {"rows": [len(a["step"]), len(b["step"])]}
    for group, columns in GROUPS.items():
        worst = 0.0
        for c in columns:
            for x, y in zip(a.get(c, []), b.get(c, [])):
                if math.isnan(x) and math.isnan(y):
                    continue
                worst = max(worst, abs(x - y) / scale[group] if not (math.isnan(x) or math.isnan(y)) else math.inf)
        out[group] = worst
        if group == "gap":
            out["gap_m"] = worst * scale[group]  # [m]
            out["gap_of_size"] = worst * scale[group] / size
    out["active_contacts_equal"] = a["active_contacts"] == b["active_contacts"]
    return out


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    print(json.dumps(compare(sys.argv[1], sys.argv[2])))
