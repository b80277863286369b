#!/usr/bin/python3
"""Constraint methods side by side: runs each case with every method on the
same scenario file (only [[contact]] `method`, `penalty`, `penalty_force`
or the [active_set] scheme change, by --set) and writes docs/comparison.md
with the figures in docs/figures/comparison_*.png.

Usage: /usr/bin/python3 bench/comparison.py [--quick] [--binary PATH]
           [--work DIR] [--cases cube,bars,...] [--no-run]
  --quick   a few hundred steps of each case (tests the script, minutes;
            the page and figures go to the work folder, not docs/)
  --binary  the conserve to run (default build/release/conserve, copied to
            the work folder first so that a rebuild does not change it)
  --work    where the runs go (default out/bench/comparison[_quick])
  --no-run  reuse the runs in the work folder (re-make the page only)

Every run is on one thread (OMP_NUM_THREADS=1), so that the wall times
compare the methods, not the machine's load.
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# name, title, scenario, steps in --quick, extra facts
CASES = [
    ("cube", "Peer cube (FEBio's mesh) on a rigid plane, frictionless", "bench/cube/febio_cube.toml", 300, {}),
    ("cylinders_61", "Paper §6.1: three cylinders, frictionless", "examples/cylinders/three_cylinders.toml", 200, {}),
    ("hollow_62", "Paper §6.2: two hollow cylinders, frictionless", "examples/cylinders/two_hollow_cylinders.toml",
     300, {}),
    ("ball_63", "Paper §6.3: hollow ball on a rigid plane, full stick", "examples/ball/ball_on_plane.toml", 500, {}),
    ("bars", "Two bars, longitudinal impact (2D), frictionless", "examples/validation/bars_2d.toml", 250,
     {"bodies": {"A": 100.0, "B": 100.0}, "duration": 2e-3, "exit": {"A": 0.0, "B": 1.0}}),
    ("block", "Block resting on a rigid plane under gravity, frictionless", "bench/comparison/block_on_plane.toml",
     300, {}),
]

PAPER = ["--set", "active_set.scheme=paper", "--set", "active_set.locate_impacts=false"]
LOCATED = ["--set", "active_set.scheme=persistent", "--set", "active_set.locate_impacts=true"]
# name, label, --set arguments (the penalty's are added per case)
VARIANTS = [
    ("paper", "elimination (the paper's scheme)", PAPER),
    ("located", "elimination, located + persistent", LOCATED),
    ("lagrange", "Lagrange multipliers (the paper's scheme)", ["--set", "contact.0.method=lagrange"] + PAPER),
    ("penalty", "penalty (discrete gradient)", ["--set", "contact.0.method=penalty"]),
    ("penalty_mid", "penalty, mid-point force (control)",
     ["--set", "contact.0.method=penalty", "--set", "contact.0.penalty_force=midpoint"]),
]
FACTORS = [0.1, 1.0, 10.0, 100.0]


def run(binary, scenario, out, extra, steps):
    args = [str(binary), "run", "-q", "-o", str(out), str(ROOT / scenario), "--set", "output.vtu_every=0"] + extra
    if steps:
        args += ["--steps", str(steps)]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    r = subprocess.run(args, capture_output=True, text=True, env=env)
    (out.parent / (out.name + ".log")).write_text(" ".join(args) + "\n" + r.stdout + r.stderr)
    return r.returncode == 0


def load(out):
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "history.csv") as f:
        rows = list(csv.DictReader(f))
    return summary, rows


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def contact_window(rows):
    """First and last time a contact carries force."""
    times = [number(r["time"]) for r in rows if number(r["contact_force"]) > 0.0 or number(r["active_contacts"]) > 0]
    return (times[0], times[-1]) if times else (math.nan, math.nan)


def figures(summary, rows):
    """One table row's figures."""
    def drift(kind):
        picked = [v for k, v in summary["drift"].items() if k.startswith(kind + "_")]
        return max(picked) if picked else math.nan

    solves = summary.get("linear_solves") or 0
    gaps = [abs(number(r["max_active_gap"])) for r in rows if not math.isnan(number(r["max_active_gap"]))]
    return {
        "E": summary["drift"]["E"],
        "L": drift("L"),
        "J": drift("J"),
        "slave": summary.get("slave_penetration", math.nan),
        "master": summary.get("master_penetration", math.nan),
        "gap": max(gaps) if gaps else 0.0,
        "newton": summary["mean_newton_iterations"],
        "krylov": summary["linear_iterations"] / solves if solves else math.nan,
        "equations": (summary.get("mean_equations", math.nan), summary.get("max_equations", math.nan)),
        "failed": summary["cutbacks"],
        "wall": summary["wall_seconds"],
        "released": summary.get("contact_released", 0.0),
        "steps": summary["steps"],
    }


