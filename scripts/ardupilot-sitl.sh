#!/usr/bin/env bash
# A whole mission on a real ArduPilot Rover SITL, as a user would run it: the SITL is started and
# `mavtempo run --config config/ardupilot-rover.toml` right after it (no waiting for its boot: the companion
# waits for a fix and arming itself); an operator script (scripts/ardupilot-faults.py, pymavlink in a
# virtualenv this script creates) arms the rover (arming is the operator's in that config), uploads a goal
# file through the companion's ground-station port during the run, switches the rover to HOLD in the middle
# of a move (the companion yields) and back to GUIDED 10 s later (it resumes). Everything runs inside a private network
# namespace (ArduPilot's SITL listens on all interfaces).
#
#   scripts/ardupilot-sitl.sh -b ARDUROVER -d ROVER_PARM [-p PROBLEM] [-g GOALS] [-u UPLOAD_AT_S]
#                             [-m HOLD_MOVE] [-x SPEEDUP] [-n] [-o DIR]
#     -b  the SITL binary built from ArduPilot's sources (build/sitl/bin/ardurover)
#     -d  ArduPilot's rover defaults (Tools/autotest/default_params/rover.parm)
#     -p  the problem (default domains/rover/problems/fig2.ixt)
#     -g  the goal file uploaded during the run (default config/goals/example.plan; "" for none)
#     -u  when, in the vehicle's seconds since boot (default 120)
#     -m  HOLD in the middle of the N-th move (default 2; 0: never)
#     -x  SITL speed-up (default 5)
#     -n  no camera (stock parameters: IMAGE_START_CAPTURE is FAILED, pictures fail)
#     -o  where logs and the JSON report go (default: a temporary directory)
# Needs a release build of mavtempo (MAVTEMPO_BIN overrides it), python3, unshare and ip (iproute2).
# Nothing of ArduPilot is part of this project: point -b and -d at your own build.
set -euo pipefail

problem=domains/rover/problems/fig2.ixt
goals=config/goals/example.plan
upload_at=120
hold_move=2
speedup=5
camera=1
out=""
bin_ap=""
defaults=""
while getopts "b:d:p:g:u:m:x:no:" opt; do
  case $opt in
    b) bin_ap=$OPTARG ;;
    d) defaults=$OPTARG ;;
    p) problem=$OPTARG ;;
    g) goals=$OPTARG ;;
    u) upload_at=$OPTARG ;;
    m) hold_move=$OPTARG ;;
    x) speedup=$OPTARG ;;
    n) camera=0 ;;
    o) out=$OPTARG ;;
    *) sed -n 2,20p "$0"; exit 2 ;;
  esac
done
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${MAVTEMPO_BIN:-${CARGO_TARGET_DIR:-$root/target}/release/mavtempo}
[ -x "$bin" ] || { echo "no $bin: cargo build --release first" >&2; exit 2; }
[ -x "$bin_ap" ] || { echo "-b: the ArduPilot SITL binary is needed (build/sitl/bin/ardurover)" >&2; exit 2; }
[ -f "$defaults" ] || { echo "-d: ArduPilot's rover.parm is needed" >&2; exit 2; }
bin_ap=$(realpath "$bin_ap"); defaults=$(realpath "$defaults")
[ -n "$out" ] || out=$(mktemp -d)
mkdir -p "$out"; out=$(realpath "$out")

# pymavlink for the operator script, from the package registry into our own virtualenv.
# shellcheck source=scripts/sitl-common.sh
. "$root/scripts/sitl-common.sh"
venv=${ARDUPILOT_VENV:-$out/venv}
sitl_venv "$venv"

# Re-run inside a private network namespace with loopback up.
if [ -z "${MAVTEMPO_IN_NETNS:-}" ]; then
  no_camera=()
  [ "$camera" = 0 ] && no_camera=(-n)
  exec unshare -n env MAVTEMPO_IN_NETNS=1 ARDUPILOT_VENV="$venv" MAVTEMPO_BIN="$bin" \
    "$0" -b "$bin_ap" -d "$defaults" -p "$problem" -g "$goals" -u "$upload_at" -m "$hold_move" \
    -x "$speedup" "${no_camera[@]}" -o "$out"
fi
ip link set lo up

cd "$root"
# Our parameters on top of ArduPilot's defaults: a SITL camera (CAM2_TYPE 0, else ArduPilot resets CAM1_TYPE).
extra="$out/mavtempo.parm"
if [ "$camera" = 1 ]; then printf 'CAM1_TYPE 1\nCAM2_TYPE 0\n' > "$extra"; else : > "$extra"; fi
home=$(awk -F' *= *' '/^\[home\]/{h=1} h&&/^lat/{la=$2} h&&/^lon/{lo=$2} h&&/^alt/{al=$2} END{print la+0","lo+0","al+0",0"}' config/ardupilot-rover.toml)
echo "ArduPilot SITL: $bin_ap, home $home, speed-up $speedup, camera $camera; logs in $out"

(cd "$out" && exec "$bin_ap" --model rover --speedup "$speedup" --home "$home" -I0 \
  --defaults "$defaults,$extra" > sitl.log 2>&1) &
sitl=$!
trap 'kill $sitl 2>/dev/null || true' EXIT

# Right after boot: the companion waits for the fix and the operator's arming.
"$bin" run --config config/ardupilot-rover.toml --speedup "$speedup" --gcs udpin:127.0.0.1:14551 \
  --report "$out/report.json" --link-timeout 60 domains/rover/rover.ixt "$problem" > "$out/run.log" 2>&1 &
companion=$!

op_args=(--mavtempo "$bin" --companion-pid "$companion" --hold-move "$hold_move")
if [ -n "$goals" ]; then op_args+=(--goals "$goals" --upload-at "$upload_at"); fi
"$venv/bin/python" scripts/ardupilot-faults.py "${op_args[@]}" > "$out/operator.log" 2>&1 &
operator=$!

sitl_finish $companion $operator "$out"
