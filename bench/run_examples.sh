#!/usr/bin/env bash
# Runs every scenario under examples/ to its end and tabulates what each
# conserves: the drift of E and of each conserved component of L and J
# (summary.json's "drift"), the quantities it does not conserve with why
# ("not_conserved"), steps, impact splits and wall time.
#
# Usage: bash bench/run_examples.sh [--no-build]
#   --no-build  use build/release/conserve as it is (or $CONSERVE)
# Runs go to $BENCH_WORK (default out/bench/examples), without VTU output;
# the table to bench/results/examples.md. The binary is copied first, so a
# rebuild during the runs does not change it.
set -euo pipefail
cd "$(dirname "$0")/.."

build=1
case "${1:-}" in
  --no-build) build=0 ;;
  "") ;;
  -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
  *) echo "run_examples.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
esac
[ "$build" -eq 1 ] && bash scripts/build.sh release > /dev/null
work="${BENCH_WORK:-out/bench/examples}"
mkdir -p "$work" bench/results
binary="$work/conserve"
cp "${CONSERVE:-build/release/conserve}" "$binary"

runs=()
while IFS= read -r scenario; do
  name=$(echo "${scenario#examples/}" | sed 's/\.toml$//; s#/#_#g')
  echo "== $scenario"
  if "$binary" run "$scenario" -q -o "$work/$name" --set output.vtu_every=0 > "$work/$name.log" 2>&1; then
    runs+=("$scenario:$work/$name/summary.json")
  else
    echo "   failed: $(tail -1 "$work/$name.log")"
    runs+=("$scenario:")
  fi
done < <(find examples -name '*.toml' | sort)

/usr/bin/python3 - "${runs[@]}" <<'EOF'
import json, sys

lines = [
    "# Every example to its end: what it conserves",
    "",
    "Written by `bash bench/run_examples.sh` (no VTU output). Drift: the largest deviation of the quantity over the",
    "run divided by the run's scale (summary.json's `drift`; E is `total` + Σ `contact_released`, where `total`",
    "counts the work of loads, supports and rigid tools). Quantities a scenario does not conserve are listed with why.",
    "",
    "| example | steps (splits) | wall [s] | drift E | conserved components of L and J: largest drift | not conserved |",
    "|---|---|---|---|---|---|",
]
for run in sys.argv[1:]:
    scenario, path = run.split(":", 1)
    if not path:
        lines.append(f"| `{scenario}` | failed | | | | |")
        continue
    with open(path) as f:
        s = json.load(f)
    drift = s["drift"]
    others = {k: v for k, v in drift.items() if k != "E"}
    momenta = (", ".join(others) + f": {max(others.values()):.1e}") if others else "none"
    reasons = {}
    for k, why in s["not_conserved"].items():
        reasons.setdefault(why, []).append(k)
    not_conserved = "; ".join(f"{', '.join(ks)} ({why})" for why, ks in reasons.items()) or "none"
    lines.append(f"| `{scenario}` | {s['steps']} ({s['impact_splits']}) | {s['wall_seconds']:.1f} | "
                 f"{drift['E']:.1e} | {momenta} | {not_conserved} |")
with open("bench/results/examples.md", "w") as f:
    f.write("\n".join(lines) + "\n")
print("\n".join(lines))
EOF
