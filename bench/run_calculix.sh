#!/usr/bin/env bash
# The peer cube (bench/cube/README.md) in CalculiX and in conserve, one
# after the other on this machine, each with its own defaults and one
# thread: CalculiX's deck from bench/calculix/cube_to_ccx.py (C3D4, SVK
# under NLGEOM, node-to-surface penalty contact on a fixed slab, HHT
# alpha = -0.05 with automatic increments), conserve's
# bench/cube/febio_cube.toml as it is, to the time ccx reached. Writes
# bench/results/calculix_cube.md: wall and CPU time, iterations, energy
# error, penetration, contact times.
#
#   bash bench/run_calculix.sh [--reuse] [END]   # END: simulated time, default 0.6 s
#
# ccx is Debian's calculix-ccx (scripts/install-deps.sh). In contact its
# increments fall to 2e-5 to 4.5e-5 s: the first bounce (END = 0.15) takes
# it about 6 minutes of CPU here; with its defaults it does not get past
# t = 0.4635 s, where its increments stay at 6e-11 s (stop it by hand,
# then --reuse). --reuse
# tabulates a ccx run already in BENCH_WORK (stopped by hand, say) instead
# of starting one. BENCH_WORK=DIR keeps the runs' files; CONSERVE=PATH
# picks the binary.
set -euo pipefail
cd "$(dirname "$0")/.."
reuse=0
if [ "${1:-}" = "--reuse" ]; then reuse=1; shift; fi
end=${1:-0.6}
conserve=${CONSERVE:-build/release/conserve}
command -v ccx > /dev/null || { echo "run_calculix: no ccx (Debian's calculix-ccx: bash scripts/install-deps.sh)" >&2; exit 1; }
[ -x "$conserve" ] || { echo "run_calculix: no $conserve (build first: bash scripts/build.sh)" >&2; exit 1; }
work=${BENCH_WORK:-$(mktemp -d)}
mkdir -p "$work"
export OMP_NUM_THREADS=1 CCX_NPROC_EQUATION_SOLVER=1

if [ "$reuse" = 0 ]; then
  /usr/bin/python3 bench/calculix/cube_to_ccx.py bench/cube/febio_cube.msh "$work/cube.inp" --end "$end"
  echo "run_calculix: ccx on the cube to t = $end s (in $work)"
  # ccx may stop itself before END ("solution seems to diverge"): its
  # status is kept, and the results say how far it got.
  cut -d' ' -f1 /proc/loadavg > "$work/ccx_load.txt"
  ( cd "$work" && /usr/bin/time -f "%e %U" -o ccx_time.txt ccx -i cube > ccx.log 2>&1 ) || true
fi
[ -s "$work/cube.sta" ] || { echo "run_calculix: no ccx run in $work" >&2; exit 1; }
/usr/bin/python3 bench/calculix/ccx_results.py "$work/cube" > "$work/ccx.json"
[ -s "$work/ccx_time.txt" ] || { echo "run_calculix: no ccx_time.txt in $work (ccx's run not timed)" >&2; exit 1; }
asked=$end
end=$(/usr/bin/python3 -c "import json,sys; print(min(float(sys.argv[2]), json.load(open(sys.argv[1]))['reached']))" \
  "$work/ccx.json" "$end")

echo "run_calculix: conserve on the cube to t = $end s"
rm -rf "$work/conserve"
cut -d' ' -f1 /proc/loadavg > "$work/conserve_load.txt"
/usr/bin/time -f "%e %U" -o "$work/conserve_time.txt" "$conserve" run bench/cube/febio_cube.toml -o "$work/conserve" -q \
  --set output.vtu_every=0 --set time.end="$end"

/usr/bin/python3 - "$work" "$end" "$({ ccx -v 2> /dev/null || true; } | grep -o 'Version [0-9.]*' | head -1)" \
  "$(git rev-parse --short HEAD)" "$asked" "$reuse" > bench/results/calculix_cube.md <<'PY'
import csv
import json
import os
import sys

