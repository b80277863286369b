#!/usr/bin/env bash
# One pass against two for a rigid tool: examples/punch/punch_plate.toml
# to 0.05 s with the plate meshed at --sizes and the punch moved so that
# its corners are mid-facet, in one and two passes; the punch force
# (history.csv R_y:punch) against a one-pass reference at --reference,
# over t = 0.015 … 0.05 s, with each run's deepest node behind and E
# drift. Writes bench/results/punch_passes.md.
#
# Usage: bash bench/run_punch_passes.sh [--sizes "0.02 0.01 0.005"]
#                                       [--reference 0.00125] [--no-build]
set -euo pipefail
cd "$(dirname "$0")/.."
sizes="0.02 0.01 0.005"
reference=0.00125
build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --sizes) sizes="$2"; shift 2 ;;
    --reference) reference="$2"; shift 2 ;;
    --no-build) build=0; shift ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "run_punch_passes.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ "$build" = 1 ] && bash scripts/build.sh >/dev/null
conserve="${CONSERVE:-build/release/conserve}"
work="${BENCH_WORK:-out/bench/punch}"
mkdir -p "$work" bench/results
# scene SIZE PASSES SHIFT: the punch example with these, to 0.05 s.
scene() {
  local out="$work/punch_$1_$2.toml"
  sed -e "s/^size = 0.01\$/size = $1/" -e 's/^end = 0.08/end = 0.05/' \
      -e "s/translate = \[0.0, 0.076\]/translate = [$3, 0.076]/" examples/punch/punch_plate.toml > "$out"
  [ "$2" = 2 ] && sed -i 's/^kind = "frictionless"/kind = "frictionless"\npasses = 2/' "$out"
  echo "$out"
}
run() {  # run SIZE PASSES SHIFT
  local file dir
  file=$(scene "$1" "$2" "$3")
  dir="$work/out_$1_$2"
  "$conserve" run "$file" -o "$dir" -q --set output.vtu_every=0 > "$dir.log" 2>&1
  echo "$dir"
}
ref=$(run "$reference" 1 0.0)
rows=()
for h in $sizes; do
  # the punch's corners (x = ±0.05 m; the plate's nodes at −0.2 m + k h) mid-facet
  shift_x=$(python3 -c "import math; f = 0.25 / $h; f -= math.floor(f + 1e-9); print(round(((0.5 - f) % 1.0) * $h, 12))")
  rows+=("$h $(run "$h" 1 "$shift_x") $(run "$h" 2 "$shift_x")")
done
python3 - "$ref" "$reference" "${rows[@]}" > bench/results/punch_passes.md <<'PY'
import bisect, csv, json, sys
ref_dir, reference = sys.argv[1], sys.argv[2]
def load(d):
    r = list(csv.DictReader(open(d + "/history.csv")))
    return [float(x["time"]) for x in r], [float(x["R_y:punch"]) for x in r]
def summary(d):
    return json.load(open(d + "/summary.json"))
rt, rf = load(ref_dir)
times = [0.015 + 0.005 * k for k in range(8)]
def errors(d):
    t, f = load(d)
    out = []
    for s in times:
        i = min(bisect.bisect_left(t, s - 1e-12), len(t) - 1)
        j = min(bisect.bisect_left(rt, s - 1e-12), len(rt) - 1)
        out.append((f[i] - rf[j]) / rf[j] * 100)
    return min(out), max(out)
def deepest(d):
    s = summary(d)
    return max(s["slave_penetration"], s["master_penetration"])
def drift(d):
    return summary(d)["drift"]["E"]
print(f"# A rigid punch in one and two passes\n")
print(f"`bash bench/run_punch_passes.sh`: examples/punch/punch_plate.toml to 0.05 s, the plate's facets as listed, "
      f"the punch moved so that its corners are mid-facet; punch force (R_y:punch) against a {float(reference)*1e3:g} mm one-pass "
      f"reference over t = 0.015 … 0.05 s.\n")
print("| plate facets | deepest node behind, one pass / two | force, one pass | force, two passes | E drift, two passes |")
print("|---|---|---|---|---|")
for row in sys.argv[3:]:
    h, one, two = row.split()
    a, b = errors(one), errors(two)
    print(f"| {float(h)*1e3:g} mm | {deepest(one):.1e} m / {deepest(two):.1e} m | {a[0]:+.1f} … {a[1]:+.1f} % | "
          f"{b[0]:+.1f} … {b[1]:+.1f} % | {drift(two):.1e} |")
PY
cat bench/results/punch_passes.md
