#!/usr/bin/env python3
"""Live walk commands end to end (issue 30 item 5): ohrp_run runs scenarios/walk_live.yaml paced
to the wall clock; this client connects to the walk's socket, sends "velocity 0.2 0 0" (until
told) once the robot stands, and "stop" 4 s later. Passes when both are answered "ok", the run's
checks pass, the base went at least 0.15 m forward (a simulation slowed by a loaded machine walks
less of those 4 s), and the walk reports done, standing, with the
live commands counted. Usage: walk_live_test.py RUNNER SCENARIO OUT_DIR"""
import csv
import json
import os
import socket
import subprocess
import sys
import time


def fail(why):
    print("walk_live_test: FAIL: " + why)
    sys.exit(1)


def main():
    runner, scenario, out = sys.argv[1:4]
    sock_path = os.path.join(out, "walk.sock")
    if os.path.exists(sock_path):
        os.unlink(sock_path)
    run = subprocess.Popen([runner, scenario, "--out", out, "--realtime", "--quiet", "--no-plot"])
    deadline = time.time() + 10
    while not os.path.exists(sock_path):
        if time.time() > deadline or run.poll() is not None:
            run.kill()
            fail("the walk's socket never appeared at " + sock_path)
        time.sleep(0.05)
    client = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    client.connect(sock_path)
    lines = client.makefile("rw")

    def send(command):
        lines.write(command + "\n")
        lines.flush()
        answer = lines.readline().strip()
        print("walk_live_test: %r -> %r" % (command, answer))
        if not answer.startswith("ok"):
            run.kill()
            fail("%r was answered %r" % (command, answer))

    time.sleep(3.0)  # the stand-up (ramp 1 s) and the start of the walk
    send("velocity 0.2 0 0")
    time.sleep(4.0)
    send("stop")
    client.close()
    if run.wait(timeout=60) != 0:
        fail("ohrp_run exited %d (see %s)" % (run.returncode, out))
    with open(os.path.join(out, "log.csv")) as f:
        rows = list(csv.DictReader(f))
    moved = float(rows[-1]["base_x"]) - float(rows[0]["base_x"])
    if moved < 0.15:
        fail("the base moved %.3f m forward, less than 0.15 m" % moved)
    with open(os.path.join(out, "walk.stderr")) as f:
        report = f.read()
    if "done, standing on both feet" not in report or "live: 2 received, 0 refused" not in report:
        fail("the walk's report does not say done with 2 live commands:\n" + report)
    print("walk_live_test: pass: the base moved %.3f m; %s" % (moved, json.dumps(
        [l for l in report.splitlines() if l.startswith("walk: done")])))


if __name__ == "__main__":
    main()
