#!/usr/bin/env bash
# Sets up, builds and runs the test suite (about two minutes on 2 cores).
# Usage: scripts/test.sh [release|sanitize] [extra ctest arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
shift || true
bash scripts/build.sh "$preset"
ctest --preset "$preset" "$@"
