#!/usr/bin/env python3
"""Watches a real ArduPilot Rover SITL (or PX4 SIH rover, --autopilot px4) on a spare port (pymavlink) while
`mavtempo run` drives it, and does what an operator would: uploads a goal file through the companion's
ground-station port once the vehicle's clock reaches a given time, arms the rover once its estimator is ready
(arming is the operator's with config/ardupilot-rover.toml and config/px4-rover.toml), takes control in the
middle of its N-th move (a foreign mode change: the companion yields) and hands control back --hold-for
seconds later. ArduPilot: HOLD, then GUIDED. PX4: the companion's moves run in AUTO/LOITER, which is PX4's
Hold itself, so the operator takes control with Return (AUTO/RTL) and hands it back by switching to Hold.
Prints one line per thing seen or done; exits when the companion process ends or at --timeout.

Used by scripts/ardupilot-sitl.sh and scripts/px4-sitl.sh; nothing of either autopilot is in here.
"""
import argparse
import subprocess
import sys
import time

from pymavlink import mavutil

# DO_SET_MODE (p2, p3) and the custom_mode a heartbeat shows, per autopilot:
# the companion's mode, the operator's "take control" mode, the mode that hands control back.
MODES = {
    "ardupilot": {"guided": 15, "take": (4, 0), "take_name": "HOLD", "back": (15, 0), "back_name": "GUIDED"},
    # PX4 custom_mode = main << 16 | sub << 24; AUTO 4, sub LOITER 3, RTL 5.
    "px4": {"guided": 4 << 16 | 3 << 24, "take": (4, 5), "take_name": "Return",
            "back": (4, 3), "back_name": "Hold"},
}


