#!/usr/bin/env python3
"""Watches a real ArduPilot Rover SITL on a spare port (pymavlink) while `mavtempo run` drives it, and does
what an operator would: uploads a goal file through the companion's ground-station port once the vehicle's
clock reaches a given time, arms the rover once its estimator is ready (arming is the operator's with
config/ardupilot-rover.toml), switches it to HOLD in the middle of its N-th move (a foreign mode change: the
companion yields) and hands control back by switching it to GUIDED --hold-for seconds later. Prints one line per thing seen or done; exits when the companion process ends or at --timeout.

Used by scripts/ardupilot-sitl.sh; nothing of ArduPilot is in here.
"""
import argparse
import subprocess
import sys
import time

from pymavlink import mavutil

GUIDED, HOLD = 15, 4


def say(*parts):
    print("[operator]", *parts, flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--vehicle", default="tcp:127.0.0.1:5762")
    ap.add_argument("--mavtempo", required=True, help="the mavtempo binary")
    ap.add_argument("--gcs", default="udpout:127.0.0.1:14551", help="the companion's goal port")
    ap.add_argument("--goals", help="goal file uploaded at --upload-at")
    ap.add_argument("--upload-at", type=float, default=None, help="vehicle seconds since boot")
    ap.add_argument("--hold-move", type=int, default=0, help="HOLD during the N-th move (0: never)")
    ap.add_argument("--hold-after", type=float, default=3.0, help="vehicle seconds into that move")
    ap.add_argument("--hold-for", type=float, default=10.0, help="vehicle seconds before GUIDED again")
    ap.add_argument("--no-arm", action="store_true", help="leave arming to someone else")
    ap.add_argument("--companion-pid", type=int, required=True)
    ap.add_argument("--timeout", type=float, default=1800.0, help="wall seconds")
    a = ap.parse_args()

    deadline = time.time() + a.timeout
    m = None
    while m is None and time.time() < deadline:
        try:
            m = mavutil.mavlink_connection(a.vehicle, source_system=250, source_component=190)
        except OSError:
            time.sleep(0.5)
    if m is None:
        say("no connection to", a.vehicle)
        return 1
    m.wait_heartbeat(timeout=60)
    say("watching", a.vehicle, "sysid", m.target_system)
    uploaded = a.upload_at is None or not a.goals
    moves, moving_since, held = 0, None, a.hold_move == 0
    boot_s, mode, speed = 0.0, None, 0.0
    armed, last_arm, held_at, handed_back = False, -10.0, None, False
    while time.time() < deadline:
        if subprocess.run(["kill", "-0", str(a.companion_pid)], capture_output=True).returncode != 0:
            say("the companion ended")
            return 0
        msg = m.recv_match(blocking=True, timeout=0.5)
        if msg is None:
            continue
        t = msg.get_type()
        if t == "SYSTEM_TIME":
            boot_s = msg.time_boot_ms / 1000.0
        elif t == "HEARTBEAT" and msg.get_srcComponent() == 1:
            mode = msg.custom_mode
            armed = bool(msg.base_mode & mavutil.mavlink.MAV_MODE_FLAG_SAFETY_ARMED)
        elif t == "VFR_HUD":
            speed = msg.groundspeed
        elif t == "CAMERA_FEEDBACK":
            # The picture's evidence: how fast the rover went when the camera fired (the domain wants STILL).
            say(f"t={boot_s:.1f}s capture {msg.img_idx} at {speed:.2f} m/s")
        elif t == "STATUSTEXT" and msg.severity <= 4:
            say(f"t={boot_s:.1f}s autopilot:", msg.text)
        if not a.no_arm and not armed and not held and boot_s - last_arm >= 5.0 and boot_s > 0:
            # The operator arms (ArduPilot refuses for ~20 s after boot; tried every 5 s).
            say(f"t={boot_s:.1f}s arming")
            m.mav.command_long_send(m.target_system, 1,
                                    mavutil.mavlink.MAV_CMD_COMPONENT_ARM_DISARM, 0, 1, 0, 0, 0, 0, 0, 0)
            last_arm = boot_s
        if held_at is not None and not handed_back and boot_s - held_at >= a.hold_for:
            say(f"t={boot_s:.1f}s handing control back: GUIDED")
            m.mav.command_long_send(m.target_system, 1, mavutil.mavlink.MAV_CMD_DO_SET_MODE, 0,
                                    1, GUIDED, 0, 0, 0, 0, 0)
            handed_back = True
        driving = mode == GUIDED and speed > 0.2
        if driving and moving_since is None:
            moves += 1
            moving_since = boot_s
            say(f"t={boot_s:.1f}s move {moves} under way ({speed:.2f} m/s)")
        elif not driving and moving_since is not None and speed < 0.05:
            moving_since = None
        if not held and moves == a.hold_move and moving_since is not None \
                and boot_s - moving_since >= a.hold_after:
            say(f"t={boot_s:.1f}s switching the rover to HOLD in the middle of move {moves}")
            m.mav.command_long_send(m.target_system, 1, mavutil.mavlink.MAV_CMD_DO_SET_MODE, 0,
                                    1, HOLD, 0, 0, 0, 0, 0)
            held, held_at = True, boot_s
        if not uploaded and boot_s >= a.upload_at:
            say(f"t={boot_s:.1f}s uploading {a.goals} to {a.gcs}")
            out = subprocess.run([a.mavtempo, "goal", "send", "--to", a.gcs, "--timeout", "30", a.goals],
                                 capture_output=True, text=True)
            for line in (out.stdout + out.stderr).splitlines():
                say("  ", line)
            uploaded = True
    say("timeout")
    return 1


if __name__ == "__main__":
    sys.exit(main())
