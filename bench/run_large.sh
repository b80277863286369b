#!/bin/bash
# Large models read from binary .msh files: the §6.3 ball's shell meshed
# once by Gmsh (bench/large/shell.geo, Delaunay, one thread; cached) at
# each mesh size, then read by conserve (renumbered: [body.mesh] reorder)
# and run for a few vibrating steps (released with a 1 % stretch, before
# any contact) on each number of MPI ranks. Per size and rank count:
# Gmsh's meshing time, conserve's set-up (summary.json setup_seconds),
# time and GMRES iterations per Newton iteration, the largest rank's peak
# memory and its bytes per unknown; growth exponents by least squares on
# log-log over the sizes, per rank count; and each rank's memory split
# into a part every rank holds and a part shared out (P(N) = R + S/N, from
# 1 and 2 ranks). Writes bench/results/large_models.md.
#
#   bash bench/run_large.sh [--sizes "0.0182 0.0117 0.00774"] [--ranks "1 2"] [--steps 3] [--set KEY=VALUE]...
#                           [--reuse] [--no-build]
#
# --set passes a key to every run (e.g. solver.preconditioner=ilu: the
# automatic choice takes GAMG from 2M unknowns); --reuse tabulates the runs
# already in BENCH_WORK.
#
# The default sizes give about 0.1M, 0.35M and 1.18M unknowns; the largest
# needs about 4 GB and 10 minutes on 2 cores (most of it Gmsh, once);
# 0.00567 gives 3M unknowns (Gmsh: 10 minutes and 3 GB, once; conserve
# about 10 GB on one rank).
set -euo pipefail
cd "$(dirname "$0")/.."
sizes="0.0182 0.0117 0.00774"
rank_counts="1 2"
steps=3
sets=()
reuse=0
build=1
while [ $# -gt 0 ]; do
  case "$1" in
    --sizes) sizes="$2"; shift ;;
    --steps) steps="$2"; shift ;;
    --ranks) rank_counts="$2"; shift ;;
    --set) sets+=(--set "$2"); shift ;;
    --reuse) reuse=1 ;;
    --no-build) build=0 ;;
    -h|--help) sed -n '2,24p' "$0"; exit 0 ;;
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
  for n in $rank_counts; do
    [ "$reuse" -eq 1 ] && [ -f "$work/run_${h}_$n/summary.json" ] && continue
    echo "== run h = $h on $n rank(s) $(date -u +%H:%M:%S) UTC"
    launcher=()
    [ "$n" -gt 1 ] && launcher=(mpiexec -q --oversubscribe -n "$n")
    OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
      "${launcher[@]}" "$bin" run "$scen" -o "$work/run_${h}_$n" --steps "$steps" -q "${sets[@]}" > "$work/run_${h}_$n.log" 2>&1
    tail -n 3 "$work/run_${h}_$n.log" | sed 's/^/   /'
  done
  rows+=("$h")
done
# The smallest size once more with the file's own numbering (no reorder), on one rank.
first=${rows[0]}
sed '/^reorder = true/d' "$work/ball_$first.toml" > "$work/ball_${first}_file.toml"
[ "$reuse" -eq 1 ] && [ -f "$work/run_${first}_file/summary.json" ] ||
  "$bin" run "$work/ball_${first}_file.toml" -o "$work/run_${first}_file" --steps "$steps" -q "${sets[@]}" \
    > "$work/run_${first}_file.log" 2>&1
/usr/bin/python3 - "$work" "$rank_counts" "${sets[*]:-}" "${rows[@]}" <<'PY'
import datetime, json, math, os, sys
work, counts, sets, sizes = sys.argv[1], [int(n) for n in sys.argv[2].split()], sys.argv[3], sys.argv[4:]
rows = []
for h in sizes:
    for n in counts:
        s = json.load(open(f"{work}/run_{h}_{n}/summary.json"))
        it = s["mean_newton_iterations"] * s["steps"]
        gmsh = float(open(f"{work}/gmsh_{h}.seconds").read())
        mem = s["peak_memory_bytes"]
        rows.append(dict(h=h, n=s["unknowns"], ranks=n, gmsh=gmsh, setup=s["setup_seconds"],
                         per_it=s["wall_seconds"] / it, krylov=s["linear_iterations"] / it, mem=mem,
                         bpu=mem / s["unknowns"], e=s["drift"]["E"]))
