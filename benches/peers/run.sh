#!/usr/bin/env bash
# Established planners beside mavtempo on the same random problems, in one command:
#
#   bash benches/peers/run.sh [VENV_DIR]        # VENV_DIR defaults to target/peers-venv
#
# 1. a virtualenv with unified-planning and the engines LPG-td (up-lpg), TAMER (up-tamer), Aries (up-aries)
#    and Kairos (up-kairos), from PyPI;
# 2. `mavtempo bench suite --write DIR --pddl --json`: every problem planned by mavtempo, and written in the
#    domain language and in PDDL (DIR/<domain>/domain.pddl, DIR/<domain>/n<N>_s<SEED>.pddl);
# 3. benches/peers/run_peers.py: each planner on each PDDL problem, plans validated, and the Markdown table.
#
# Environment: SEEDS (10), FIRST_SEED (1000), TIME_LIMIT (10 s), MAX_SIZE (12), DOMAIN (all three; or
# rover, auv, shopping), PLANNERS (lpg,tamer,aries,kairos), OUT (target/peers), PYTHON (python3),
# CARGO_TARGET_DIR (where the release build goes). Outputs: OUT/mavtempo.jsonl, OUT/peers.jsonl, OUT/table.md.
# Not in .ci/run: with 10 s per planner and problem it takes about an hour.
set -euo pipefail
cd "$(dirname "$0")/../.."

VENV=${1:-target/peers-venv}
OUT=${OUT:-target/peers}
SEEDS=${SEEDS:-10}
FIRST_SEED=${FIRST_SEED:-1000}
TIME_LIMIT=${TIME_LIMIT:-10}
MAX_SIZE=${MAX_SIZE:-12}
PLANNERS=${PLANNERS:-lpg,tamer,aries,kairos}
PYTHON=${PYTHON:-python3}

if [ ! -x "$VENV/bin/python" ]; then
    "$PYTHON" -m venv "$VENV"
fi
"$VENV/bin/pip" install --quiet unified-planning up-lpg up-tamer up-aries up-kairos

cargo build --release --quiet
MAVTEMPO="${CARGO_TARGET_DIR:-target}/release/mavtempo"

rm -rf "$OUT/problems"
mkdir -p "$OUT"
domain_arg=()
if [ -n "${DOMAIN:-}" ]; then domain_arg=(--domain "$DOMAIN"); fi
"$MAVTEMPO" bench suite "${domain_arg[@]}" --max-size "$MAX_SIZE" --seeds "$SEEDS" --first-seed "$FIRST_SEED" \
    --time-limit "$TIME_LIMIT" --write "$OUT/problems" --pddl --json > "$OUT/mavtempo.jsonl"

"$VENV/bin/python" benches/peers/run_peers.py --problems "$OUT/problems" --mavtempo "$OUT/mavtempo.jsonl" \
    --planners "$PLANNERS" --time-limit "$TIME_LIMIT" --out "$OUT/peers.jsonl" | tee "$OUT/table.md"