def say(*parts):
    print("[operator]", *parts, flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--vehicle", default="tcp:127.0.0.1:5762")
    ap.add_argument("--autopilot", choices=sorted(MODES), default="ardupilot")
    ap.add_argument("--mavtempo", required=True, help="the mavtempo binary")
    ap.add_argument("--gcs", default="udpout:127.0.0.1:14551", help="the companion's goal port")
    ap.add_argument("--goals", help="goal file uploaded at --upload-at")
    ap.add_argument("--upload-at", type=float, default=None, help="vehicle seconds since boot")
    ap.add_argument("--hold-move", type=int, default=0, help="HOLD during the N-th move (0: never)")
    ap.add_argument("--hold-after", type=float, default=3.0, help="vehicle seconds into that move")
    ap.add_argument("--hold-for", type=float, default=10.0, help="vehicle seconds before GUIDED again")
    ap.add_argument("--no-arm", action="store_true", help="leave arming to someone else")
    ap.add_argument("--bat-drain", type=float, default=3600.0,
                    help="PX4: SIM_BAT_DRAIN, seconds from full to empty while armed")
    ap.add_argument("--companion-pid", type=int, required=True)
    ap.add_argument("--timeout", type=float, default=1800.0, help="wall seconds")
    a = ap.parse_args()
    modes = MODES[a.autopilot]

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
    if a.autopilot == "px4":
        # PX4's simulated battery empties in SIM_BAT_DRAIN s (60) while armed, linearly, down to
        # SIM_BAT_MIN_PCT (50 %), and reads full again once disarmed (BatterySimulator.cpp): a test rig's
        # setting, not a vehicle's. An hour drains about as the rover domain plans; a copter's pack
        # (--bat-drain 600) empties in 10 minutes of flight, down to 0 %.
        m.mav.param_set_send(m.target_system, 1, b"SIM_BAT_DRAIN", a.bat_drain,
                             mavutil.mavlink.MAV_PARAM_TYPE_REAL32)
        m.mav.param_set_send(m.target_system, 1, b"SIM_BAT_MIN_PCT", 0.0,
                             mavutil.mavlink.MAV_PARAM_TYPE_REAL32)
        say(f"SIM_BAT_DRAIN set to {a.bat_drain:.0f} s, SIM_BAT_MIN_PCT to 0 %")
    uploaded = a.upload_at is None or not a.goals
    moves, moving_since, held = 0, None, a.hold_move == 0
    boot_s, mode, speed, battery = 0.0, None, 0.0, None
    armed, last_arm, held_at, handed_back = False, -10.0, None, False
    last_hb = 0.0
    while time.time() < deadline:
        if time.time() - last_hb >= 1.0:
            # A ground station's heartbeat: PX4 counts a GCS link among its arming checks.
            m.mav.heartbeat_send(mavutil.mavlink.MAV_TYPE_GCS, mavutil.mavlink.MAV_AUTOPILOT_INVALID, 0, 0, 0)
            last_hb = time.time()
        if subprocess.run(["kill", "-0", str(a.companion_pid)], capture_output=True).returncode != 0:
            say("the companion ended")
            return 0
        msg = m.recv_match(blocking=True, timeout=0.5)
        if msg is None:
            continue
        t = msg.get_type()
        if t in ("SYSTEM_TIME", "GLOBAL_POSITION_INT"):
            boot_s = max(boot_s, msg.time_boot_ms / 1000.0)
        elif t == "SYS_STATUS" and (armed or battery is None):
            battery = msg.battery_remaining
        elif t == "HEARTBEAT" and msg.get_srcComponent() == 1:
            mode = msg.custom_mode
            was_armed = armed
            armed = bool(msg.base_mode & mavutil.mavlink.MAV_MODE_FLAG_SAFETY_ARMED)
            if armed != was_armed:
                # The battery at arming and at the disarm (a copter's landing; PX4's simulated battery
                # reads full again once disarmed, so this is the last reading armed).
                say(f"t={boot_s:.1f}s {'armed' if armed else 'disarmed'} in mode {mode}, battery {battery} %")
        elif t == "VFR_HUD":
            speed = msg.groundspeed
        elif t == "CAMERA_FEEDBACK":
            # The picture's evidence: how fast the rover went when the camera fired (the domain wants STILL).
            say(f"t={boot_s:.1f}s capture {msg.img_idx} at {speed:.2f} m/s")
        elif t == "COMMAND_ACK" and msg.result != 0:
            say(f"t={boot_s:.1f}s command {msg.command} answered {msg.result}")
        elif t == "STATUSTEXT" and msg.severity <= 4:
            say(f"t={boot_s:.1f}s autopilot:", msg.text)
        # Before the mission, and after handing control back on PX4 (its Return disarms the rover at home).
        rearm = not held or (a.autopilot == "px4" and handed_back)
        if not a.no_arm and not armed and rearm and boot_s - last_arm >= 5.0 and boot_s > 0:
            # The operator arms (ArduPilot refuses for ~20 s after boot; tried every 5 s).
            if a.autopilot == "px4" and mode is not None and (mode >> 16) & 0xFF == 1:
                # PX4 boots in Manual, which needs a stick (SIH has none): the operator selects Hold first.
                say(f"t={boot_s:.1f}s selecting Hold before arming")
                m.mav.command_long_send(m.target_system, 1, mavutil.mavlink.MAV_CMD_DO_SET_MODE, 0,
                                        1, 4, 3, 0, 0, 0, 0)
            say(f"t={boot_s:.1f}s arming")
            m.mav.command_long_send(m.target_system, 1,
                                    mavutil.mavlink.MAV_CMD_COMPONENT_ARM_DISARM, 0, 1, 0, 0, 0, 0, 0, 0)
            last_arm = boot_s
        if held_at is not None and not handed_back and boot_s - held_at >= a.hold_for:
            say(f"t={boot_s:.1f}s handing control back: {modes['back_name']}")
            m.mav.command_long_send(m.target_system, 1, mavutil.mavlink.MAV_CMD_DO_SET_MODE, 0,
                                    1, *modes["back"], 0, 0, 0, 0)
            handed_back = True
        driving = mode == modes["guided"] and speed > 0.2
        if driving and moving_since is None:
            moves += 1
            moving_since = boot_s
            say(f"t={boot_s:.1f}s move {moves} under way ({speed:.2f} m/s)")
        elif not driving and moving_since is not None and speed < 0.05:
            moving_since = None
        if not held and moves == a.hold_move and moving_since is not None \
                and boot_s - moving_since >= a.hold_after:
            say(f"t={boot_s:.1f}s switching the rover to {modes['take_name']} in the middle of move {moves}")
            m.mav.command_long_send(m.target_system, 1, mavutil.mavlink.MAV_CMD_DO_SET_MODE, 0,
                                    1, *modes["take"], 0, 0, 0, 0)
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
