#!/usr/bin/env bash
# General contact's search cost against the scene's size: N balls poured
# into a box (scripts/make_pour.py) for N in --counts, each run for --steps
# steps; per run the contact search's seconds per step (broad and narrow
# phase, summary.json's contact_search) over the scene's contact facets,
# with the set-up time and peak memory. Writes
# bench/results/general_contact.md.
#
# Usage: bash bench/run_general.sh [--dim 2|3] [--counts "25 50 100 200"]
#                                  [--steps N] [--before BIN] [--no-build]
#   --before BIN   also run another conserve binary on the same scenes
#                  (its search seconds per step in a second column)
set -euo pipefail
cd "$(dirname "$0")/.."
dim=2
counts="25 50 100 200"
steps=30
before=""
build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --dim) dim="$2"; shift 2 ;;
    --counts) counts="$2"; shift 2 ;;
    --steps) steps="$2"; shift 2 ;;
    --before) before="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) echo "run_general.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ "$build" = 1 ] && bash scripts/build.sh >/dev/null
conserve="${CONSERVE:-build/release/conserve}"
work="${BENCH_WORK:-out/bench/general}"
mkdir -p "$work" bench/results
rows="$work/rows.txt"
: > "$rows"
for n in $counts; do
  scene="$work/pour${dim}d_$n.toml"
  python3 scripts/make_pour.py --dim "$dim" --count "$n" -o "$scene"
  facets=$("$conserve" check "$scene" --pairs | python3 -c '
import re, sys
seen = {}
for line in sys.stdin:
    m = re.match(r"\s+\S+ on (\S+) \(\d+ slave nodes, (\d+) master facets\)", line)
    if m: seen[m.group(1)] = int(m.group(2))
print(sum(seen.values()))')
  for side in after before; do
    bin="$conserve"
    if [ "$side" = before ]; then [ -n "$before" ] || continue; bin="$before"; fi
    out="$work/$side-$dim-$n"
    /usr/bin/time -f "%e %M" -o "$out.mem" env OMP_NUM_THREADS=1 "$bin" run "$scene" -q -o "$out" \
      --set output.vtu_every=0 --steps "$steps" > "$out.log" 2>&1
    echo "$side $n $facets $out $(cat "$out.mem")" >> "$rows"
  done
done
python3 - "$rows" "$dim" "$steps" "$before" > bench/results/general_contact.md <<'EOF'
import json, sys
rows, dim, steps, before = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
runs = {}
for line in open(rows):
    side, n, facets, out, elapsed, mem = line.split()
    j = json.load(open(out + "/summary.json"))
    s = j["seconds"]
    solve = sum(s[k] for k in ("assembly", "elimination", "linear_setup", "linear_solve", "contact_search"))
    runs.setdefault(int(n), {})[side] = dict(facets=int(facets), steps=j["steps"], search=s["contact_search"],
                                             wall=j["wall_seconds"], elapsed=float(elapsed), solve=solve, mem=int(mem) / 1024,
                                             drift=j["drift"].get("E"), pen=j.get("max_penetration"))
print(f"# General contact: search cost against the scene ({dim}D, {steps} steps)\n")
print(f"`bash bench/run_general.sh --dim {dim}`: N balls poured into a box (scripts/make_pour.py), one thread.")
print("Search: summary.json's contact_search (broad and narrow phase) per step; per facet: that over the")
print("scene's contact facets. Steps' time: assembly, solves and search. Set-up: the run's wall time before")
print("and after its steps (meshing, contact pairs and their trees).")
if before:
    print(f"Before: the search per step of `{before}` on the same scenes.")
print()
head = "| balls | contact facets | search per step [ms] | per facet [µs] | steps' time [s] | set-up [s] | peak memory [MB] | E drift | deepest node behind [m] |"
if any("before" in r for r in runs.values()):
    head = head.replace("| per facet", "| before [ms] | per facet")
print(head)
print("|" + "---|" * (head.count("|") - 1))
for n in sorted(runs):
    a = runs[n]["after"]
    per_step = 1e3 * a["search"] / a["steps"]
    cells = [str(n), str(a["facets"]), f"{per_step:.2f}"]
    if "before" in runs[n]:
        b = runs[n]["before"]
        cells.append(f"{1e3 * b['search'] / b['steps']:.2f}")
    elif "before" in head:
        cells.append("")
    cells += [f"{1e6 * a['search'] / a['steps'] / a['facets']:.2f}", f"{a['solve']:.1f}",
              f"{a['elapsed'] - a['wall']:.1f}", f"{a['mem']:.0f}", f"{a['drift']:.1e}", f"{a['pen']:.1e}"]
    print("| " + " | ".join(cells) + " |")
EOF
cat bench/results/general_contact.md
