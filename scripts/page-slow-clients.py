#!/usr/bin/env python3
"""Slow clients against the live page (issue 31): runs `mavtempo demo --speedup 10 --http 127.0.0.1:0` under
`ulimit -n 1024`, opens N connections that each send an unfinished request head and nothing more, samples the
demo's open descriptors (/proc/PID/fd) every 0.2 s until the mission is over, then counts the clients the
page closed. Usage: python3 scripts/page-slow-clients.py target/release/mavtempo 1000
"""
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

exe, n = sys.argv[1], int(sys.argv[2])
report = os.path.join(tempfile.mkdtemp(), "report.json")
demo = subprocess.Popen(
    ["bash", "-c", f"ulimit -n 1024; exec {exe} demo --quiet --speedup 10 --no-upload "
                   f"--http 127.0.0.1:0 --report {report}"],
    stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
url = None
deadline = time.time() + 60
while url is None and time.time() < deadline:
    line = demo.stdout.readline()
    if line.startswith("http listening on http://"):
        url = line.split("http://")[1].strip().rstrip("/")
if url is None:
    sys.exit("the demo did not serve its page")
lines = []
threading.Thread(target=lambda: [lines.append(l) for l in demo.stdout], daemon=True).start()
host, port = url.split(":")
socks = []
for _ in range(n):
    s = socket.create_connection((host, int(port)), timeout=5)
    s.sendall(b"GET / HTTP/1.1\r\nX-Slow: ")
    socks.append(s)
most = 0
start = time.time()
while demo.poll() is None and time.time() - start < 300 and not any("mission over" in l for l in lines):
    most = max(most, len(os.listdir(f"/proc/{demo.pid}/fd")))
    time.sleep(0.2)
closed = 0
for s in socks:
    s.setblocking(False)
    try:
        closed += s.recv(1) == b""
    except BlockingIOError:
        pass
    except OSError:
        closed += 1
demo.send_signal(signal.SIGTERM)
demo.communicate(timeout=60)
ended = [l.strip() for l in lines if l.startswith("mission ended")]
print(f"most descriptors open in the demo: {most}; clients closed by the page: {closed}/{n}; "
      f"{ended[0] if ended else 'no mission end'}; report written: {os.path.exists(report)}")
