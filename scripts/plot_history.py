#!/usr/bin/python3
"""Plots a conserve history.csv like the paper's Figures 4-6, 9-11 and 14.

Usage: /usr/bin/python3 scripts/plot_history.py out/NAME/history.csv
           [--out DIR] [--scenario SCENARIO.toml]

Writes, next to the history (or in DIR):
  energy.png          kinetic, elastic (strain), potential and total energy
  momentum.png        total linear and angular momentum (about the origin)
  body_momentum.png   linear momentum of each body (only with two or more
                      moving bodies: e.g. the velocity passing 1 -> 2 -> 3
                      in the Newton's cradle of the paper's section 6.1)
  contact.png         active contacts and total normal contact force
                      (only when the history has contact columns)
  drift.png           relative drift of E, |L|, |J| on a log scale, which
                      is what shows conservation
With --scenario, drift.png also says which quantities the scenario is
expected to conserve (gravity, fixed bodies, prescribed displacements and
stick friction remove some), draws the others dashed, and adds the
conserved components of L and J when their norms are not conserved.
"""
import argparse
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

AXES = "xyz"


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    # an empty field is a value that is not there (e.g. min_active_gap
    # with nothing active)
    header = rows[0]
    data = np.array([[float(x) if x else np.nan for x in row] for row in rows[1:]], dtype=float)
    if data.ndim != 2 or len(data) == 0:
        sys.exit(f"plot_history: {path}: no data rows")
    return {name: data[:, i] for i, name in enumerate(header)}


def vec(h, name):
    return np.stack([h[f"{name}_{c}"] for c in AXES], axis=1)


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


# --------------------------------------------------------------------------
# What the scenario should conserve


def expected_conservation(scenario_path):
    """Returns (E, L[3], J[3], reasons): booleans for the total energy and for
    each component of the linear and angular momentum (about the origin),
    read from the scenario's external actions:
      - gravity g: a force along g on every body (E keeps it in the
        potential; L is lost along g, J except about the axis along g);
      - a rigid (fixed or moving) body or a [[boundary]]: a reaction of any
        direction, except a rigid bare `square`/`segment` touched only by
        frictionless contact, which pushes along its normal (+z or +y);
      - a moving rigid body or a nonzero prescribed rate does work (E lost);
      - stick contact conserves L but not J (paper section 4)."""
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        return None
    with open(scenario_path, "rb") as f:
        s = tomllib.load(f)
    dim = int(s.get("dimension", 3))
    energy, reasons = True, []
    directions = []  # external force directions (unit vectors), or "any"
    any_direction = False
    g = np.array(list(s.get("loads", {}).get("gravity", [0.0] * dim)) + [0.0] * (3 - dim), dtype=float)
    if np.linalg.norm(g) > 0:
        directions.append(g / np.linalg.norm(g))
        reasons.append("gravity")
    bodies = {b["name"]: b for b in s.get("body", [])}
    contacts = s.get("contact", [])

    def body_of(surface):
        return surface.split(":")[0]

    for name, b in bodies.items():
        if not b.get("rigid", False):
            continue
        pairs = [c for c in contacts if body_of(c["master"]) == name or body_of(c["slave"]) == name]
        if not pairs:
            continue  # touches nothing: exerts nothing
        v = np.array(b.get("velocity", [0.0] * dim), dtype=float)
        if np.linalg.norm(v) > 0:
            energy = False
            reasons.append(f"moving rigid body '{name}' (work)")
        generator = b.get("mesh", {}).get("generator", "")
        flat = generator in ("square", "segment")
        if flat and all(c.get("kind") == "frictionless" for c in pairs):
            directions.append(np.array([0.0, 0.0, 1.0]) if generator == "square" else np.array([0.0, 1.0, 0.0]))
            reasons.append(f"frictionless reaction of rigid '{name}' along its normal")
        else:
            any_direction = True
            reasons.append(f"reaction of rigid '{name}'")
    for bc in s.get("boundary", []):
        any_direction = True
        reasons.append(f"prescribed displacement on '{bc.get('body', '?')}'")
        if any(float(r) != 0.0 for r in bc.get("rate", [])):
            energy = False
            reasons.append("prescribed rate (work)")
    stick = any(c.get("kind") == "stick" for c in contacts)
    if any_direction:
        L = [False] * 3
        J = [False] * 3
    else:
        e = np.eye(3)
        # L_e is conserved iff every external force is orthogonal to e; J_e
        # (about the origin, forces at arbitrary points) iff every external
        # force is parallel to e.
        L = [all(abs(d @ e[k]) < 1e-12 for d in directions) for k in range(3)]
        J = [all(np.linalg.norm(np.cross(d, e[k])) < 1e-12 for d in directions) for k in range(3)]
    if stick:
        J = [False] * 3
        reasons.append("stick friction (J not conserved)")
    if dim == 2:  # only L_x, L_y and J_z exist
        L[2] = False
        J[0] = J[1] = False
    return {"E": energy, "L": L, "J": J, "dim": dim, "reasons": reasons}