work, end, version, commit, asked, reuse = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6]
ccx = json.load(open(f"{work}/ccx.json"))
ccx_wall, ccx_cpu = map(float, open(f"{work}/ccx_time.txt").read().split()[-2:])
wall, cpu = map(float, open(f"{work}/conserve_time.txt").read().split()[-2:])
rows = list(csv.DictReader(open(f"{work}/conserve/history.csv")))
e0 = float(rows[0]["total"])
errors = [(float(r["total"]) - e0) / e0 for r in rows]
steps = len(rows) - 1
newton = sum(int(r["newton_iterations"]) for r in rows[1:])
penetration = max(float(r["slave_penetration"]) for r in rows)
contact, start = [], None
for r in rows[1:]:
    active, t = int(r["active_contacts"]) > 0, float(r["time"])
    if active and start is None:
        start = t
    if not active and start is not None:
        contact.append([start, t])
        start = None
if start is not None:
    contact.append([start, None])
out = [r for r in rows if int(r["active_contacts"]) == 0]
flight_time, flight_error = float(out[-1]["time"]), (float(out[-1]["total"]) - e0) / e0


def intervals(spans):
    text = ", ".join(f"{a:.3f}–{b:.3f}" if b is not None else f"{a:.3f}–" for a, b in spans)
    return text + " s" if text else "none"


def load(name):
    path = f"{work}/{name}_load.txt"
    return open(path).read().strip() if os.path.exists(path) else "not recorded"


def rel(x):
    return "—" if x is None else f"{x:+.2e}"


print(f"# The peer cube: CalculiX against conserve, t = 0 … {end:g} s\n")
command = f"bash bench/run_calculix.sh {asked}" + (" (its CalculiX run tabulated with --reuse)" if reuse == "1" else "")
print(f"`{command}` at {commit}, CalculiX {version}: one thread each, one run after the other on the same")
print("machine, each code with its own defaults (bench/run_calculix.sh says which); conserve to the time")
print(f"CalculiX reached. Load average (1 min) at the start: CalculiX {load('ccx')}, conserve {load('conserve')}.\n")
print("| code | reached | wall (CPU) | increments | Newton iterations | energy error / E₀, largest (at the end) | out of contact | deepest node below the plane | contact |")
print("|---|---|---|---|---|---|---|---|---|")
print(f"| CalculiX, node-to-surface penalty, HHT α = −0.05, automatic increments | {ccx['reached']:.4g} s | "
      f"{ccx_wall:.0f} s ({ccx_cpu:.0f} s) | {ccx['increments']} | {ccx['iterations']} "
      f"({ccx['iterations'] / max(ccx['increments'], 1):.2f} / increment) | {rel(ccx['error_max'])} ({rel(ccx['error_end'])}) | "
      f"{rel(ccx['error_flight'])} at {ccx['flight_time']:.3f} s | {1e3 * ccx['penetration']:.3g} mm | {intervals(ccx['contact'])} |")
print(f"| conserve, `bench/cube/febio_cube.toml` | {float(rows[-1]['time']):.4g} s | {wall:.0f} s ({cpu:.0f} s) | {steps} | "
      f"{newton} ({newton / max(steps, 1):.2f} / step) | {max(errors, key=abs):+.2e} ({errors[-1]:+.2e}) | "
      f"{flight_error:+.2e} at {flight_time:.3f} s | "
      f"{1e3 * penetration:.3g} mm | {intervals(contact)} |")
print(f"\nWall-time ratio CalculiX / conserve: {ccx_wall / wall:.1f} (CPU {ccx_cpu / cpu:.1f}).")
print("CalculiX's energy: its kinetic and strain energies (`*EL PRINT` ELKE, ELSE) plus gravity's potential from")
print("the nodes' heights with the lumped masses; the penalty springs' energy is left out, as in the FEBio")
print("figures of bench/cube/README.md, so the error in contact includes it. conserve's: history.csv `total`.")
print("A CalculiX run that stopped before the end time is reported to where it got; its last increments were")
print(", ".join(f"{x:.3g}" for x in ccx["last_increments"]) + " s.")
PY
cat bench/results/calculix_cube.md
