#!/usr/bin/env bash
# The assembly's threads on a quiet and on a loaded machine (issue 44): the
# peer cube and the §6.3 ball, each run with the default thread count
# ([solver] threads = 0: the cores other processes leave free, re-measured
# every second), with OMP_NUM_THREADS=1 and with OMP_NUM_THREADS=2, while
# 0, 1 and 2 busy processes (shell loops) share the machine. The three
# variants of a case run one after another, N times in turn, and each
# ratio is the median over those N rounds (with its range): the machine's
# speed drifts between rounds, not within one.
#
# Usage: bash bench/run_threads.sh [--no-build] [--rounds N] [--cases "cube ball"]
#   --rounds   rounds per case and load (default 3)
#   --cases    cube: bench/cube/febio_cube.toml, 300 steps;
#              ball: examples/ball/ball_on_plane.toml, 800 steps (its first impact)
#   --no-build use build/release/conserve (or $CONSERVE) as it is
# Writes bench/results/threads.md. About 13 minutes on the project's 2-core
# machine with the defaults.
set -euo pipefail
cd "$(dirname "$0")/.."

build=1
rounds=3
cases="cube ball"
while [ $# -gt 0 ]; do
  case "$1" in
    --no-build) build=0 ;;
    --rounds) rounds="${2:?--rounds needs a value}"; shift ;;
    --cases) cases="${2:?--cases needs a value}"; shift ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    *) echo "run_threads.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
case "$rounds" in '' | *[!0-9]* | 0) echo "run_threads.sh: --rounds needs a positive integer" >&2; exit 2 ;; esac
[ "$build" = 1 ] && bash scripts/build.sh release >/dev/null
conserve="${CONSERVE:-build/release/conserve}"
work="${BENCH_WORK:-out/bench/threads}"
mkdir -p "$work"
times="$work/times.csv"
echo "case,busy,round,variant,seconds" > "$times"

busy_pids=()
stop_busy() { for p in "${busy_pids[@]}"; do kill "$p" 2>/dev/null || true; done; busy_pids=(); }
trap stop_busy EXIT

run_one() {  # case file steps variant → seconds
  local file="$1" steps="$2" variant="$3" start end
  local -a env_args=()
  case "$variant" in
    one) env_args=(OMP_NUM_THREADS=1) ;;
    two) env_args=(OMP_NUM_THREADS=2) ;;
  esac
  start=$EPOCHREALTIME
  env -u OMP_NUM_THREADS "${env_args[@]}" "$conserve" run "$file" -q -o "$work/out_$variant" --steps "$steps" \
    --set output.vtu_every=0 >/dev/null
  end=$EPOCHREALTIME
  echo "$start $end" | awk '{printf "%.3f", $2 - $1}'
}

for c in $cases; do
  case "$c" in
    cube) file=bench/cube/febio_cube.toml; steps=300 ;;
    ball) file=examples/ball/ball_on_plane.toml; steps=800 ;;
    *) echo "run_threads.sh: unknown case '$c'" >&2; exit 2 ;;
  esac
  for busy in 0 1 2; do
    for ((i = 0; i < busy; i++)); do sh -c 'while :; do :; done' & busy_pids+=($!); done
    sleep 1
    for ((r = 1; r <= rounds; r++)); do
      for variant in default one two; do
        echo "$c,$busy,$r,$variant,$(run_one "$file" "$steps" "$variant")" >> "$times"
      done
    done
    stop_busy
    sleep 1
  done
done

/usr/bin/python3 - "$times" bench/results/threads.md "$rounds" <<'PY'
import csv, statistics, sys, collections
rows = list(csv.DictReader(open(sys.argv[1])))
t = collections.defaultdict(dict)
for r in rows:
    t[(r["case"], int(r["busy"]), int(r["round"]))][r["variant"]] = float(r["seconds"])
out = ["# Assembly threads on a quiet and a loaded machine", "",
       "`bash bench/run_threads.sh` (%s rounds per line; wall seconds, medians over the rounds; ratios to one "
       "thread per round, median [range]). `default` is `[solver] threads = 0`." % sys.argv[3], "",
       "| case | busy processes | default [s] | 1 thread [s] | 2 threads [s] | default / 1 thread | 2 threads / 1 thread |",
       "|---|---|---|---|---|---|---|"]
for case in dict.fromkeys(r["case"] for r in rows):
    for busy in (0, 1, 2):
        rs = [v for k, v in sorted(t.items()) if k[0] == case and k[1] == busy and len(v) == 3]
        if not rs: continue
        med = lambda key: statistics.median(r[key] for r in rs)
        ratio = lambda key: [r[key] / r["one"] for r in rs]
        fmt = lambda xs: "%.2f [%.2f, %.2f]" % (statistics.median(xs), min(xs), max(xs))
        out.append("| %s | %d | %.2f | %.2f | %.2f | %s | %s |" % (case, busy, med("default"), med("one"), med("two"),
                                                                fmt(ratio("default")), fmt(ratio("two"))))
open(sys.argv[2], "w").write("\n".join(out) + "\n")
print("\n".join(out))
PY