# --------------------------------------------------------------------------
# Plots


def plot_energy(h, out):
    fig, ax = plt.subplots(figsize=(7, 4))
    for key, label, style in [
        ("kinetic", "kinetic", "-"),
        ("strain", "elastic (strain)", "-"),
        ("potential", "potential (gravity)", "-"),
        ("total", "total", "k-"),
    ]:
        ax.plot(h["time"], h[key], style, label=label)
    ax.set(xlabel="time [s]", ylabel="energy [J]", title="Energies")
    ax.legend()
    ax.grid(alpha=0.3)
    save(fig, out / "energy.png")


def plot_momentum(h, out, dim):
    comps_L = AXES[:dim]
    comps_J = AXES if dim == 3 else "z"
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
    for c in comps_L:
        a1.plot(h["time"], h["L_" + c], label="L_" + c)
    for c in comps_J:
        a2.plot(h["time"], h["J_" + c], label="J_" + c)
    a1.set(xlabel="time [s]", ylabel="linear momentum [kg m/s]", title="Linear momentum (total)")
    a2.set(xlabel="time [s]", ylabel="angular momentum [kg m²/s]", title="Angular momentum (total, about the origin)")
    for a in (a1, a2):
        a.legend()
        a.grid(alpha=0.3)
    save(fig, out / "momentum.png")


def body_names(h):
    names = []
    for key in h:
        if key.startswith("L_x:"):
            names.append(key[4:])
    return names


def plot_body_momentum(h, out, dim):
    """Per-body linear momentum, one panel per component that moves."""
    names = body_names(h)
    moving = [n for n in names if any(np.abs(h[f"L_{c}:{n}"]).max() > 0 for c in AXES[:dim])]
    if len(moving) < 2:
        return None
    scale = max(np.abs(h[f"L_{c}:{n}"]).max() for n in moving for c in AXES[:dim])
    comps = [c for c in AXES[:dim] if max(np.abs(h[f"L_{c}:{n}"]).max() for n in moving) > 1e-3 * scale]
    fig, axes = plt.subplots(1, len(comps), figsize=(5.5 * len(comps), 4), squeeze=False)
    for a, c in zip(axes[0], comps):
        for n in moving:
            a.plot(h["time"], h[f"L_{c}:{n}"], label=n)
        a.plot(h["time"], h["L_" + c], "k--", lw=1, label="total")
        a.set(xlabel="time [s]", ylabel=f"L_{c} [kg m/s]", title=f"Linear momentum L_{c} per body")
        a.legend()
        a.grid(alpha=0.3)
    save(fig, out / "body_momentum.png")
    return "body_momentum.png"


def plot_contact(h, out):
    if "active_contacts" not in h or not np.any(h["active_contacts"]) and not np.any(h["activations"]):
        return None
    fig, a1 = plt.subplots(figsize=(7, 4))
    a1.plot(h["time"], h["active_contacts"], "C0-", lw=1, label="active contact nodes")
    a1.set(xlabel="time [s]", ylabel="active contact nodes", title="Contact")
    a1.grid(alpha=0.3)
    a2 = a1.twinx()
    a2.plot(h["time"], h["contact_force"], "C3-", lw=1, label="total normal force")
    a2.set_ylabel("total normal contact force [N]")
    lines = a1.get_lines() + a2.get_lines()
    a1.legend(lines, [l.get_label() for l in lines], loc="upper left")
    save(fig, out / "contact.png")
    return "contact.png"


