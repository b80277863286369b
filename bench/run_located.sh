#!/usr/bin/env bash
# The paper's contact scheme against impacts located in time with the
# persistent-contact velocity (issue 13), on the cases of the issue's second
# target: each case is run twice from the same file, the second time with
#   --set active_set.scheme=persistent --set active_set.locate_impacts=true
# and a markdown table of gaps, drifts, steps, contact counts and wall time
# is written.
#
# Usage: bash bench/run_located.sh [--no-build] [--cases "cube ball s61 s62"]
#                                  [--threads N] [--pairs N]
#   --cases    which cases (default all four):
#                cube  bench/cube/febio_cube.toml (the peer benchmark)
#                ball  examples/ball/ball_on_plane.toml (§6.3)
#                s61   examples/cylinders/three_cylinders.toml (§6.1)
#                s62   examples/cylinders/two_hollow_cylinders.toml (§6.2)
#   --threads  OMP_NUM_THREADS of every run (default 1)
#   --pairs    run each case's two variants N times side by side (both at
#              once, so they share the machine's state; needs 2 × threads
#              cores) and give the median ratio and its range over the N
#              pairs. On a shared VM the speed drifts by ±10 % from minute
#              to minute, more than a one-at-a-time ratio can tell apart.
#              Default: one run of each, one at a time.
#   --no-build do not run scripts/build.sh; use build/release/conserve (or
#              the binary named by $CONSERVE)
#
# Runs are without VTU output (--set output.vtu_every=0), in $BENCH_WORK
# (default out/bench/located). Table: bench/results/located_table.md (and
# .json). About 4 minutes for all four on one thread of this project's
# reference machine, one at a time; with --pairs N about N × 2.5 minutes.
set -euo pipefail
cd "$(dirname "$0")/.."

build=1
cases="cube ball s61 s62"
threads=1
pairs=0
while [ $# -gt 0 ]; do
  case "$1" in
    --cases | --threads | --pairs)
      [ $# -ge 2 ] || { echo "run_located.sh: $1 needs a value (see --help)" >&2; exit 2; } ;;
  esac
  case "$1" in
    --no-build) build=0 ;;
    --cases) cases="$2"; shift ;;
    --threads) threads="$2"; shift ;;
    --pairs)
      pairs="$2"; shift
      case "$pairs" in *[!0-9]* | 0) echo "run_located.sh: --pairs needs a positive integer, got '$pairs'" >&2; exit 2 ;; esac ;;
    -h|--help) sed -n '2,29p' "$0"; exit 0 ;;
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
run_one() {  # case variant file out
  local extra=()
  [ "$2" = located ] && extra=("${located[@]}")
  OMP_NUM_THREADS="$threads" "$work/conserve" run "$3" -q -o "$4" --set output.vtu_every=0 "${extra[@]}" \
    > "$4.log" 2>&1 || { echo "run_located.sh: $1 $2 failed, see $4.log" >&2; return 1; }
}
runs=()
for c in $cases; do
  file=$(file_of "$c")
  if [ "$pairs" -eq 0 ]; then
    for variant in plain located; do
      out="$work/${c}_${variant}"
      echo "run_located.sh: $c $variant ($file)"
      run_one "$c" "$variant" "$file" "$out" || exit 1
      runs+=("$c:$variant:0:$out/summary.json")
    done
  else
    for ((k = 1; k <= pairs; ++k)); do
      echo "run_located.sh: $c, pair $k of $pairs ($file)"
      run_one "$c" plain "$file" "$work/${c}_plain_$k" & first=$!
      run_one "$c" located "$file" "$work/${c}_located_$k" & second=$!
      # A failed run ends the script without leaving its partner running.
      wait "$first" || { kill "$second" 2> /dev/null; exit 1; }
      wait "$second" || exit 1
      for variant in plain located; do runs+=("$c:$variant:$k:$work/${c}_${variant}_$k/summary.json"); done
    done
  fi
done

mkdir -p bench/results
/usr/bin/python3 - "$threads" "$pairs" "${runs[@]}" <<'EOF'
import json, statistics, sys

threads, pairs, runs = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
keys = ("steps", "cutbacks", "impact_splits", "wall_seconds", "max_active_gap", "min_active_gap",
        "max_penetration", "activations", "releases", "chatter", "loaded_releases", "pushes", "creases")
every = []
for run in runs:
    case, variant, pair, path = run.split(":", 3)
    with open(path) as f:
        s = json.load(f)
    every.append({"case": case, "variant": variant, "energy_drift": s["drift"]["E"], **{k: s[k] for k in keys}})
# One row per case and variant: the figures of its last run (the work does
# not depend on the machine: every run of a variant gives the same), the
# median of its walls, and the median and range of the pairs' ratios.
rows = {}
for r in every:
    row = rows.setdefault((r["case"], r["variant"]), {"walls": []})
    row.update(r)
    row["walls"].append(r["wall_seconds"])
for row in rows.values():
    row["wall_seconds"] = statistics.median(row["walls"])
    base = rows.get((row["case"], "plain"))
    row["ratios"] = [w / b for w, b in zip(row["walls"], base["walls"])] if base and row is not base else []
with open("bench/results/located_table.json", "w") as f:
    json.dump({"threads": int(threads), "pairs": pairs, "runs": list(rows.values())}, f, indent=1)

how = (f"each case's two variants side by side, {pairs} pairs: wall is the median, ratio the median of the "
       "pairs' ratios with their range" if pairs else "one run at a time")
lines = [
    "# Paper scheme against located impacts + persistent velocity",
    "",
    f"Written by `bash bench/run_located.sh` (OMP_NUM_THREADS={threads}, {how}). "
    "`located` adds `--set active_set.scheme=persistent --set active_set.locate_impacts=true`. "
    "Gaps are over the active slaves at step ends; `behind` is the deepest slave behind its master at a step end.",
    "",
    "| case | variant | steps (cut back, splits) | wall [s] | ratio | E drift | largest / smallest active gap [m] "
    "| behind [m] | activations / releases / chatter / loaded | push-outs | crease pairs |",
    "|---|---|---|---|---|---|---|---|---|---|---|",
]
for r in rows.values():
    ratios = r["ratios"]
    ratio = f"{statistics.median(ratios):.2f}" if ratios else ("1.00" if r["variant"] == "plain" else "–")
    if len(ratios) > 1:
        ratio += f" ({min(ratios):.2f}–{max(ratios):.2f})"
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
