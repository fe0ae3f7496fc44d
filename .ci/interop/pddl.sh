#!/usr/bin/env bash
# Interop (issue 17): mavtempo's plans of the IPC-2002 Rovers and Satellite benchmarks checked by an independent
# validator, unified-planning's temporal plan validator (from PyPI, in a virtualenv). Fails when a SimpleTime
# p1-p10 instance is unsolved or its plan rejected; for the Time (numeric) variants prints the share solved and
# validated (unified-planning's reader refuses Rovers Time: `?duration` in a numeric effect). Then proves it can
# fail: broken copies of one plan must be rejected. Runs from the repository root, after the release soak.
#
# PDDL_PLANS=DIR [PDDL_BENCH_JSONL=FILE] checks plans already written in the layout of `bench ipc --plans-out`
# (e.g. LPG-td's, from benches/peers/run_ipc.sh: target/ipc-plans/lpg) instead of running mavtempo.
# PDDL_NUMERIC_LIMIT: the Time variants' limit (3 s); PDDL_VENV: the virtualenv (target/pddl-venv);
# PDDL_MIN_VALIDATED=N: at least N SimpleTime instances validated instead of all (a rejected plan still fails).
set -euo pipefail
cd "$(dirname "$0")/../.."
. .ci/interop/lib/common.sh

target="${CARGO_TARGET_DIR:-target}"
venv="${PDDL_VENV:-$target/pddl-venv}"
ensure_venv "$venv" unified_planning unified-planning

scratch_dir
plans="${PDDL_PLANS:-}"
jsonl=()
if [ -z "$plans" ]; then
  plans="$work/plans"
  # SimpleTime within the default limit; Time with a short one, so this script stays within its CI minutes.
  for run in "simple 10" "time ${PDDL_NUMERIC_LIMIT:-3}"; do
    set -- $run
    echo "-- mavtempo bench ipc --variants $1 --time-limit $2"
    cargo run --release --quiet -- bench ipc --json --instances 1-10 --variants "$1" --time-limit "$2" \
      --plans-out "$plans" >> "$work/bench.jsonl" \
      || echo "mavtempo bench ipc --variants $1 exited with $? (a missing plan fails below)" >&2
  done
  jsonl=(--bench-jsonl "$work/bench.jsonl")
elif [ -n "${PDDL_BENCH_JSONL:-}" ]; then
  jsonl=(--bench-jsonl "$PDDL_BENCH_JSONL")
fi

"$venv/bin/python" benches/peers/validate_ipc.py --plans "$plans" "${jsonl[@]}" --instances 1-10 \
  --variants simple,time --required simple ${PDDL_MIN_VALIDATED:+--min-validated "$PDDL_MIN_VALIDATED"} \
  --corrupt rovers:simple:1
echo "pddl interop: ok"
