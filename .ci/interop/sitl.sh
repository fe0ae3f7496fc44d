#!/usr/bin/env bash
# Interop: independent MAVLink peers from PyPI (pymavlink, MAVSDK) fly `mavtempo sim`.
# (a) pymavlink: 3-waypoint upload, download, arm, AUTO, MISSION_ITEM_REACHED for each.
# (b) MAVSDK MissionRaw: upload + download, and telemetry.
# Needs python3.11 (or python3) with venv + pip and access to the package registry.
set -euo pipefail
cd "$(dirname "$0")/../.."
. .ci/interop/lib/common.sh

target="${CARGO_TARGET_DIR:-$PWD/target}"
venv="$target/interop-venv"
PYTHON="$(command -v python3.11 || command -v python3)" ensure_venv "$venv" "pymavlink, mavsdk" pymavlink mavsdk

cargo build --quiet --bin mavtempo
bin="$target/debug/mavtempo"

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

# Starts a sim on a free port; prints the port.
start_sim() {
  local log="$1"
  "$bin" sim --listen tcpin:127.0.0.1:0 --speedup 20 --seed 1 >"$log" 2>&1 &
  pids+=("$!")
  if wait_for_line "$log" "sitl listening on" "$!"; then
    sed -n 's/^sitl listening on [0-9.]*:\([0-9]*\) .*/\1/p' "$log" | head -n 1
    return 0
  fi
  echo "mavtempo sim did not start:" >&2
  cat "$log" >&2
  return 1
}

logdir="$(mktemp -d)"
port_a="$(start_sim "$logdir/sim-a.log")"
echo "== pymavlink against mavtempo sim on port $port_a"
timeout 180 "$venv/bin/python" .ci/interop/sitl_pymavlink.py "$port_a"

port_b="$(start_sim "$logdir/sim-b.log")"
echo "== MAVSDK against mavtempo sim on port $port_b"
timeout 180 "$venv/bin/python" .ci/interop/sitl_mavsdk.py "$port_b"
echo "interop sitl: OK"
