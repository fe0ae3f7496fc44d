#!/usr/bin/env bash
# mavtempo and established planners on the IPC-2002 Rovers and Satellite temporal benchmarks (issue 17):
#
#   bash benches/peers/run_ipc.sh [VENV_DIR]      # VENV_DIR defaults to target/peers-venv
#   bash benches/peers/run_ipc.sh --report        # the tables again, from the saved results
#
# 1. the peers' virtualenv (as benches/peers/run.sh: unified-planning up-lpg up-tamer up-aries up-kairos);
# 2. `mavtempo bench ipc --json --plans-out DIR` on every instance (skipped, with a note, when this build has
#    no `bench ipc`);
# 3. benches/peers/run_ipc.py: LPG-td, Kairos, Aries and TAMER on the same files, one run at a time, the same
#    limit (a run still going 5 s past it is killed); every plan, mavtempo's included, checked by
#    unified-planning's validator; the Markdown tables on standard output.
#
# Environment: IPC_DIR (../shared/benchmarks/ipc2002), TIME_LIMIT (10 s), INSTANCES (1-20), DOMAINS
# (rovers,satellite), VARIANTS (simple,time), PLANNERS (lpg,kairos,aries,tamer; empty: the saved peers' results
# are reused), MAVTEMPO (1; 0 skips its run and reuses its saved results), OUT (benches/peers/results), PYTHON
# (python3), CARGO_TARGET_DIR. Outputs: OUT/ipc2002-peers.jsonl, OUT/ipc2002-mavtempo-bench.jsonl (the bench's
# own lines), OUT/ipc2002-mavtempo.jsonl (its rows, checked), OUT/ipc2002-table.md; plans under
# target/ipc-plans. Not in .ci/run (about 45 min at 10 s); .ci/interop/pddl.sh checks mavtempo's plans in CI.
set -euo pipefail
cd "$(dirname "$0")/../.."

OUT=${OUT:-benches/peers/results}
IPC_DIR=${IPC_DIR:-../shared/benchmarks/ipc2002}
TIME_LIMIT=${TIME_LIMIT:-10}
INSTANCES=${INSTANCES:-1-20}
DOMAINS=${DOMAINS:-rovers,satellite}
VARIANTS=${VARIANTS:-simple,time}
PLANNERS=${PLANNERS-lpg,kairos,aries,tamer}
MAVTEMPO=${MAVTEMPO:-1}
PYTHON=${PYTHON:-python3}
target="${CARGO_TARGET_DIR:-target}"
plans="$target/ipc-plans"
select=(--dir "$IPC_DIR" --time-limit "$TIME_LIMIT" --instances "$INSTANCES" --domains "$DOMAINS"
        --variants "$VARIANTS")
mavtempo_rows=()
[ -s "$OUT/ipc2002-mavtempo.jsonl" ] && mavtempo_rows=(--mavtempo-jsonl "$OUT/ipc2002-mavtempo.jsonl")

if [ "${1:-}" = "--report" ]; then
    exec "$PYTHON" benches/peers/run_ipc.py --report "${select[@]}" --out "$OUT/ipc2002-peers.jsonl" \
        "${mavtempo_rows[@]}"
fi

VENV=${1:-target/peers-venv}
if [ ! -x "$VENV/bin/python" ]; then
    "$PYTHON" -m venv "$VENV"
fi
"$VENV/bin/pip" install --quiet unified-planning up-lpg up-tamer up-aries up-kairos
mkdir -p "$OUT"

if [ "$MAVTEMPO" = 1 ]; then
    cargo build --release --quiet
    bin="$target/release/mavtempo"
    if "$bin" bench ipc --help >/dev/null 2>&1; then
        rm -rf "$plans/mavtempo"
        "$bin" bench ipc "${select[@]}" --json --plans-out "$plans/mavtempo" > "$OUT/ipc2002-mavtempo-bench.jsonl"
        mavtempo_rows=(--mavtempo-jsonl "$OUT/ipc2002-mavtempo-bench.jsonl" --mavtempo-plans "$plans/mavtempo"
                       --mavtempo-out "$OUT/ipc2002-mavtempo.jsonl")
    else
        echo "# this build has no \`mavtempo bench ipc\`: its column is left out" >&2
    fi
fi

"$VENV/bin/python" benches/peers/run_ipc.py "${select[@]}" --planners "$PLANNERS" --out "$OUT/ipc2002-peers.jsonl" \
    --plans-out "$plans" "${mavtempo_rows[@]}" | tee "$OUT/ipc2002-table.md"
