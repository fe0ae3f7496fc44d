#!/usr/bin/env bash
# Interop (issue 6): an independent ground station (pymavlink, from PyPI) uploads a goal list to mavtempo's goal
# intake (component 191) and reads the MISSION_ACK and one STATUSTEXT per goal, including a rejected goal; then
# the .tlog mavtempo recorded is read back with pymavlink. Runs from the repository root.
set -euo pipefail
cd "$(dirname "$0")/../.."
. .ci/interop/lib/common.sh

target="${CARGO_TARGET_DIR:-target}"
venv="${MAVTEMPO_VENV:-$target/interop-venv}"
ensure_venv "$venv" pymavlink pymavlink

cargo build --quiet --bin mavtempo
scratch_dir

# Port 0: the server prints the address it bound.
"$target/debug/mavtempo" goal serve --listen udpin:127.0.0.1:0 --home 43.5616,1.4847 --tlog "$work/intake.tlog" \
  > "$work/server.out" 2> "$work/server.err" &
bg_pid=$!
wait_for_line "$work/server.out" '^listening on ' "$bg_pid" \
  || { echo "goal server did not start" >&2; cat "$work/server.err" >&2; exit 1; }
addr="$(sed -n 's/^listening on //p' "$work/server.out")"

cat > "$work/upload.py" <<'PY'
import sys, time
from pymavlink import mavutil

addr = sys.argv[1]
m = mavutil.mavlink_connection("udpout:" + addr, source_system=255, source_component=190)
deadline = time.time() + 10

def heartbeat():
    m.mav.heartbeat_send(mavutil.mavlink.MAV_TYPE_GCS, mavutil.mavlink.MAV_AUTOPILOT_INVALID, 0, 0, 0)

hb = None
while hb is None and time.time() < deadline:
    heartbeat()
    msg = m.recv_match(type="HEARTBEAT", blocking=True, timeout=1)
    if msg is not None and msg.get_srcComponent() == 191:
        hb = msg
assert hb is not None, "no heartbeat from component 191"
assert hb.type == mavutil.mavlink.MAV_TYPE_ONBOARD_CONTROLLER, hb
sysid = hb.get_srcSystem()

G = mavutil.mavlink
items = [
    # be at a position that is no known object: a new location
    (G.MAV_CMD_NAV_WAYPOINT, G.MAV_FRAME_GLOBAL, 0, 0, 0, 0, int(43.5617e7), int(1.4848e7), 0),
    # goal attributes for the next item: priority 2, window [0, 30] s, d_achiev 60 s -> rejected
    (31011, G.MAV_FRAME_MISSION, 2, 0, 30, 0, 60, 0, 0),
    (G.MAV_CMD_IMAGE_START_CAPTURE, G.MAV_FRAME_GLOBAL, 0, 0, 1, 0, int(43.5620e7), int(1.4850e7), 0),
]
m.mav.mission_count_send(sysid, 191, len(items), 0)
ack = None
while ack is None and time.time() < deadline:
    msg = m.recv_match(type=["MISSION_REQUEST_INT", "MISSION_REQUEST", "MISSION_ACK"], blocking=True, timeout=1)
    if msg is None:
        continue
    if msg.get_type() == "MISSION_ACK":
        ack = msg
        break
    cmd, frame, p1, p2, p3, p4, x, y, z = items[msg.seq]
    m.mav.mission_item_int_send(sysid, 191, msg.seq, frame, cmd, 0, 1, p1, p2, p3, p4, x, y, z, 0)
assert ack is not None, "no MISSION_ACK"
assert ack.type == G.MAV_MISSION_ACCEPTED, ack
texts = []
while len(texts) < 2 and time.time() < deadline:
    msg = m.recv_match(type="STATUSTEXT", blocking=True, timeout=1)
    if msg is not None:
        texts.append(msg.text)
print("\n".join(texts))
assert len(texts) == 2, texts
assert texts[0].endswith("accepted: at(" + texts[0].split()[0] + "_loc)"), texts
assert texts[1].endswith("rejected: window ends before reachable"), texts
PY

echo "-- MAVLink 2"
MAVLINK20=1 "$venv/bin/python" "$work/upload.py" "$addr"
echo "-- MAVLink 1"
MAVLINK20= "$venv/bin/python" "$work/upload.py" "$addr"

# Stop the server (it flushes its .tlog) and read the log with pymavlink.
kill -INT "$bg_pid"
wait "$bg_pid" || true
bg_pid=""
cat > "$work/tlog.py" <<'PY'
import sys, time
from pymavlink import mavutil
m = mavutil.mavlink_connection(sys.argv[1])
seen = {}
while True:
    msg = m.recv_match()
    if msg is None:
        break
    if msg.get_type() == "BAD_DATA":
        raise SystemExit("bad data in tlog: %r" % msg)
    seen[(msg.get_type(), msg.get_srcComponent())] = msg._timestamp
for key in [("MISSION_COUNT", 190), ("MISSION_ITEM_INT", 190), ("MISSION_ACK", 191), ("STATUSTEXT", 191), ("HEARTBEAT", 191)]:
    assert key in seen, (key, sorted(seen))
    assert abs(seen[key] - time.time()) < 600, seen[key]
print("tlog ok:", len(seen), "message kinds")
PY
"$venv/bin/python" "$work/tlog.py" "$work/intake.tlog"
echo "goals interop: ok"
