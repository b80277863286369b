#!/usr/bin/env bash
# Sets up, builds and runs one example end to end (default: the paper's
# §6.3 ball), writing history.csv, plots and ParaView files to out/<name>/.
# Usage: scripts/run-example.sh [examples/NAME.toml]
set -euo pipefail
cd "$(dirname "$0")/.."
scenario="${1:-examples/ball/ball_on_plane.toml}"
name="$(basename "$scenario" .toml)"
bash scripts/build.sh release
./build/release/conserve run "$scenario" -o "out/$name"
if [ -x /usr/bin/python3 ]; then
  /usr/bin/python3 scripts/plot_history.py "out/$name/history.csv"
  /usr/bin/python3 scripts/render_snapshots.py "out/$name" --count 6 || echo "(snapshots skipped)"
fi
