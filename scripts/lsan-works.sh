#!/usr/bin/env bash
# Exits 0 if LeakSanitizer works on this machine. It stops the process's
# threads with ptrace at exit, which some containers forbid; there it dies
# with "LeakSanitizer has encountered a fatal error" on every program.
# Usage: scripts/lsan-works.sh [COMPILER]   (default: c++)
set -uo pipefail
compiler="${1:-c++}"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
echo 'int main() { return 0; }' >"$dir/probe.cpp"
"$compiler" -fsanitize=address "$dir/probe.cpp" -o "$dir/probe" 2>/dev/null || exit 1
ASAN_OPTIONS=detect_leaks=1 "$dir/probe" >/dev/null 2>&1
