#!/usr/bin/env bash
# Benchmarks conserve on the paper's three examples and on a mesh-size sweep
# of the §6.3 ball, and writes a markdown table of the costs.
#
# Usage: bash bench/run_paper.sh [--quick] [--no-build] [--no-plots]
#                                [--sizes "10000 30000 100000 200000"]
#                                [--sweep-steps N] [--mem-limit-gb G] [--sweep-only]
#   --sweep-only  keep the work folder's paper runs and redo only the sweep
#
#   (default)   the three paper examples in full (examples/cylinders/
#               three_cylinders.toml 600 steps, two_hollow_cylinders.toml
#               1000 steps, examples/ball/ball_on_plane.toml 2500 steps),
#               then the ball with its mesh size set for about 10k, 30k,
#               100k and 200k unknowns, 2 steps each from the start (free
#               flight, so no contact: it measures the elastodynamics and
#               the linear solver), without VTU output.
#               Table: bench/results/paper_table.md
#   --quick     200 steps of the cylinder examples, 400 of the ball (its
#               first impact), a 10k/100k sweep: tests the script (minutes).
#               Table: bench/results/paper_table_quick.md
#   --no-build  do not run scripts/build.sh; use build/release/conserve
#               as it is (or the binary named by $CONSERVE)
#   --no-plots  skip the figures (plot_history.py, render_snapshots.py)
#   --sizes     target numbers of unknowns of the sweep (UMFPACK fails from
#               about 200k on, and 1M would need far more memory than a
#               24 GB machine has: see bench/README.md)
#   --sweep-steps  steps of each sweep run (default 2)
#   --mem-limit-gb address-space limit of each run (default: 80% of RAM);
#               a run over it fails and is reported as such
#
# Every run is timed by /usr/bin/time -v (peak memory). Runs go to
# $BENCH_WORK (default out/bench/full or out/bench/quick): generated
# scenarios, the run folders, logs. The binary is copied there first, so a
# concurrent rebuild does not change it in the middle of the benchmark.
set -euo pipefail
cd "$(dirname "$0")/.."

quick=0
build=1
plots=1
sizes=""
sweep_steps=2
mem_gb=""
sweep_only=0
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --no-build) build=0 ;;
    --no-plots) plots=0 ;;
    --sweep-only) sweep_only=1 ;;
    --sizes) sizes="$2"; shift ;;
    --sweep-steps) sweep_steps="$2"; shift ;;
    --mem-limit-gb) mem_gb="$2"; shift ;;
    -h|--help) sed -n '2,35p' "$0"; exit 0 ;;
    *) echo "run_paper.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

if [ "$quick" -eq 1 ]; then
  mode=quick
  paper_steps=200   # the ball: 400, to include its first impact (t ≈ 0.35 s)
  ball_steps=400
  sizes="${sizes:-10000 100000}"
  table=bench/results/paper_table_quick.md
else
  mode=full
  paper_steps=""
  ball_steps=""
  sizes="${sizes:-10000 30000 100000 200000}"
  table=bench/results/paper_table.md
fi

if [ "$build" -eq 1 ]; then
  bash scripts/build.sh release
else
  # the benchmark's own dependencies (GNU time, matplotlib) even without a build
  command -v /usr/bin/time >/dev/null 2>&1 || bash scripts/install-deps.sh