def slope(key, ranks):
    sel = [r for r in rows if r["ranks"] == ranks]
    if len(sel) < 2: return float("nan")
    x = [math.log(r["n"]) for r in sel]; y = [math.log(r[key]) for r in sel]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    return sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
out = ["# Large models read from binary .msh files (the §6.3 ball's shell)", "",
       f"`bash bench/run_large.sh --sizes \"{' '.join(sizes)}\" --ranks \"{' '.join(map(str, counts))}\""
       f"{' ' + sets if sets else ''}`; the linear solver as summary.json names it: "
       f"{json.load(open(f'{work}/run_{sizes[-1]}_{counts[-1]}/summary.json'))['linear_solver']} at the largest size. "
       "Gmsh meshes each size once (Delaunay, one thread);",
       "conserve reads the file (`reorder = true`) and runs vibrating steps before any contact, on each number of "
       "MPI ranks (one process without a launcher).",
       f"{os.cpu_count()} cores, {datetime.date.today().isoformat()}; set-up is `summary.json` `setup_seconds`; "
       "memory is the largest rank's peak resident memory (`peak_memory_bytes`).", "",
       "| mesh size [m] | unknowns | ranks | Gmsh meshing [s] | conserve set-up [s] | s / Newton it | GMRES it / Newton it | peak per rank [GB] | bytes / unknown per rank | E drift |",
       "|---|---|---|---|---|---|---|---|---|---|"]
for r in rows:
    out.append(f"| {r['h']} | {r['n']:,} | {r['ranks']} | {r['gmsh']:.1f} | {r['setup']:.1f} | {r['per_it']:.3f} | "
               f"{r['krylov']:.1f} | {r['mem'] / 1e9:.2f} | {r['bpu']:,.0f} | {r['e']:.1e} |")
if 1 in counts and 2 in counts:
    out += ["", "Each rank's memory as P(N) = R + S/N (R held by every rank, S shared out), from the peaks on 1 and 2 ranks:", "",
            "| unknowns | R [GB] | S [GB] | R per unknown [B] | S per unknown [B] |", "|---|---|---|---|---|"]
    for h in sizes:
        one = next(r for r in rows if r["h"] == h and r["ranks"] == 1)
        two = next(r for r in rows if r["h"] == h and r["ranks"] == 2)
        shared = 2 * (one["mem"] - two["mem"]); held = one["mem"] - shared
        out.append(f"| {one['n']:,} | {held / 1e9:.2f} | {shared / 1e9:.2f} | {held / one['n']:,.0f} | {shared / one['n']:,.0f} |")
f = json.load(open(f"{work}/run_{sizes[0]}_file/summary.json"))
r0 = next(r for r in rows if r["h"] == sizes[0] and r["ranks"] == counts[0])
f_it = f["wall_seconds"] / (f["mean_newton_iterations"] * f["steps"])
r0_assembly = json.load(open(f"{work}/run_{r0['h']}_{counts[0]}/summary.json"))["seconds"]["assembly"]
out += ["", f"Mesh size {r0['h']} with the file's own (Gmsh's) numbering instead of `reorder = true`, one rank: "
        f"{f_it:.3f} s / Newton it ({f_it / r0['per_it']:.2f}× the reordered), "
        f"{f['linear_iterations'] / (f['mean_newton_iterations'] * f['steps']):.1f} GMRES it / Newton it, "
        f"assembly {f['seconds']['assembly']:.2f} s against {r0_assembly:.2f} s."]
out += [""]
for n in counts:
    out.append(f"Growth on {n} rank(s) (least squares on log-log): time per Newton iteration ∝ n^{slope('per_it', n):.2f}, "
               f"GMRES iterations ∝ n^{slope('krylov', n):.2f}, set-up ∝ n^{slope('setup', n):.2f}, "
               f"peak memory per rank ∝ n^{slope('mem', n):.2f}.")
open("bench/results/large_models.md", "w").write("\n".join(out) + "\n")
print("\n".join(out))
PY
