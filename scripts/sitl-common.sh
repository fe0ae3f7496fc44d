# Shared by scripts/ardupilot-sitl.sh, scripts/ardupilot-copter-sitl.sh and scripts/px4-sitl.sh (sourced,
# not run).

# sitl_venv DIR: a virtualenv with pymavlink at DIR, for the operator script (from the package registry).
sitl_venv() {
  if [ ! -x "$1/bin/python" ]; then
    python3 -m venv "$1"
    "$1/bin/pip" install --quiet pymavlink
  fi
}

# sitl_finish COMPANION_PID OPERATOR_PID OUT: waits for the companion and the operator script, prints the
# operator's log and the run's summary, and exits with the companion's status.
sitl_finish() {
  local status=0
  wait "$1" || status=$?
  wait "$2" || true
  cat "$3/operator.log"
  grep -E "vehicle|position fix|mission ended|^  [a-z_]|plan repairs|REJECTED|achieved|BATTERY" "$3/run.log" | head -40
  echo "companion exit $status; trace $3/run.log, report $3/report.json"
  exit $status
}
