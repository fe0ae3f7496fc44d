#!/usr/bin/env bash
# mavtempo, LPG-td and Kairos side by side on the development set (../shared/benchmarks), every plan checked by
# unified-planning's validator (issue 32):
#
#   bash benches/peers/devset.sh [devset.py options]     # e.g. --domains depots --instances 1-3
#
# 1. the peers' virtualenv (VENV, default target/peers-venv: unified-planning up-lpg up-kairos from PyPI);
# 2. `cargo build --release` (skipped with BUILD=0);
# 3. benches/peers/devset.py in that virtualenv: p1-p10 of every folder, 10 s each, one run at a time; rows in
#    OUT/devset-peers.jsonl (OUT: benches/peers/results), the table in OUT/devset-peers.md.
# About 45 min on 2 cores. Not in .ci/run.
set -euo pipefail
cd "$(dirname "$0")/../.."

OUT=${OUT:-benches/peers/results}
VENV=${VENV:-target/peers-venv}
PYTHON=${PYTHON:-python3}
if [ ! -x "$VENV/bin/python" ]; then
    "$PYTHON" -m venv "$VENV"
fi
"$VENV/bin/pip" install --quiet unified-planning up-lpg up-kairos
if [ "${BUILD:-1}" = 1 ]; then
    cargo build --release --quiet
fi
mkdir -p "$OUT"
"$VENV/bin/python" benches/peers/devset.py --out "$OUT/devset-peers.jsonl" "$@" | tee "$OUT/devset-peers.md"