def fmt(v, digits=2):
    if isinstance(v, float) and math.isnan(v):
        return "–"
    if isinstance(v, int):
        return str(v)
    if v == 0:
        return "0"
    return f"{v:.{digits}e}" if abs(v) < 1e-2 or abs(v) >= 1e4 else f"{v:.{digits + 1}g}"


def plot(case, title, series, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    for label, rows in series:
        t = [number(r["time"]) for r in rows]
        e0 = number(rows[0]["total"])
        top.plot(t, [(number(r["total"]) - e0) / abs(e0) for r in rows], label=label)
        bottom.plot(t, [number(r["slave_penetration"]) * 1e3 for r in rows], label=label)
    top.set_ylabel("(E − E₀) / E₀")
    top.set_title(title)
    top.legend(fontsize=8)
    top.grid(alpha=0.3)
    bottom.set_ylabel("deepest slave behind its master [mm]")
    bottom.set_xlabel("time [s]")
    bottom.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--binary", default=str(ROOT / "build/release/conserve"))
    ap.add_argument("--work")
    ap.add_argument("--cases")
    ap.add_argument("--no-run", action="store_true")
    a = ap.parse_args()
    work = Path(a.work or ROOT / ("out/bench/comparison_quick" if a.quick else "out/bench/comparison"))
    work.mkdir(parents=True, exist_ok=True)
    binary = work / "conserve"
    if not a.no_run:
        shutil.copy2(a.binary, binary)
    cases = [c for c in CASES if not a.cases or c[0] in a.cases.split(",")]
    page = work / "comparison.md" if a.quick else ROOT / "docs/comparison.md"
    figures_dir = work / "figures" if a.quick else ROOT / "docs/figures"
    figures_dir.mkdir(parents=True, exist_ok=True)
    out_lines = []
    for name, title, scenario, quick_steps, facts in cases:
        steps = quick_steps if a.quick else None
        print(f"{name}:", end="", flush=True)
        results, series = {}, []
        for variant, label, extra in VARIANTS:
            out = work / name / variant
            if not a.no_run:
                ok = run(binary, scenario, out, extra, steps)
                print(f" {variant}{'' if ok else ' (failed)'}", end="", flush=True)
            if (out / "summary.json").exists():
                results[variant] = load(out)
                series.append((label, results[variant][1]))
        # The penalty at multiples of its automatic ε.
        sweep = []
        if "penalty" in results:
            eps = results["penalty"][0].get("contact_settings", {})
            for factor in FACTORS:
                out = work / name / f"penalty_x{factor:g}"
                extra = ["--set", "contact.0.method=penalty"]
                for key, value in eps.items():
                    pair = key[key.index("[") + 1:key.index("]")]
                    extra += ["--set", f"contact.{pair}.penalty={factor * value:.6g}"]
                if not a.no_run:
                    ok = run(binary, scenario, out, extra, steps)
                    print(f" x{factor:g}{'' if ok else ' (failed)'}", end="", flush=True)
                log = (work / name / f"penalty_x{factor:g}.log")
                if (out / "summary.json").exists():
                    s, rows = load(out)
                    sweep.append((factor, eps, figures(s, rows), None))
                else:
                    sweep.append((factor, eps, None, log.read_text().strip().splitlines()[-1] if log.exists() else ""))
        print()
        figure = figures_dir / f"comparison_{name}.png"
        if series:
            plot(name, title, series, figure)
        # The page's section.
        steps_run = results["paper"][0]["steps"] if "paper" in results else "?"
        out_lines.append(f"## {title}\n")
        out_lines.append(f"`{scenario}`, {steps_run} steps.\n")
        any_run = next(iter(results.values()))[0] if results else {"drift": {}}
        cons = ", ".join(k for k in any_run["drift"] if k != "E") or "none"
        out_lines.append(f"Components of L and J the scenario conserves (summary.json's `drift`): {cons}.\n")
        out_lines.append("| method | E drift | L drift | J drift | slave behind [m] | master behind [m] | "
                         "largest \\|active gap\\| [m] | Newton / step | Krylov / solve | equations mean / max | "
                         "failed steps | wall [s] |")
        out_lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for variant, label, _ in VARIANTS:
            if variant not in results:
                out_lines.append(f"| {label} | failed | | | | | | | | | | |")
                continue
            f = figures(*results[variant])
            eq = f"{f['equations'][0]:.0f} / {f['equations'][1]:.0f}"
            out_lines.append(
                f"| {label} | {fmt(f['E'])} | {fmt(f['L'])} | {fmt(f['J'])} | {fmt(f['slave'])} | "
                f"{fmt(f['master'])} | {fmt(f['gap'])} | {f['newton']:.2f} | {fmt(f['krylov'])} | {eq} | "
                f"{f['failed']} | {f['wall']:.1f} |")
        released = {v: results[v][0].get("contact_released", 0.0) for v in results}
        if any(abs(x) > 0 for x in released.values()):
            out_lines.append("")
            out_lines.append("Energy a penalty let go outside its steps (`contact_released`, summed: stick "
                             "springs at release, less the potential of slaves coupled already behind their "
                             "master): " +
                             ", ".join(f"{v} {fmt(x)} J" for v, x in released.items() if x) +
                             "; E + Σ contact_released drifts by " +
                             ", ".join(f"{v} {fmt(abs(number(results[v][1][-1]['total']) + x - number(results[v][1][0]['total'])) / results[v][0]['drift_reference']['energy'])}"
                                       for v, x in released.items() if x) + ".")
        if "bodies" in facts:
            out_lines.append("")
            out_lines.append(f"1D wave theory: contact lasts {facts['duration'] * 1e3:g} ms, then "
                             + ", ".join(f"{b} moves at {v:g} m/s" for b, v in facts["exit"].items()) + ".\n")
            out_lines.append("| method | contact [ms] | " + " | ".join(f"exit v_{b} [m/s]" for b in facts["bodies"]) + " |")
            out_lines.append("|---|---|" + "---|" * len(facts["bodies"]))
            for variant, label, _ in VARIANTS:
                if variant not in results:
                    continue
                rows = results[variant][1]
                first, last = contact_window(rows)
                v = [number(rows[-1][f"L_x:{b}"]) / m for b, m in facts["bodies"].items()]
                out_lines.append(f"| {label} | {(last - first) * 1e3:.3f} | " + " | ".join(f"{x:.4f}" for x in v) + " |")
        if sweep:
            out_lines.append("")
            out_lines.append("Penalty at multiples of its automatic ε (" +
                             ", ".join(f"{k} = {v:.3g} Pa/m" for k, v in sweep[0][1].items()) + "):\n")
            out_lines.append("| ε factor | slave behind [m] | E drift | Newton / step | Krylov / solve | failed steps | wall [s] |")
            out_lines.append("|---|---|---|---|---|---|---|")
            for factor, _, f, failure in sweep:
                if f is None:
                    out_lines.append(f"| {factor:g} | failed: {failure} | | | | | |")
                else:
                    out_lines.append(f"| {factor:g} | {fmt(f['slave'])} | {fmt(f['E'])} | {f['newton']:.2f} | "
                                     f"{fmt(f['krylov'])} | {f['failed']} | {f['wall']:.1f} |")
        if series:
            out_lines.append("")
            out_lines.append(f"![{title}](figures/{figure.name})\n")
        out_lines.append("")
    header = (page.read_text().split("<!-- generated -->")[0] if page.exists() else "# Constraint methods side by side\n\n")
    page.write_text(header + "<!-- generated -->\n\n" + "\n".join(out_lines))
    print(f"wrote {page}")


if __name__ == "__main__":
    sys.exit(main())
