#!/bin/bash
# The peer cube, the paper's ball (§6.3, full stick) and the 2D bars (their
# slaves on rank 0, every master facet on rank 1) on one process and on N
# MPI ranks (mpiexec -n N): wall time, Newton and Krylov iterations, the
# drifts, and how far the N-rank history parts from the one-process one
# (scripts/compare_histories.py: E, L, J, gaps; active contacts step by
# step), with the ball's controls (ranges on N ranks; one process 1 ulp
# lower). Writes bench/results/ranks.md.
#
#   bash bench/run_ranks.sh [--ranks 2] [--no-build]
set -euo pipefail
cd "$(dirname "$0")/.."
ranks=2
build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --ranks) ranks="$2"; shift ;;
    --no-build) build=0 ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) echo "run_ranks.sh: unknown option $1 (--help)" >&2; exit 1 ;;
  esac
  shift
done
[ "$build" -eq 1 ] && bash scripts/build.sh release
bin="${CONSERVE:-build/release/conserve}"
[ -x "$bin" ] || { echo "run_ranks.sh: no executable $bin (build first)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work="${BENCH_WORK:-out/bench/ranks}"
mkdir -p "$work"
scenarios=(bench/cube/febio_cube.toml examples/ball/ball_on_plane.toml examples/validation/bars_2d.toml)
for s in "${scenarios[@]}"; do
  name=$(basename "$s" .toml)
  echo "== $name, one process $(date -u +%H:%M:%S) UTC"
  rm -rf "$work/${name}_1"
  "$bin" run "$s" -o "$work/${name}_1" -q --set output.vtu_every=0 > "$work/${name}_1.log"
  echo "== $name, $ranks ranks"
  rm -rf "$work/${name}_$ranks"
  mpiexec -q --oversubscribe -n "$ranks" "$bin" run "$s" -o "$work/${name}_$ranks" -q --set output.vtu_every=0 \
    > "$work/${name}_$ranks.log"
done
# The ball's controls: on N ranks with the meshes' numbering cut into
# ranges, and on one process from 1 ulp lower (z = 1 - 1.1e-16 m): how far
# a change of round-off alone moves the trajectory.
ball=examples/ball/ball_on_plane.toml
echo "== ball_on_plane, $ranks ranks, partition = ranges"
rm -rf "$work/ball_ranges_$ranks" "$work/ball_ulp_1"
mpiexec -q --oversubscribe -n "$ranks" "$bin" run "$ball" -o "$work/ball_ranges_$ranks" -q --set output.vtu_every=0 \
  --set solver.partition=ranges > "$work/ball_ranges_$ranks.log"
echo "== ball_on_plane, one process, 1 ulp lower"
"$bin" run "$ball" -o "$work/ball_ulp_1" -q --set output.vtu_every=0 \
  --set 'body.ball.translate=[0.0,0.0,0.9999999999999999]' > "$work/ball_ulp_1.log"
/usr/bin/python3 - "$work" "$ranks" "${scenarios[@]}" <<'PY'
import datetime, json, os, sys
sys.path.insert(0, "scripts")
from compare_histories import compare
work, ranks, scenarios = sys.argv[1], sys.argv[2], sys.argv[3:]
out = [f"# One process against {ranks} MPI ranks", "",
       f"`bash bench/run_ranks.sh --ranks {ranks}`; {os.cpu_count()} cores, {datetime.date.today().isoformat()}. "
       "Wall time is summary.json's `wall_seconds` of one run each (the machine varies up to 2×). "
       f"\"parts by\": the largest difference of the {ranks}-rank history from the one-process one over the run, "
       "E, L, J on the drifts' scales, gaps on their largest value (scripts/compare_histories.py).", "",
       "| scenario | ranks | wall [s] | Newton it / step | Krylov it / solve | linear solver | drift E / L / J | parts by E / L / J / gap | active contacts step by step |",
       "|---|---|---|---|---|---|---|---|---|"]
def drift(s, q):
    d = s["drift"]
    keys = [k for k in d if k == q or k.startswith(q + "_")]
    return f"{max(d[k] for k in keys):.1e}" if keys else "–"
for path in scenarios:
    name = os.path.basename(path)[:-5]
    one, many = f"{work}/{name}_1", f"{work}/{name}_{ranks}"
    d = compare(one, many)
    for run, label in ((one, "1"), (many, ranks)):
        s = json.load(open(f"{run}/summary.json"))
        solves = max(s["linear_solves"], 1)
        parts = (f"{d['E']:.1e} / {d['L']:.1e} / {d['J']:.1e} / {d['gap']:.1e} ({d['gap_m']:.1e} m, "
                 f"{d['gap_of_size']:.1e} of the model's size)" if run == many else "")
        same = ("same" if d["active_contacts_equal"] else "differ") if run == many else ""
        out.append(f"| {name} | {label} | {s['wall_seconds']:.1f} | {s['mean_newton_iterations']:.2f} | "
                   f"{s['linear_iterations'] / solves:.1f} | {s['linear_solver']} | "
                   f"{drift(s, 'E')} / {drift(s, 'L')} / {drift(s, 'J')} | {parts} | {same} |")
for run, label in ((f"{work}/ball_ranges_{ranks}", f"{ranks}, `partition = \"ranges\"`"),
                   (f"{work}/ball_ulp_1", "1, the ball 1 ulp lower")):
    one = f"{work}/ball_on_plane_1"
    d, s = compare(one, run), json.load(open(f"{run}/summary.json"))
    solves = max(s["linear_solves"], 1)
    out.append(f"| ball_on_plane | {label} | {s['wall_seconds']:.1f} | {s['mean_newton_iterations']:.2f} | "
               f"{s['linear_iterations'] / solves:.1f} | {s['linear_solver']} | "
               f"{drift(s, 'E')} / {drift(s, 'L')} / {drift(s, 'J')} | "
               f"{d['E']:.1e} / {d['L']:.1e} / {d['J']:.1e} / {d['gap']:.1e} ({d['gap_m']:.1e} m, "
               f"{d['gap_of_size']:.1e} of the model's size) | {'same' if d['active_contacts_equal'] else 'differ'} |")
out += ["", "On N ranks a body the ranks share is numbered by graph parts (`[solver] partition = \"graph\"`, "
        "the default), which changes the order of every node's sums; the ball's last two rows are its controls: "
        "the meshes' numbering cut into ranges, and one process started 1 ulp (1.1e-16 m) lower, a change of "
        "round-off alone."]
open("bench/results/ranks.md", "w").write("\n".join(out) + "\n")
print("\n".join(out))
PY
