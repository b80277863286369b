#!/usr/bin/env bash
# Runs every scenario under examples/ to its end with two builds of
# conserve and compares their history.csv and steps.csv byte for byte: a
# change that should not change any trajectory (a refactoring) must print
# "same" for every run.
#
# Usage: bash bench/same_histories.sh BEFORE AFTER
#   BEFORE, AFTER  two conserve binaries (e.g. one built from main, one from
#                  the working tree); copied first, so rebuilding is safe.
# Runs go to $BENCH_WORK (default out/bench/same), without VTU output, one
# thread each. Exit status 1 if any history differs.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ne 2 ] || [ ! -x "$1" ] || [ ! -x "$2" ]; then
  echo "same_histories.sh: give two conserve binaries (see the header)" >&2
  exit 2
fi
work="${BENCH_WORK:-out/bench/same}"
mkdir -p "$work"
cp "$1" "$work/before"
cp "$2" "$work/after"
status=0
while IFS= read -r scenario; do
  name=$(echo "${scenario#examples/}" | sed 's/\.toml$//; s#/#_#g')
  for side in before after; do
    OMP_NUM_THREADS=1 "$work/$side" run "$scenario" -q -o "$work/$side-$name" --set output.vtu_every=0 \
      > "$work/$side-$name.log" 2>&1 || true
  done
  verdict=same
  for file in history.csv steps.csv; do
    cmp -s "$work/before-$name/$file" "$work/after-$name/$file" || verdict="DIFFERENT ($file)"
  done
  [ "$verdict" = same ] || status=1
  echo "$scenario: $verdict"
done < <(find examples -name '*.toml' | sort)
exit $status
