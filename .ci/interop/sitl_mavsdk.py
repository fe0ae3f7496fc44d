"""Interop (b): MAVSDK (C++ library through its Python binding) uploads a mission with MissionRaw
to `mavtempo sim`, downloads it back, and reads telemetry (position, battery, flight mode).
Usage: python sitl_mavsdk.py PORT"""
import math
import sys
import time

from mavsdk import ComponentType, Configuration, ConnectionResult, Mavsdk
from mavsdk.plugins.mission_raw import MissionItem, MissionRaw, MissionRawError
from mavsdk.plugins.telemetry import Telemetry


def fail(why):
    print(f"MAVSDK interop FAILED: {why}", flush=True)
    sys.exit(1)


def main():
    port = int(sys.argv[1])
    sdk = Mavsdk(Configuration.create_with_component_type(ComponentType.GROUND_STATION))
    result = sdk.add_any_connection(f"tcpout://127.0.0.1:{port}")
    if result != ConnectionResult.SUCCESS:
        fail(f"connection: {result!r}")
    system = sdk.first_autopilot(15.0)
    if system is None:
        fail("no autopilot found")
    print(f"autopilot {system.get_system_id()} connected", flush=True)

    telemetry = Telemetry(system)
    deadline = time.monotonic() + 15
    pos = telemetry.position()
    while not (pos.latitude_deg == pos.latitude_deg and abs(pos.latitude_deg) > 1e-6):
        if time.monotonic() > deadline:
            fail("no position telemetry")
        time.sleep(0.1)
        pos = telemetry.position()
    print(f"position {pos.latitude_deg:.7f}, {pos.longitude_deg:.7f}", flush=True)
    battery = telemetry.battery()
    if not 0.0 < battery.remaining_percent <= 100.0 or not battery.voltage_v > 0.0:
        fail(f"implausible battery telemetry: {battery}")
    print(f"battery {battery.remaining_percent:.0f}% {battery.voltage_v:.2f} V", flush=True)

    lat0, lon0 = pos.latitude_deg, pos.longitude_deg
    def at(north, east):
        return (int(round((lat0 + north / 111319.49) * 1e7)),
                int(round((lon0 + east / (111319.49 * math.cos(math.radians(lat0)))) * 1e7)))
    items = []
    for seq, (north, east) in enumerate([(0, 0), (25, 0), (25, 25), (0, 25)]):
        x, y = at(north, east)
        items.append(MissionItem(seq=seq, frame=3, command=16, current=1 if seq == 0 else 0,
                                 autocontinue=1, x=x, y=y, z=0.0, mission_type=0))
    raw = MissionRaw(system)
    try:
        raw.upload_mission(items)
        print("mission uploaded", flush=True)
        downloaded = raw.download_mission()
    except MissionRawError as e:
        fail(f"mission transfer: {e}")
    print(f"downloaded {len(downloaded)} items", flush=True)
    if len(downloaded) != len(items):
        fail(f"downloaded {len(downloaded)} items, uploaded {len(items)}")
    for a, b in zip(items[1:], downloaded[1:]):
        if (a.x, a.y, a.command) != (b.x, b.y, b.command):
            fail(f"item {a.seq} differs after the round trip")
    mode = telemetry.flight_mode()
    print(f"flight mode {mode}", flush=True)
    print("MAVSDK interop OK", flush=True)


if __name__ == "__main__":
    main()
