#!/bin/bash
# Large models read from binary .msh files: the §6.3 ball's shell meshed
# once by Gmsh (bench/large/shell.geo, Delaunay, one thread; cached) at
# each mesh size, then read by conserve (renumbered: [body.mesh] reorder)
# and run for a few vibrating steps (released
# with a 1 % stretch, before any contact). Per size: Gmsh's meshing time,
# conserve's set-up (summary.json setup_seconds: reading the file, the
# model, the pattern), time and GMRES iterations per Newton iteration,
# peak memory and bytes per unknown; growth exponents by least squares on
# log-log over the sizes. Writes bench/results/large_models.md.
#
#   bash bench/run_large.sh [--sizes "0.0182 0.0117 0.00774"] [--steps 3] [--no-build]
#
# The default sizes give about 0.1M, 0.35M and 1.18M unknowns; the largest
# needs about 4 GB and 10 minutes on 2 cores (most of it Gmsh, once).
set -euo pipefail
cd "$(dirname "$0")/.."
sizes="0.0182 0.0117 0.00774"
steps=3
build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --sizes) sizes="$2"; shift ;;
    --steps) steps="$2"; shift ;;
    --no-build) build=0 ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    *) echo "run_large.sh: unknown option $1 (--help)" >&2; exit 1 ;;
  esac
  shift
done
[ "$build" -eq 1 ] && bash scripts/build.sh release
bin="${CONSERVE:-build/release/conserve}"
[ -x "$bin" ] || { echo "run_large.sh: no executable $bin (build first)" >&2; exit 1; }
command -v gmsh >/dev/null || { echo "run_large.sh: gmsh missing (bash scripts/install-deps.sh)" >&2; exit 1; }
work="${BENCH_WORK:-out/bench/large}"
mkdir -p "$work"
rows=()
for h in $sizes; do
  msh="$work/shell_$h.msh"
  if [ ! -f "$msh" ]; then
    echo "== meshing h = $h"
    start=$(date +%s.%N)
    gmsh bench/large/shell.geo -setnumber h "$h" -3 -bin -format msh41 -nt 1 -o "$msh.part" > "$work/gmsh_$h.log" 2>&1
    mv "$msh.part" "$msh"
    awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {print b - a}' > "$work/gmsh_$h.seconds"
  fi
  scen="$work/ball_$h.toml"
  sed -e 's|^generator = "spherical_shell"|file = "'"$(realpath "$msh")"'"\nreorder = true|' -e '/^inner_radius/d;/^outer_radius/d' \
      -e '0,/^size = .*/{/^size = .*/d}' -e 's/^vtu_every = .*/vtu_every = 0/' \
      -e '0,/^velocity = .*/s//&\ninitial_deformation = [[1.01, 0.0, 0.0], [0.0, 0.995, 0.0], [0.0, 0.0, 0.995]]/' \
      examples/ball/ball_on_plane.toml > "$scen"
  grep -q '^file = ' "$scen" || { echo "run_large.sh: could not point $scen at $msh" >&2; exit 1; }
  echo "== run h = $h $(date -u +%H:%M:%S) UTC"
  "$bin" run "$scen" -o "$work/run_$h" --steps "$steps" -q > "$work/run_$h.log" 2>&1
  tail -n 3 "$work/run_$h.log" | sed 's/^/   /'
  rows+=("$h")
done
# The smallest size once more with the file's own numbering (no reorder).
first=${rows[0]}
sed '/^reorder = true/d' "$work/ball_$first.toml" > "$work/ball_${first}_file.toml"
"$bin" run "$work/ball_${first}_file.toml" -o "$work/run_${first}_file" --steps "$steps" -q > "$work/run_${first}_file.log" 2>&1
/usr/bin/python3 - "$work" "${rows[@]}" <<'PY'
import datetime, json, math, os, sys
work, sizes = sys.argv[1], sys.argv[2:]
rows = []
for h in sizes:
    s = json.load(open(f"{work}/run_{h}/summary.json"))
    it = s["mean_newton_iterations"] * s["steps"]
    gmsh = float(open(f"{work}/gmsh_{h}.seconds").read())
    rows.append(dict(h=h, n=s["unknowns"], gmsh=gmsh, setup=s["setup_seconds"], per_it=s["wall_seconds"] / it,
                     krylov=s["linear_iterations"] / it, mem=s["peak_memory_bytes"], bpu=s["bytes_per_unknown"],
                     e=s["drift"]["E"]))
def slope(key):
    if len(rows) < 2: return float("nan")
    x = [math.log(r["n"]) for r in rows]; y = [math.log(r[key]) for r in rows]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    return sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
out = ["# Large models read from binary .msh files (the §6.3 ball's shell)", "",
       "`bash bench/run_large.sh` (defaults). Gmsh meshes each size once (Delaunay, one thread);",
       "conserve reads the file (`reorder = true`) and runs vibrating steps before any contact.",
       f"{os.cpu_count()} cores, {datetime.date.today().isoformat()}; set-up is `summary.json` `setup_seconds`.", "",
       "| mesh size [m] | unknowns | Gmsh meshing [s] | conserve set-up [s] | s / Newton it | GMRES it / Newton it | peak [GB] | bytes / unknown | E drift |",
       "|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    out.append(f"| {r['h']} | {r['n']:,} | {r['gmsh']:.1f} | {r['setup']:.1f} | {r['per_it']:.3f} | {r['krylov']:.1f} | "
               f"{r['mem'] / 1e9:.2f} | {r['bpu']:,.0f} | {r['e']:.1e} |")
f = json.load(open(f"{work}/run_{sizes[0]}_file/summary.json"))
r0 = rows[0]
f_it = f["wall_seconds"] / (f["mean_newton_iterations"] * f["steps"])
r0_assembly = json.load(open(f"{work}/run_{r0['h']}/summary.json"))["seconds"]["assembly"]
out += ["", f"Mesh size {r0['h']} with the file's own (Gmsh's) numbering instead of `reorder = true`: "
        f"{f_it:.3f} s / Newton it ({f_it / r0['per_it']:.2f}× the reordered), "
        f"{f['linear_iterations'] / (f['mean_newton_iterations'] * f['steps']):.1f} GMRES it / Newton it, "
        f"assembly {f['seconds']['assembly']:.2f} s against {r0_assembly:.2f} s."]
out += ["", f"Growth (least squares on log-log): time per Newton iteration ∝ n^{slope('per_it'):.2f}, "
        f"set-up ∝ n^{slope('setup'):.2f}, peak memory ∝ n^{slope('mem'):.2f}."]
open("bench/results/large_models.md", "w").write("\n".join(out) + "\n")
print("\n".join(out))
PY
