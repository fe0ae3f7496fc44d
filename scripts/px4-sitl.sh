#!/usr/bin/env bash
# A whole mission on a real PX4 SIH rover (no Gazebo), as a user would run it: PX4 is started with a SIH model
# and `mavtempo run --config config/px4-rover.toml` right after it (the companion waits for PX4's pre-arm
# checks, its estimator and the operator's arming itself); an operator script (scripts/ardupilot-faults.py
# --autopilot px4, pymavlink in a virtualenv this script creates) arms the rover on PX4's ground-station link,
# uploads a goal file through the companion's ground-station port during the run, takes control in the middle
# of a move (Return: the companion yields) and hands it back by switching to Hold 10 s later (the companion's
# own mode on PX4: it resumes). Everything runs inside a private network namespace (PX4 listens on all
# interfaces).
#
#   scripts/px4-sitl.sh -b PX4_BUILD_DIR [-M MODEL] [-c CONFIG] [-D DOMAIN] [-p PROBLEM] [-g GOALS]
#                       [-u UPLOAD_AT_S] [-m HOLD_MOVE] [-B DRAIN_S] [-x SPEEDUP] [-o DIR]
#     -b  PX4's build directory (build/px4_sitl_default or build/px4_sitl_nodds: bin/px4 and etc/)
#     -M  the SIH model (default sihsim_rover_ackermann; sihsim_quadx: the copter below)
#     -c  the vehicle configuration (default config/px4-rover.toml); its [home] is SIH's origin
#     -D  the domain (default domains/rover/rover.ixt)
#     -p  the problem (default domains/rover/problems/fig2.ixt)
#     -g  the goal file uploaded during the run (default config/goals/px4-example.plan; "" for none)
#     -u  when, in the vehicle's seconds since boot (default 120)
#     -m  take control in the middle of the N-th move (default 2; 0: never)
#     -B  SIM_BAT_DRAIN, seconds from a full battery to empty while armed (default 3600; PX4's own 60)
#     -x  PX4_SIM_SPEED_FACTOR, and the companion's --speedup (default 1)
#     -o  where logs and the JSON report go (default: a temporary directory)
# The copter (domains/copter, a quadrotor in SIH, arming and takeoff left to the companion):
#   scripts/px4-sitl.sh -b PX4_BUILD_DIR -M sihsim_quadx -c config/px4-copter.toml -D domains/copter/copter.ixt \
#     -p domains/copter/problems/survey.ixt -g config/goals/copter.plan -u 60 -m 0 -B 600
# Needs a release build of mavtempo (MAVTEMPO_BIN overrides it), python3, unshare and ip (iproute2).
# Nothing of PX4 is part of this project: point -b at your own build (../shared/notes/autopilot-sitl.md).
set -euo pipefail

model=sihsim_rover_ackermann
config=config/px4-rover.toml
domain=domains/rover/rover.ixt
drain=3600
problem=domains/rover/problems/fig2.ixt
goals=config/goals/px4-example.plan
upload_at=120
hold_move=2
speedup=1
out=""
build=""
while getopts "b:M:c:D:p:g:u:m:B:x:o:" opt; do
  case $opt in
    b) build=$OPTARG ;;
    M) model=$OPTARG ;;
    c) config=$OPTARG ;;
    D) domain=$OPTARG ;;
    B) drain=$OPTARG ;;
    p) problem=$OPTARG ;;
    g) goals=$OPTARG ;;
    u) upload_at=$OPTARG ;;
    m) hold_move=$OPTARG ;;
    x) speedup=$OPTARG ;;
    o) out=$OPTARG ;;
    *) sed -n 2,28p "$0"; exit 2 ;;
  esac
done
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${MAVTEMPO_BIN:-${CARGO_TARGET_DIR:-$root/target}/release/mavtempo}
[ -x "$bin" ] || { echo "no $bin: cargo build --release first" >&2; exit 2; }
[ -x "$build/bin/px4" ] && [ -d "$build/etc" ] || {
  echo "-b: PX4's build directory is needed (with bin/px4 and etc/)" >&2; exit 2; }
build=$(realpath "$build")
[ -n "$out" ] || out=$(mktemp -d)
mkdir -p "$out"; out=$(realpath "$out")

# pymavlink for the operator script, from the package registry into our own virtualenv.
# shellcheck source=scripts/sitl-common.sh
. "$root/scripts/sitl-common.sh"
venv=${PX4_VENV:-$out/venv}
sitl_venv "$venv"

# Re-run inside a private network namespace with loopback up.
if [ -z "${MAVTEMPO_IN_NETNS:-}" ]; then
  exec unshare -n env MAVTEMPO_IN_NETNS=1 PX4_VENV="$venv" MAVTEMPO_BIN="$bin" \
    "$0" -b "$build" -M "$model" -c "$config" -D "$domain" -p "$problem" -g "$goals" -u "$upload_at" \
    -m "$hold_move" -B "$drain" -x "$speedup" -o "$out"
fi
ip link set lo up

cd "$root"
# SIH starts at the configuration's [home] (px4-rc.sihsim: PX4_HOME_LAT/LON/ALT set SIH_LOC_LAT0/LON0/H0;
# without them SIH starts in Zurich), as written in the file (no rounding), comments dropped.
read -r home_lat home_lon home_alt < <(awk -F' *= *' '/^\[/{h=($0=="[home]")}
  h&&($1=="lat"||$1=="lon"||$1=="alt"){sub(/ *#.*/,"",$2); v[$1]=$2} END{print v["lat"], v["lon"], v["alt"]}' "$config")
echo "PX4 SIH: $build/bin/px4, model $model, home $home_lat,$home_lon,$home_alt, speed factor $speedup; logs in $out"
# A fresh working directory: PX4 keeps its parameters there (a second run would start from the first's).
rm -rf "$out/px4-work"; mkdir -p "$out/px4-work"
(cd "$out/px4-work" && PX4_SIM_MODEL=$model PX4_SIMULATOR=sihsim PX4_SIM_SPEED_FACTOR=$speedup \
  PX4_HOME_LAT=$home_lat PX4_HOME_LON=$home_lon PX4_HOME_ALT=$home_alt exec "$build/bin/px4" -d -w "$out/px4-work" "$build/etc" > "$out/px4.log" 2>&1) &
px4=$!
trap 'kill $px4 2>/dev/null || true' EXIT

# Right after boot: PX4's onboard link sends to UDP 14540, its ground-station link to 14550.
"$bin" run --config "$config" --speedup "$speedup" --gcs udpin:127.0.0.1:14551 \
  --report "$out/report.json" --link-timeout 60 "$domain" "$problem" > "$out/run.log" 2>&1 &
companion=$!

op_args=(--autopilot px4 --vehicle udpin:127.0.0.1:14550 --mavtempo "$bin" --companion-pid "$companion"
  --hold-move "$hold_move" --bat-drain "$drain")
# Arming is the operator's unless the configuration leaves it to the companion (the copter arms at takeoff).
arm_by=$(awk -F' *= *' '/^\[/{a=($0=="[authority]")} a&&$1=="arm"{gsub(/"| *#.*/,"",$2); print $2}' "$config")
if [ "$arm_by" = companion ]; then op_args+=(--no-arm); fi
if [ -n "$goals" ]; then op_args+=(--goals "$goals" --upload-at "$upload_at"); fi
"$venv/bin/python" scripts/ardupilot-faults.py "${op_args[@]}" > "$out/operator.log" 2>&1 &
operator=$!

echo "PX4 log: $out/px4.log"
sitl_finish $companion $operator "$out"
