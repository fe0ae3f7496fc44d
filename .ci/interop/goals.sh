#!/usr/bin/env bash
# Interop (issue 6): an independent ground station (pymavlink, from PyPI) uploads a goal list to mavtempo's goal
# intake (component 191) and reads the MISSION_ACK and one STATUSTEXT per goal, including a rejected goal; then
# (issue 30) pymavlink's mavwp uploads a Mission Planner file with home as item 0 and camera actions, clears it
# and reads the list back empty, and MAVProxy (`wp load`, with only `--target-system 1`) uploads the same file;
# then the .tlog mavtempo recorded is read back with pymavlink. Runs from the repository root.
set -euo pipefail
cd "$(dirname "$0")/../.."
. .ci/interop/lib/common.sh

target="${CARGO_TARGET_DIR:-target}"
venv="${MAVTEMPO_VENV:-$target/interop-venv}"
ensure_venv "$venv" "pymavlink, MAVProxy" pymavlink MAVProxy

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
# Each run its own station: a second list from the same one would replace the first (same goals: kept).
m = mavutil.mavlink_connection("udpout:" + addr, source_system=int(sys.argv[2]), source_component=190)
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
    # be at a position that is no known object: a new location (not in the absolute global frame: a waypoint
    # there as item 0 is home, as ArduPilot's ground stations send it)
    (G.MAV_CMD_NAV_WAYPOINT, G.MAV_FRAME_GLOBAL_RELATIVE_ALT, 0, 0, 0, 0, int(43.5617e7), int(1.4848e7), 0),
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
MAVLINK20=1 "$venv/bin/python" "$work/upload.py" "$addr" 255
echo "-- MAVLink 1"
MAVLINK20= "$venv/bin/python" "$work/upload.py" "$addr" 254

# pymavlink's mavwp: a Mission Planner file (home as item 0, DO_DIGICAM_CONTROL, a camera trigger distance, a
# speed change), uploaded as mavwp loads it (targets 0/0), then cleared and read back.
cat > "$work/mavwp_upload.py" <<'PY'
import sys, time
from pymavlink import mavutil, mavwp

addr, path = sys.argv[1], sys.argv[2]
m = mavutil.mavlink_connection("udpout:" + addr, source_system=253, source_component=190)
G = mavutil.mavlink
deadline = time.time() + 10
hb = None
while hb is None and time.time() < deadline:
    m.mav.heartbeat_send(G.MAV_TYPE_GCS, G.MAV_AUTOPILOT_INVALID, 0, 0, 0)
    hb = m.recv_match(type="HEARTBEAT", blocking=True, timeout=1)
wp = mavwp.MAVWPLoader()
wp.load(path)
assert wp.count() == 8, wp.count()
m.mav.mission_count_send(0, 0, wp.count())

def answer(kinds):
    got = []
    while time.time() < deadline:
        msg = m.recv_match(type=["MISSION_REQUEST_INT", "MISSION_REQUEST", "MISSION_ACK", "MISSION_COUNT", "STATUSTEXT"], blocking=True, timeout=1)
        if msg is None:
            continue
        if msg.get_type() in ("MISSION_REQUEST_INT", "MISSION_REQUEST"):
            m.mav.send(wp.wp(msg.seq))
            continue
        got.append(msg)
        if msg.get_type() in kinds:
            return got
    raise SystemExit("no %s" % kinds)

def texts_after(got, n):
    # STATUSTEXTs longer than 50 bytes come in chunks sharing an id; a chunk shorter than 50 ends the text.
    texts, parts = [], {}
    def take(x):
        if x.id == 0:
            texts.append(x.text)
            return
        parts[x.id] = parts.get(x.id, "") + x.text
        if len(x.text) < 50:
            texts.append(parts.pop(x.id))
    for x in got:
        if x.get_type() == "STATUSTEXT":
            take(x)
    while len(texts) < n and time.time() < deadline:
        msg = m.recv_match(type="STATUSTEXT", blocking=True, timeout=1)
        if msg is not None:
            take(msg)
    return texts

got = answer(["MISSION_ACK"])
assert got[-1].type == G.MAV_MISSION_ACCEPTED, got[-1]
texts = texts_after(got, 6)
print("\n".join(texts))
assert texts[0].startswith("item 0: the home position"), texts
assert texts[1].startswith("item 7: command 178 is not a goal"), texts
assert all(t.startswith("g") and " accepted: picture_of(" in t for t in texts[2:6]), texts
m.mav.mission_clear_all_send(0, 0)
got = answer(["MISSION_ACK"])
assert got[-1].type == G.MAV_MISSION_ACCEPTED, got[-1]
texts = texts_after(got, 1)
print("\n".join(texts))
assert "cancelled: cleared" in texts[0], texts
m.mav.mission_request_list_send(0, 0)
got = answer(["MISSION_COUNT"])
assert got[-1].count == 0, got[-1]
print("mavwp: uploaded, cleared, read back empty")
PY
echo "-- pymavlink mavwp"
"$venv/bin/python" "$work/mavwp_upload.py" "$addr" tests/fixtures/vehicle/camera.waypoints

# MAVProxy as an operator starts it: only the target system set (MAVProxy takes its target from an autopilot's
# HEARTBEAT; the companion's is not one); target_component stays at its default 0.
echo "-- MAVProxy wp load"
cp tests/fixtures/vehicle/camera.waypoints "$work/"
mavproxy="$(cd "$venv/bin" && pwd)/mavproxy.py"
( cd "$work" && exec "$mavproxy" --master="udpout:$addr" --target-system=1 --non-interactive \
    --source-system=252 --cmd="wp load camera.waypoints" > "$work/mavproxy.out" 2>&1 ) &
mavproxy_pid=$!
for _ in $(seq 1 300); do
  [ "$(grep -c 'accepted: picture_of' "$work/mavproxy.out" 2>/dev/null)" -ge 4 ] && break
  kill -0 "$mavproxy_pid" 2>/dev/null || break
  sleep 0.1
done
if [ "$(grep -c 'accepted: picture_of' "$work/mavproxy.out" 2>/dev/null)" -lt 4 ] \
    || ! grep -q 'MISSION_ACK: TYPE_MISSION: ACCEPTED' "$work/mavproxy.out" \
    || ! grep -q 'item 0: the home position' "$work/mavproxy.out"; then
  kill "$mavproxy_pid" 2>/dev/null || true
  echo "MAVProxy upload failed" >&2; cat "$work/mavproxy.out" >&2; exit 1
fi
kill "$mavproxy_pid" 2>/dev/null || true
wait "$mavproxy_pid" 2>/dev/null || true
grep -E '^(AP: |Got MISSION_ACK)' "$work/mavproxy.out"

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
