"""Interop (a): pymavlink uploads a 3-waypoint mission to `mavtempo sim`, reads it back, arms,
sets AUTO (Rover mode 10) and must see MISSION_ITEM_REACHED for each waypoint.
Usage: python sitl_pymavlink.py PORT"""
import math
import sys
import time

from pymavlink import mavutil


def fail(why):
    print(f"pymavlink interop FAILED: {why}", flush=True)
    sys.exit(1)


def recv(m, types, timeout, cond=lambda msg: True):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        msg = m.recv_match(type=types, blocking=True, timeout=max(0.05, deadline - time.monotonic()))
        if msg is not None and cond(msg):
            return msg
    return None


def command(m, cmd, *params):
    p = list(params) + [0.0] * (7 - len(params))
    m.mav.command_long_send(m.target_system, m.target_component, cmd, 0, *p)
    ack = recv(m, "COMMAND_ACK", 10, lambda a: a.command == cmd)
    if ack is None:
        fail(f"no COMMAND_ACK for command {cmd}")
    return ack.result


def main():
    port = int(sys.argv[1])
    m = mavutil.mavlink_connection(f"tcp:127.0.0.1:{port}", source_system=255, source_component=190)
    m.mav.heartbeat_send(mavutil.mavlink.MAV_TYPE_GCS, mavutil.mavlink.MAV_AUTOPILOT_INVALID, 0, 0, 0)
    hb = m.wait_heartbeat(timeout=15)
    if hb is None:
        fail("no HEARTBEAT")
    if hb.type != mavutil.mavlink.MAV_TYPE_GROUND_ROVER or hb.autopilot != mavutil.mavlink.MAV_AUTOPILOT_ARDUPILOTMEGA:
        fail(f"unexpected identity type={hb.type} autopilot={hb.autopilot}")
    print(f"heartbeat from system {m.target_system}: rover, ArduPilot, mode {hb.custom_mode}", flush=True)

    pos = recv(m, "GLOBAL_POSITION_INT", 10)
    if pos is None:
        fail("no GLOBAL_POSITION_INT")
    lat0, lon0 = pos.lat * 1e-7, pos.lon * 1e-7
    m_per_deg = 111319.49
    def at(north, east):
        return (int(round((lat0 + north / m_per_deg) * 1e7)),
                int(round((lon0 + east / (m_per_deg * math.cos(math.radians(lat0)))) * 1e7)))
    # seq 0 is a placeholder: ArduPilot replaces it with home.
    points = [at(0, 0), at(40, 0), at(40, 40), at(0, 40)]

    m.mav.mission_count_send(m.target_system, m.target_component, len(points), 0)
    while True:
        msg = recv(m, ["MISSION_REQUEST_INT", "MISSION_REQUEST", "MISSION_ACK"], 10)
        if msg is None:
            fail("upload stalled")
        if msg.get_type() == "MISSION_ACK":
            if msg.type == mavutil.mavlink.MAV_MISSION_INVALID_SEQUENCE:
                continue  # a late item crossed a re-request; the upload stays open
            if msg.type != mavutil.mavlink.MAV_MISSION_ACCEPTED:
                fail(f"upload refused: MISSION_ACK {msg.type}")
            break
        x, y = points[msg.seq]
        m.mav.mission_item_int_send(m.target_system, m.target_component, msg.seq,
                                    mavutil.mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT,
                                    mavutil.mavlink.MAV_CMD_NAV_WAYPOINT, 0, 1,
                                    0, 0, 0, 0, x, y, 0)
    print("mission uploaded", flush=True)

    m.mav.mission_request_list_send(m.target_system, m.target_component)
    count = recv(m, "MISSION_COUNT", 10)
    if count is None or count.count != len(points):
        fail(f"download count {None if count is None else count.count}")
    for seq in range(1, count.count):
        m.mav.mission_request_int_send(m.target_system, m.target_component, seq)
        it = recv(m, "MISSION_ITEM_INT", 10, lambda i: i.seq == seq)
        if it is None or (it.x, it.y) != points[seq]:
            fail(f"downloaded item {seq} differs")
    m.mav.mission_ack_send(m.target_system, m.target_component, 0)
    print("mission downloaded and identical", flush=True)

    if command(m, mavutil.mavlink.MAV_CMD_COMPONENT_ARM_DISARM, 1) != 0:
        fail("arming refused")
    if command(m, mavutil.mavlink.MAV_CMD_DO_SET_MODE, 1, 10) != 0:
        fail("AUTO refused")
    print("armed, AUTO", flush=True)

    reached = []
    while len(reached) < 3:
        msg = recv(m, "MISSION_ITEM_REACHED", 60)
        if msg is None:
            fail(f"only reached {reached}")
        reached.append(msg.seq)
        print(f"MISSION_ITEM_REACHED {msg.seq}", flush=True)
    if reached != [1, 2, 3]:
        fail(f"reached {reached}, expected [1, 2, 3]")
    print("pymavlink interop OK", flush=True)


if __name__ == "__main__":
    main()