def plot_drift(h, out, expected, dim):
    """Relative drift |q(t) - q(0)| / q_ref, the figures conserve itself
    reports (history columns drift_E, drift_L, drift_J; for L and J the
    norm of the vector change). The references never vanish while anything
    moves: E_ref is the largest K + W seen so far, L_ref the largest sum of
    the nodes' momentum magnitudes, J_ref = L_ref times the model's size."""
    t = h["time"][1:]
    L, J = vec(h, "L"), vec(h, "J")
    series = {"E": h["drift_E"], "|L|": h["drift_L"], "|J|": h["drift_J"]}

    def component(arr, drift, k):
        """|q_k(t) - q_k(0)| / q_ref, from the norm's drift and change."""
        change = np.linalg.norm(arr - arr[0], axis=1)
        part = np.abs(arr[:, k] - arr[0, k])
        return np.divide(drift * part, change, out=np.zeros_like(part), where=change > 0)

    fig, ax = plt.subplots(figsize=(8, 4.5))
    colours = {"E": "C0", "|L|": "C1", "|J|": "C2"}
    if expected is None:
        for label, d in series.items():
            ax.semilogy(t, np.maximum(d[1:], 1e-17), color=colours[label], label=label)
        title = "Conservation: relative drift |q(t) − q(0)| / q_ref"
        note = "expected conservation unknown (pass --scenario)"
    else:
        flags = {
            "E": expected["E"],
            "|L|": all(expected["L"][: dim]),
            "|J|": all(expected["J"]) if dim == 3 else expected["J"][2],
        }
        for label, d in series.items():
            ok = flags[label]
            ax.semilogy(t, np.maximum(d[1:], 1e-17), color=colours[label], ls="-" if ok else ":", lw=1.5 if ok else 1,
                        label=f"{label} ({'conserved' if ok else 'not conserved'})")
        # conserved components whose norm is not conserved
        for name, arr, flag_key, cols in [("L", L, "|L|", ("C1", "C3", "C5")), ("J", J, "|J|", ("C2", "C4", "C6"))]:
            if flags[flag_key]:
                continue
            for k, c in enumerate(AXES):
                if expected[name][k]:
                    d = component(arr, series[flag_key], k)
                    ax.semilogy(t, np.maximum(d[1:], 1e-17), color=cols[k], ls="-", lw=1,
                                label=f"{name}_{c} (conserved)")
        title = "Conservation: relative drift |q(t) − q(0)| / q_ref"
        note = "solid: expected conserved; dotted: not expected"
        if expected["reasons"]:
            note += "\n(" + "; ".join(dict.fromkeys(expected["reasons"])) + ")"
    ax.set(xlabel="time [s]", ylabel="relative drift", title=title)
    ax.text(0.01, 0.01, note, transform=ax.transAxes, fontsize=7, va="bottom", ha="left",
            bbox=dict(facecolor="white", alpha=0.7, lw=0))
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    ax.grid(alpha=0.3, which="both")
    save(fig, out / "drift.png")
    return {k: float(v.max()) for k, v in series.items()}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("history", type=pathlib.Path)
    p.add_argument("--out", type=pathlib.Path, help="folder of the PNGs (default: the history's folder)")
    p.add_argument("--scenario", type=pathlib.Path,
                   help="the run's scenario file: marks the quantities it should conserve")
    args = p.parse_args()
    out = args.out or args.history.parent
    out.mkdir(parents=True, exist_ok=True)
    h = read(args.history)
    expected = None
    if args.scenario:
        try:
            expected = expected_conservation(args.scenario)
        except (OSError, ValueError, KeyError, TypeError) as e:
            print(f"plot_history: {args.scenario}: not used ({e})", file=sys.stderr)
    dim = expected["dim"] if expected else (2 if not (np.any(h["L_z"]) or np.any(h["J_x"]) or np.any(h["J_y"])) else 3)
    written = ["energy.png", "momentum.png"]
    plot_energy(h, out)
    plot_momentum(h, out, dim)
    for extra in (plot_body_momentum(h, out, dim), plot_contact(h, out)):
        if extra:
            written.append(extra)
    drift = plot_drift(h, out, expected, dim)
    written.append("drift.png")
    print("plots: " + " ".join(f"{out}/{w}" for w in written))
    print("max relative drift: " + "  ".join(f"{k} {v:.2e}" for k, v in drift.items()))
    if expected:
        keep = ["E"] if expected["E"] else []
        keep += [f"L_{c}" for k, c in enumerate(AXES) if expected["L"][k]]
        keep += [f"J_{c}" for k, c in enumerate(AXES) if expected["J"][k]]
        print("expected conserved: " + (", ".join(keep) if keep else "none"))


if __name__ == "__main__":
    main()
