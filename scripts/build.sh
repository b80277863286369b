#!/usr/bin/env bash
# Sets up (Debian packages) and builds conserve with the given CMake preset
# (default: release). Usage: scripts/build.sh [release|debug|sanitize]
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
bash scripts/install-deps.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" --parallel "$(nproc)"
