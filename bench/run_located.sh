#!/usr/bin/env bash
# The paper's contact scheme against impacts located in time with the
# persistent-contact velocity (issue 13), on the cases of the issue's second
# target: each case is run twice from the same file, the second time with
#   --set active_set.scheme=persistent --set active_set.locate_impacts=true
# and a markdown table of gaps, drifts, steps, contact counts and wall time
# is written.
#
# Usage: bash bench/run_located.sh [--no-build] [--cases "cube ball s61 s62"]
#                                  [--threads N]
#   --cases    which cases (default all four):
#                cube  bench/cube/febio_cube.toml (the peer benchmark)
#                ball  examples/ball/ball_on_plane.toml (§6.3)
#                s61   examples/cylinders/three_cylinders.toml (§6.1)
#                s62   examples/cylinders/two_hollow_cylinders.toml (§6.2)
#   --threads  OMP_NUM_THREADS of every run (default 1)
#   --no-build do not run scripts/build.sh; use build/release/conserve (or
#              the binary named by $CONSERVE)
#
# Runs are one at a time, without VTU output (--set output.vtu_every=0), in
# $BENCH_WORK (default out/bench/located). Table:
# bench/results/located_table.md (and .json). About 4 minutes for all four
# on one thread of this project's reference machine.
set -euo pipefail
cd "$(dirname "$0")/.."

build=1
cases="cube ball s61 s62"
threads=1
while [ $# -gt 0 ]; do
  case "$1" in
    --no-build) build=0 ;;
    --cases) cases="$2"; shift ;;
    --threads) threads="$2"; shift ;;
    -h|--help) sed -n '2,23p' "$0"; exit 0 ;;
    *) echo "run_located.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
case "$threads" in '' | *[!0-9]* | 0) echo "run_located.sh: --threads needs a positive integer, got '$threads'" >&2; exit 2 ;; esac

file_of() {
  case "$1" in
    cube) echo bench/cube/febio_cube.toml ;;
    ball) echo examples/ball/ball_on_plane.toml ;;
    s61) echo examples/cylinders/three_cylinders.toml ;;
    s62) echo examples/cylinders/two_hollow_cylinders.toml ;;
    *) echo "run_located.sh: unknown case '$1' (expected cube, ball, s61 or s62)" >&2; exit 2 ;;
  esac
}
for c in $cases; do file_of "$c" > /dev/null; done

if [ "$build" -eq 1 ]; then
  bash scripts/build.sh release
fi
bin="${CONSERVE:-build/release/conserve}"
[ -x "$bin" ] || { echo "run_located.sh: no binary at $bin (build first, or drop --no-build)" >&2; exit 1; }
work="${BENCH_WORK:-out/bench/located}"
mkdir -p "$work"
cp "$bin" "$work/conserve"

located=(--set active_set.scheme=persistent --set active_set.locate_impacts=true)
runs=()
for c in $cases; do
  file=$(file_of "$c")
  for variant in plain located; do
    out="$work/${c}_${variant}"
    extra=()
    [ "$variant" = located ] && extra=("${located[@]}")
    echo "run_located.sh: $c $variant ($file)"
    OMP_NUM_THREADS="$threads" "$work/conserve" run "$file" -q -o "$out" --set output.vtu_every=0 "${extra[@]}" \
      > "$out.log" 2>&1 || { echo "run_located.sh: $c $variant failed, see $out.log" >&2; exit 1; }
    runs+=("$c:$variant:$out/summary.json")
  done
done

mkdir -p bench/results
/usr/bin/python3 - "$threads" "${runs[@]}" <<'EOF'
import json, sys

threads, runs = sys.argv[1], sys.argv[2:]
rows = []
for run in runs:
    case, variant, path = run.split(":", 2)
    with open(path) as f:
        s = json.load(f)
    rows.append({"case": case, "variant": variant, **{k: s[k] for k in (
        "steps", "cutbacks", "impact_splits", "wall_seconds", "energy_drift", "max_active_gap", "min_active_gap",
        "max_penetration", "activations", "releases", "chatter", "loaded_releases", "pushes", "creases")}})
with open("bench/results/located_table.json", "w") as f:
    json.dump({"threads": int(threads), "runs": rows}, f, indent=1)

lines = [
    "# Paper scheme against located impacts + persistent velocity",
    "",
    f"Written by `bash bench/run_located.sh` (OMP_NUM_THREADS={threads}, one run at a time). "
    "`located` adds `--set active_set.scheme=persistent --set active_set.locate_impacts=true`. "
    "Gaps are over the active slaves at step ends; `behind` is the deepest slave behind its master at a step end.",
    "",
    "| case | variant | steps (cut back, splits) | wall [s] | ratio | E drift | largest / smallest active gap [m] "
    "| behind [m] | activations / releases / chatter / loaded | push-outs | crease pairs |",
    "|---|---|---|---|---|---|---|---|---|---|---|",
]
plain_wall = {}
for r in rows:
    if r["variant"] == "plain":
        plain_wall[r["case"]] = r["wall_seconds"]
    base = plain_wall.get(r["case"])
    ratio = f"{r['wall_seconds'] / base:.2f}" if base else "–"
    lines.append(
        f"| {r['case']} | {r['variant']} | {r['steps']} ({r['cutbacks']}, {r['impact_splits']}) "
        f"| {r['wall_seconds']:.1f} | {ratio} | {r['energy_drift']:.1e} "
        f"| {r['max_active_gap']:.2e} / {r['min_active_gap']:.2e} | {r['max_penetration']:.1e} "
        f"| {r['activations']} / {r['releases']} / {r['chatter']} / {r['loaded_releases']} "
        f"| {r['pushes']} | {r['creases']} |")
with open("bench/results/located_table.md", "w") as f:
    f.write("\n".join(lines) + "\n")
print("\n".join(lines))
EOF