fi
bin="${CONSERVE:-build/release/conserve}"
[ -x "$bin" ] || { echo "run_paper.sh: no executable $bin (build first)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "run_paper.sh: /usr/bin/time missing (bash scripts/install-deps.sh)" >&2; exit 1; }

work="${BENCH_WORK:-out/bench/$mode}"
manifest="$work/manifest.tsv"
if [ "$sweep_only" -eq 1 ] && [ -f "$manifest" ]; then
  grep -v "	sweep	" "$manifest" > "$manifest.tmp" || true
  mv "$manifest.tmp" "$manifest"
else
  rm -rf "$work"
  mkdir -p "$work/scenarios" "$work/runs" bench/results
  : > "$manifest"
fi
cp "$bin" "$work/conserve"

if [ -z "$mem_gb" ]; then
  mem_kb=$(awk '/MemTotal/ {print int($2 * 0.8)}' /proc/meminfo)
else
  mem_kb=$(awk -v g="$mem_gb" 'BEGIN {print int(g * 1024 * 1024)}')
fi

# run NAME KIND SCENARIO STEPS(empty: all)
run() {
  local name="$1" kind="$2" scenario="$3" steps="$4"
  local dir="$work/runs/$name"
  local args=(run "$scenario" -o "$dir" -q)
  [ -n "$steps" ] && args+=(--steps "$steps")
  echo "== $name: $scenario ${steps:+(--steps $steps)} $(date -u +%H:%M:%S) UTC, load $(cut -d' ' -f1-3 /proc/loadavg)"
  local rc=0
  ( ulimit -v "$mem_kb"; /usr/bin/time -v -o "$work/runs/$name.time" \
      "$work/conserve" "${args[@]}" ) > "$work/runs/$name.log" 2>&1 || rc=$?
  tail -n 5 "$work/runs/$name.log" | sed 's/^/   /'
  printf '%s\t%s\t%s\t%s\t%s\n' "$name" "$kind" "$scenario" "${steps:-all}" "$rc" >> "$manifest"
  if [ "$rc" -eq 0 ] && [ "$plots" -eq 1 ] && [ "$kind" = paper ]; then
    /usr/bin/python3 scripts/plot_history.py "$dir/history.csv" | sed 's/^/   /' || true
    /usr/bin/python3 scripts/render_snapshots.py "$dir" --count 6 | sed 's/^/   /' || true
  fi
}

echo "run_paper.sh ($mode): binary $bin, work folder $work, memory limit $((mem_kb / 1024 / 1024)) GB per run"

# --- 1. the paper's three examples, at the examples' resolution ---------------
if [ "$sweep_only" -eq 0 ]; then
  run three_cylinders paper examples/cylinders/three_cylinders.toml "$paper_steps"
  run two_hollow_cylinders paper examples/cylinders/two_hollow_cylinders.toml "$paper_steps"
  run ball_on_plane paper examples/ball/ball_on_plane.toml "$ball_steps"
fi

# --- 2. mesh-size sweep of the ball -------------------------------------------
# The ball's `size` for N unknowns, fitted to `conserve check` counts of this
# shell (8379 at 0.046, 64305 at 0.0215, 102291 at 0.0182): N ≈ 102291 ·
# (0.0182 / size)^2.67 (Gmsh refines towards the curved surfaces, so the
# count grows slower than size^-3).
for n in $sizes; do
  size=$(awk -v n="$n" 'BEGIN {printf "%.5f", 0.0182 * (102291 / n) ^ (1 / 2.67)}')
  scen="$work/scenarios/ball_${n}.toml"
  # Released with a 1 % stretch, so that every step of the sweep is a
  # vibrating one (an unstressed ball in flight converges at the predictor).
  sed -e "0,/^size = .*/s//size = $size/" -e 's/^vtu_every = .*/vtu_every = 0/' \
      -e '0,/^velocity = .*/s//&\ninitial_deformation = [[1.01, 0.0, 0.0], [0.0, 0.995, 0.0], [0.0, 0.0, 0.995]]/' \
      -e "s|^directory = .*|directory = \"$work/runs/ball_$n\"|" examples/ball/ball_on_plane.toml > "$scen"
  grep -q "^size = $size\$" "$scen" || { echo "run_paper.sh: could not set the ball's size in $scen" >&2; exit 1; }
  run "ball_${n}" sweep "$scen" "$sweep_steps"
done

/usr/bin/python3 bench/make_table.py "$work" --mode "$mode" --out "$table"
echo "table: $table"
