#!/usr/bin/python3
"""Plots a conserve history.csv: energies, linear and angular momentum
against time (like the paper's Figures 4-6), and the relative drift of
E, |L| and |J| on a log scale, which is what shows conservation.

Usage: /usr/bin/python3 scripts/plot_history.py out/NAME/history.csv [--out DIR]
Writes energy.png, momentum.png and drift.png next to the history (or in DIR).
"""
import argparse
import csv
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return {name: data[:, i] for i, name in enumerate(header)}


def relative_drift(values, scale):
    return np.abs(values - values[0]) / max(scale, 1e-300)


def plot_energy(h, out):
    fig, ax = plt.subplots(figsize=(7, 4))
    for key, label in [("kinetic", "kinetic"), ("strain", "elastic"), ("potential", "potential"), ("total", "total")]:
        ax.plot(h["time"], h[key], label=label)
    ax.set(xlabel="time [s]", ylabel="energy [J]", title="Energies")
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "energy.png", dpi=120)


def plot_momentum(h, out):
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
    for c in "xyz":
        a1.plot(h["time"], h["L_" + c], label="L_" + c)
        a2.plot(h["time"], h["J_" + c], label="J_" + c)
    a1.set(xlabel="time [s]", ylabel="linear momentum [kg m/s]", title="Linear momentum")
    a2.set(xlabel="time [s]", ylabel="angular momentum [kg m²/s]", title="Angular momentum (about the origin)")
    for a in (a1, a2):
        a.legend()
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "momentum.png", dpi=120)


def plot_drift(h, out):
    L = np.stack([h["L_x"], h["L_y"], h["L_z"]], axis=1)
    J = np.stack([h["J_x"], h["J_y"], h["J_z"]], axis=1)
    series = {
        "E": relative_drift(h["total"], abs(h["total"][0])),
        "|L|": np.linalg.norm(L - L[0], axis=1) / max(np.linalg.norm(L[0]), 1e-300),
        "|J|": np.linalg.norm(J - J[0], axis=1) / max(np.linalg.norm(J[0]), 1e-300),
    }
    fig, ax = plt.subplots(figsize=(7, 4))
    for label, d in series.items():
        ax.semilogy(h["time"][1:], np.maximum(d[1:], 1e-17), label=label)
    ax.set(xlabel="time [s]", ylabel="relative drift", title="Conservation: |q(t) - q(0)| / |q(0)|")
    ax.legend()
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(out / "drift.png", dpi=120)
    return {k: float(v.max()) for k, v in series.items()}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("history", type=pathlib.Path)
    p.add_argument("--out", type=pathlib.Path)
    args = p.parse_args()
    out = args.out or args.history.parent
    out.mkdir(parents=True, exist_ok=True)
    h = read(args.history)
    plot_energy(h, out)
    plot_momentum(h, out)
    drift = plot_drift(h, out)
    print("plots: {0}/energy.png {0}/momentum.png {0}/drift.png".format(out))
    print("max relative drift: " + "  ".join(f"{k} {v:.2e}" for k, v in drift.items()))


if __name__ == "__main__":
    main()
