#!/usr/bin/env bash
# Fuzzes the .msh reader and the scenario parser with libFuzzer (clang,
# -fsanitize=fuzzer,address,undefined), each target for SECONDS (default 60),
# starting from the seed corpus: tests/data/msh/*.msh, examples/**/*.msh,
# tests/data/scenarios/*.toml and examples/**/*.toml. Installs what it needs
# from Debian packages (idempotent). Findings (crash-*, leak-*, timeout-*)
# land in build/fuzz/findings/TARGET/; the exit code is non-zero if any.
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]   (targets: fuzz_msh fuzz_scenario)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_msh fuzz_scenario)

bash scripts/install-deps.sh
packages=(clang libclang-rt-14-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "fuzz: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build=build/fuzz
CC=clang CXX=clang++ cmake -S fuzz -B "$build" -G Ninja >/dev/null
cmake --build "$build" --parallel "$(nproc)" --target "${targets[@]}"

# The seeds: the msh target reads its first byte's bit 0 as the dimension
# (odd: 3D) and its bit 1 as whether a file without cells may be a bare
# surface (set in '2' and '3': the surfaces tray.msh and valley.msh are
# read as such).
seed() {  # seed TARGET PREFIX_BYTE FILES...
  local dir="$build/corpus/$1" prefix="$2"
  shift 2
  mkdir -p "$dir"
  for f in "$@"; do
    [ -f "$f" ] || continue
    { printf '%s' "$prefix"; cat "$f"; } >"$dir/seed_$(echo "$f" | tr '/' '_')"
  done
}
shopt -s nullglob globstar
seed fuzz_msh 3 tests/data/msh/*.msh examples/**/*.msh tests/data/scenarios/meshes/*.msh
seed fuzz_msh 2 tests/data/msh/square.msh tests/data/msh/valley.msh examples/validation/disc.msh
seed fuzz_scenario "" tests/data/scenarios/*.toml examples/**/*.toml

leaks=1
if ! bash scripts/lsan-works.sh clang++; then
  leaks=0
  echo "fuzz: LeakSanitizer cannot run here (ptrace is not allowed); fuzzing without leak checks"
fi

status=0
for t in "${targets[@]}"; do
  findings="$build/findings/$t"
  mkdir -p "$findings"
  dict=fuzz/scenario.dict
  [ "$t" = fuzz_msh ] && dict=fuzz/msh.dict
  echo "fuzz: $t for ${seconds} s"
  if ! "$build/$t" "$build/corpus/$t" -dict="$dict" -max_total_time="$seconds" -max_len=65536 -timeout=10 \
      -rss_limit_mb=2048 -detect_leaks="$leaks" -artifact_prefix="$findings/" -print_final_stats=1 2>"$build/$t.log"; then
    status=1
    echo "fuzz: $t found a problem:"
    grep -E "ERROR|SUMMARY|terminate|what\(\)" "$build/$t.log" | head -20
  fi
  grep -E "stat::number_of_executed_units|stat::new_units_added|cov:" "$build/$t.log" | tail -3
done
ls "$build"/findings/*/ 2>/dev/null | grep -E "crash|leak|timeout|oom" && status=1
exit $status
