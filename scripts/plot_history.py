#!/usr/bin/python3
"""Plots a conserve history.csv like the paper's Figures 4-6, 9-11 and 14.

Usage: /usr/bin/python3 scripts/plot_history.py out/NAME/history.csv [--out DIR]

Writes, next to the history (or in DIR):
  energy.png          kinetic, elastic (strain), potential and total energy
  momentum.png        total linear and angular momentum (about the origin)
  body_momentum.png   linear momentum of each body (only with two or more
                      moving bodies: e.g. the velocity passing 1 -> 2 -> 3
                      in the Newton's cradle of the paper's section 6.1)
  contact.png         active contacts and total normal contact force
                      (only when the history has contact columns)
  reactions.png       each support's reaction against its displacement
                      (only when the run has supports or rigid tools)
  drift.png           the drifts conserve reports (history.csv's drift_E,
                      drift_L, drift_J) on a log scale; the summary.json
                      beside the history names the components of L and J
                      they cover and why the others are not conserved
"""
import argparse
import csv
import json
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


def conservation(history):
    """(drift keys, not_conserved) of the summary.json beside the history,
    or None while the run has not written it."""
    summary = history.parent / "summary.json"
    try:
        with open(summary) as f:
            s = json.load(f)
        return list(s["drift"]), s["not_conserved"]
    except (OSError, ValueError, KeyError):
        return None


def plot_drift(h, out, conserved):
    """The drifts conserve reports: the largest deviation so far over the
    run's scale so far, for E (total + released) and the largest of the
    conserved components of L and of J (empty fields when none is)."""
    t = h["time"][1:]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    note = "which components are conserved: in summary.json (not written yet)"
    labels = {"E": "E", "L": "L", "J": "J"}
    if conserved:
        keys, others = conserved
        for q in ("L", "J"):
            comps = [k for k in keys if k.startswith(q + "_")]
            labels[q] = f"{q} ({', '.join(comps)})" if comps else q
        note = "not conserved: " + ("; ".join(f"{k} ({why})" for k, why in others.items()) if others else "none")
    drifts = {}
    for q, column, colour in (("E", "drift_E", "C0"), ("L", "drift_L", "C1"), ("J", "drift_J", "C2")):
        d = h[column][1:]
        if np.all(np.isnan(d)):
            continue
        ax.semilogy(t, np.maximum(d, 1e-17), color=colour, label=labels[q])
        drifts[labels[q]] = float(d[~np.isnan(d)][-1])  # the run's: its last row
    ax.set(xlabel="time [s]", ylabel="drift", title="Conservation: largest |q − q0| so far / the run's scale")
    ax.text(0.01, 0.01, note, transform=ax.transAxes, fontsize=7, va="bottom", ha="left",
            bbox=dict(facecolor="white", alpha=0.7, lw=0))
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    ax.grid(alpha=0.3, which="both")
    save(fig, out / "drift.png")
    return drifts


def plot_reactions(h, out):
    """Each support's reaction along its largest component against its
    displacement along the same axis (a rigid tool's force–indentation
    curve), or against time for a support that does not move."""
    names = [k[len("work:"):] for k in h if k.startswith("work:")]
    if not names:
        return None
    fig, ax = plt.subplots(figsize=(7, 4.5))
    moving = False
    for n in names:
        R = np.stack([h[f"R_{c}:{n}"] for c in AXES], axis=1)
        u = np.stack([h[f"u_{c}:{n}"] for c in AXES], axis=1)
        k = int(np.argmax(np.abs(R).max(axis=0)))
        if np.abs(u[:, k]).max() > 0:
            moving = True
            sign = np.sign(u[np.argmax(np.abs(u[:, k])), k])  # the way it moves: drawn positive
            pre = "" if sign > 0 else "−"
            ax.plot(sign * u[:, k], sign * R[:, k], label=f"{n}: {pre}R_{AXES[k]} against {pre}u_{AXES[k]}")
    if not moving:
        plt.close(fig)
        fig, ax = plt.subplots(figsize=(7, 4.5))
    for n in names:
        R = np.stack([h[f"R_{c}:{n}"] for c in AXES], axis=1)
        u = np.stack([h[f"u_{c}:{n}"] for c in AXES], axis=1)
        k = int(np.argmax(np.abs(R).max(axis=0)))
        if not moving:
            ax.plot(h["time"], R[:, k], label=f"{n}: R_{AXES[k]}")
    ax.set(xlabel="displacement [m]" if moving else "time [s]", ylabel="reaction [N]",
           title="Reactions of the supports and rigid tools")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    save(fig, out / "reactions.png")
    return "reactions.png"


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("history", type=pathlib.Path)
    p.add_argument("--out", type=pathlib.Path, help="folder of the PNGs (default: the history's folder)")
    args = p.parse_args()
    out = args.out or args.history.parent
    out.mkdir(parents=True, exist_ok=True)
    h = read(args.history)
    dim = 2 if not (np.any(h["L_z"]) or np.any(h["J_x"]) or np.any(h["J_y"])) else 3
    written = ["energy.png", "momentum.png"]
    plot_energy(h, out)
    plot_momentum(h, out, dim)
    for extra in (plot_body_momentum(h, out, dim), plot_contact(h, out), plot_reactions(h, out)):
        if extra:
            written.append(extra)
    drift = plot_drift(h, out, conservation(args.history))
    written.append("drift.png")
    print("plots: " + " ".join(f"{out}/{w}" for w in written))
    print("drift: " + "  ".join(f"{k} {v:.2e}" for k, v in drift.items()))


if __name__ == "__main__":
    main()
