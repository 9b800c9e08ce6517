#!/usr/bin/env python3
"""Live reach goals end to end (issue 34 item 2): ohrp_run runs scenarios/reach_live.yaml paced to
the wall clock; this client connects to reach's socket once the robot stands and sends a joints
goal (the left arm forward over the box), a goal in collision with the body and an unknown
command (both must be refused with the reason), then a hand pose in front of the chest. Passes
when the two goals are answered "ok: goal 1 queued" / "ok: goal 2 queued", the refusals
"error: ...", the run's checks pass, reach reports both goals done with the live counts, and its
plan log holds both goals. Usage: reach_live_test.py RUNNER SCENARIO OUT_DIR"""
import os
import socket
import subprocess
import sys
import time


def fail(why, run=None):
    if run is not None and run.poll() is None:
        run.kill()
    print("reach_live_test: FAIL: " + why)
    sys.exit(1)


def main():
    runner, scenario, out = sys.argv[1:4]
    sock_path = os.path.join(out, "reach.sock")
    if os.path.exists(sock_path):
        os.unlink(sock_path)
    run = subprocess.Popen([runner, scenario, "--out", out, "--realtime", "--quiet", "--no-plot"])
    deadline = time.time() + 15
    while not os.path.exists(sock_path):
        if time.time() > deadline or run.poll() is not None:
            fail("reach's socket never appeared at " + sock_path, run)
        time.sleep(0.05)
    client = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    client.connect(sock_path)
    lines = client.makefile("rw")

    def send(command, want):
        lines.write(command + "\n")
        lines.flush()
        answer = lines.readline().strip()
        print("reach_live_test: %r -> %r" % (command, answer))
        if not answer.startswith(want):
            fail("%r was answered %r, not %r..." % (command, answer, want), run)
        return answer

    time.sleep(1.0)  # standing up
    send("joints LARM_SHOULDER_P=-1.1,LARM_SHOULDER_R=0,LARM_SHOULDER_Y=0,LARM_ELBOW=0", "ok: goal 1 queued")
    # the left forearm turned into the chest: in collision in the stance pose
    refused = send("joints LARM_SHOULDER_P=-0.6,LARM_SHOULDER_R=-0.2,LARM_SHOULDER_Y=-1.3,LARM_ELBOW=-2.5",
                   "error: joints: ")
    send("wave", "error: \"wave\": unknown command")
    send("pose lhsensor,0.20,-0.05,0.25", "ok: goal 2 queued")
    client.close()
    if run.wait(timeout=90) != 0:
        fail("ohrp_run exited %d (see %s)" % (run.returncode, out))
    with open(os.path.join(out, "reach.stderr")) as f:
        report = f.read()
    for want in ("reach: live: 4 received, 2 refused, 2 taken", "reach: goal 1/2 (live: joints",
                 "reach: goal 2/2 (live: pose lhsensor"):
        if want not in report:
            fail("reach's report lacks %r:\n%s" % (want, report))
    if "not done when the run ended" in report:
        fail("a goal was not done:\n" + report)
    with open(os.path.join(out, "plan.csv")) as f:
        first = f.readline().strip()
    if first != "# reach plan: goal 1: solved; goal 2: solved":
        fail("the plan log's first line is %r" % first)
    print("reach_live_test: pass (%s)" % refused)


if __name__ == "__main__":
    main()
