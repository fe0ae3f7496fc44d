#!/usr/bin/env bash
# A copter mission on a real ArduCopter SITL (`arducopter --model quad`): domains/copter with
# config/ardupilot-copter.toml, started right after the SITL boots (the companion waits for a fix and arms
# at its takeoff itself); an operator script (scripts/ardupilot-faults.py, pymavlink in a virtualenv this
# script creates) uploads a picture goal through the companion's ground-station port during the flight.
# Everything runs inside a private network namespace (ArduPilot's SITL listens on all interfaces).
#
#   scripts/ardupilot-copter-sitl.sh -b ARDUCOPTER -d COPTER_PARM [-p PROBLEM] [-g GOALS] [-u UPLOAD_AT_S]
#                                    [-x SPEEDUP] [-o DIR]
#     -b  the SITL binary built from ArduPilot's sources (build/sitl/bin/arducopter)
#     -d  ArduPilot's copter defaults (Tools/autotest/default_params/copter.parm)
#     -p  the problem (default domains/copter/problems/survey.ixt)
#     -g  the goal file uploaded during the run (default config/goals/copter.plan; "" for none)
#     -u  when, in the vehicle's seconds since boot (default 90)
#     -x  SITL speed-up (default 2)
#     -o  where logs and the JSON report go (default: a temporary directory)
# Needs a build of mavtempo (target/release/mavtempo; MAVTEMPO_BIN overrides it), python3, unshare and ip.
# Nothing of ArduPilot is part of this project: point -b and -d at your own build.
set -euo pipefail

problem=domains/copter/problems/survey.ixt
goals=config/goals/copter.plan
upload_at=90
speedup=2
out=""
bin_ap=""
defaults=""
while getopts "b:d:p:g:u:x:o:" opt; do
  case $opt in
    b) bin_ap=$OPTARG ;;
    d) defaults=$OPTARG ;;
    p) problem=$OPTARG ;;
    g) goals=$OPTARG ;;
    u) upload_at=$OPTARG ;;
    x) speedup=$OPTARG ;;
    o) out=$OPTARG ;;
    *) sed -n 2,17p "$0"; exit 2 ;;
  esac
done
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${MAVTEMPO_BIN:-${CARGO_TARGET_DIR:-$root/target}/release/mavtempo}
[ -x "$bin" ] || { echo "no $bin: cargo build --release first" >&2; exit 2; }
[ -x "$bin_ap" ] || { echo "-b: the ArduCopter SITL binary is needed (build/sitl/bin/arducopter)" >&2; exit 2; }
[ -f "$defaults" ] || { echo "-d: ArduPilot's copter.parm is needed" >&2; exit 2; }
bin_ap=$(realpath "$bin_ap"); defaults=$(realpath "$defaults")
[ -n "$out" ] || out=$(mktemp -d)
mkdir -p "$out"; out=$(realpath "$out")

# shellcheck source=scripts/sitl-common.sh
. "$root/scripts/sitl-common.sh"
venv=${ARDUPILOT_VENV:-$out/venv}
sitl_venv "$venv"

if [ -z "${MAVTEMPO_IN_NETNS:-}" ]; then
  exec unshare -n env MAVTEMPO_IN_NETNS=1 ARDUPILOT_VENV="$venv" MAVTEMPO_BIN="$bin" \
    "$0" -b "$bin_ap" -d "$defaults" -p "$problem" -g "$goals" -u "$upload_at" -x "$speedup" -o "$out"
fi
ip link set lo up

cd "$root"
# Our parameters on top of ArduPilot's defaults: telemetry streams on the companion's link (MAV1, SERIAL0)
# and the operator's (MAV2) — ArduCopter's default stream rates are 0 (GCS_MAVLink_Parameters.cpp; the
# SRn_* parameters of older firmware) — and a SITL camera (CAM2_TYPE 0, else ArduPilot resets CAM1_TYPE).
extra="$out/mavtempo.parm"
{
  for link in 1 2; do
    printf 'MAV%s_POSITION 4\nMAV%s_EXT_STAT 2\nMAV%s_EXTRA1 2\nMAV%s_EXTRA2 2\nMAV%s_EXTRA3 2\n' \
      "$link" "$link" "$link" "$link" "$link"
  done
  printf 'CAM1_TYPE 1\nCAM2_TYPE 0\n'
} > "$extra"
# [home]'s lat, lon and alt as written (no rounding), comments dropped.
home=$(awk -F' *= *' '/^\[/{h=($0=="[home]")} h&&($1=="lat"||$1=="lon"||$1=="alt"){sub(/ *#.*/,"",$2); v[$1]=$2}
  END{print v["lat"]","v["lon"]","v["alt"]",0"}' config/ardupilot-copter.toml)
echo "ArduCopter SITL: $bin_ap, home $home, speed-up $speedup; logs in $out"

(cd "$out" && exec "$bin_ap" --model quad --speedup "$speedup" --home "$home" -I0 \
  --defaults "$defaults,$extra" > sitl.log 2>&1) &
sitl=$!
trap 'kill $sitl 2>/dev/null || true' EXIT

"$bin" run --config config/ardupilot-copter.toml --speedup "$speedup" --gcs udpin:127.0.0.1:14551 \
  --report "$out/report.json" --link-timeout 60 domains/copter/copter.ixt "$problem" > "$out/run.log" 2>&1 &
companion=$!

op_args=(--mavtempo "$bin" --companion-pid "$companion" --no-arm)
if [ -n "$goals" ]; then op_args+=(--goals "$goals" --upload-at "$upload_at"); fi
"$venv/bin/python" scripts/ardupilot-faults.py "${op_args[@]}" > "$out/operator.log" 2>&1 &
operator=$!

sitl_finish "$companion" "$operator" "$out"
