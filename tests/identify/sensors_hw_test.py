#!/usr/bin/env python3
"""The sensors identified through the hardware path (issue 35): hw_emulator --sensor-file ->
UDP -> hw_driver --log --log-dq --log-time board -> ohrp identify --sensors.

The "robot" is HRP-1S standing half-sitting on hw_emulator (2 ms board cycle, real time), whose
sensors read through the sensor file this test writes (robot_model/sensor_params.h, the format
sim_host --sensor-file takes, applied by the same model::ApplySensorModel): velocity, torque and
encoder noise on four joints, the IMU's gyro and accelerometer bias and noise and its orientation
noise, the right ankle F/T sensor's noise. hw_driver (posture holding the robot) logs what the
boards report, each row at the boards' timestamp, a cycle without new board data not logged.
`ohrp identify --sensors` on the still window must recover each value within K stated standard
errors computed here from the truth and the sample count, not taken from the estimate:

    noise (std) of one channel      sigma / sqrt(2 (N - W))    (N rows, W = 51: the moving
                                                                average's edges and the fit's
                                                                few degrees of freedom)
    orientation noise, 3 axes pooled sigma / sqrt(6 (N - W))
    a bias (a mean)                  sigma / sqrt(N - W)        (the accelerometer's x and y:
                                                                sigma and g sigma_orientation in
                                                                quadrature, R^T g from the noisy
                                                                logged orientation)

Also: the log's time is the boards' (increasing, steps whole 2 ms cycles), the joints the file
does not name read next to noise-free (below 5 % of the smallest noise set), and a sensor file naming a sensor the
robot does not have stops hw_emulator with exit 2 before it binds.

Usage: sensors_hw_test.py BIN_DIR SOURCE_DIR OUT_DIR [SEED]
"""
import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import time

BIN, SRC, OUT = sys.argv[1], sys.argv[2], sys.argv[3]
SEED = sys.argv[4] if len(sys.argv) > 4 else "1"  # hw_emulator --seed: the noise's draws
K = 4.0
W = 51  # identify's moving average (sensors.json "moving_average")
PERIOD = 0.002
DURATION = 5.5               # driver time [s]
WINDOW = (2.5, DURATION - 0.5)  # still: after posture's take-over has settled, before the stop
SCENE = os.path.join(SRC, "mjcf/hrp1s/scene_flat.xml")
ENCODER = {"RLEG_KNEE": 2e-4, "LLEG_KNEE": 5e-4, "RARM_ELBOW": 1e-4, "WAIST_P": 3e-4}
VELOCITY = {"RLEG_KNEE": 2e-3, "LLEG_KNEE": 5e-3, "RARM_ELBOW": 1e-3, "WAIST_P": 3e-3}
TORQUE = {"RLEG_KNEE": 0.5, "LLEG_KNEE": 0.2, "RARM_ELBOW": 0.05, "WAIST_P": 1.0}
GYRO_BIAS, GYRO_NOISE = [0.01, -0.02, 0.005], [0.003, 0.004, 0.002]
ACCEL_BIAS, ACCEL_NOISE = [0.05, -0.1, 0.2], [0.03, 0.02, 0.04]
ORIENTATION = 1e-3  # 2e-3 was refused once: its moving average spanned 8.2 of its own sigma (docs)
FT_NOISE = [2.0, 1.5, 3.0, 0.1, 0.2, 0.05]
G = 9.81
failures = []


def check(ok, what):
    print(("ok      " if ok else "FAILED  ") + what)
    if not ok:
        failures.append(what)


def write_truth(path, imu="imu"):
    lines = ["encoders:"]
    lines += ["  %s: {noise: %g, velocity_noise: %g, torque_noise: %g}" % (j, s, VELOCITY[j], TORQUE[j])
              for j, s in ENCODER.items()]
    lines += ["imus:", "  %s: {gyro_bias: %s, gyro_noise: %s, accel_bias: %s, accel_noise: %s, "
              "orientation_noise: %g}" % (imu, GYRO_BIAS, GYRO_NOISE, ACCEL_BIAS, ACCEL_NOISE, ORIENTATION)]
    lines += ["force_torque:", "  rfsensor: {noise: %s}" % FT_NOISE]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def wait(p, timeout):
    try:
        return p.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        p.kill()
        return p.wait()


def record(truth, log):
    """emulator, driver and posture; returns (driver exit, emulator exit, outputs)"""
    port_file = os.path.join(OUT, "port")
    if os.path.exists(port_file):
        os.remove(port_file)
    out = {n: open(os.path.join(OUT, n + ".out"), "w") for n in ("emu", "driver", "posture")}
    emu = subprocess.Popen([os.path.join(BIN, "hw_emulator"), "--model", SCENE, "--keyframe", "halfsit",
                            "--port", "0", "--port-file", port_file, "--wait-driver", "60",
                            "--period", str(PERIOD), "--sensor-file", truth, "--seed", SEED],
                           stdout=out["emu"], stderr=subprocess.STDOUT)
    port = None
    for _ in range(3000):
        if emu.poll() is not None:
            break
        try:
            port = int(open(port_file).read())
            break
        except (OSError, ValueError):
            time.sleep(0.01)
    if port is None:
        wait(emu, 5)
        return None, emu.returncode
    segment = "idhw_sensors_hw_%d" % os.getpid()
    driver = subprocess.Popen(
        [os.path.join(BIN, "hw_driver"), "--model", SCENE, "--io", os.path.join(BIN, "../lib/libohrp_io_udp.so"),
         "--io-arg", "port=%d" % port, "--io-arg", "timeout_ms=1000", "--segment", segment,
         "--period", str(PERIOD), "--watchdog-cycles", "500", "--board-timeout-cycles", "500",
         "--rt-priority", "0", "--no-mlock", "--duration", str(DURATION), "--log", log, "--log-dq",
         "--log-time", "board"], stdout=out["driver"], stderr=subprocess.STDOUT)
    for _ in range(3000):
        if driver.poll() is not None or any(segment in f for f in os.listdir("/dev/shm")):
            break
        time.sleep(0.01)
    posture = subprocess.Popen([os.path.join(BIN, "posture"), "--segment", segment, "--ramp", "0"],
                               stdout=out["posture"], stderr=subprocess.STDOUT)
    d = wait(driver, DURATION + 60)
    wait(posture, 30)
    emu.send_signal(signal.SIGINT)
    wait(emu, 30)
    return d, emu.returncode


def main():
    os.makedirs(OUT, exist_ok=True)
    # a sensor the robot does not have: refused before anything runs
    bad = write_truth(os.path.join(OUT, "bad.yaml"), imu="no_such_imu")
    r = subprocess.run([os.path.join(BIN, "hw_emulator"), "--model", SCENE, "--port", "0",
                        "--sensor-file", bad], capture_output=True, text=True, timeout=60)
    check(r.returncode == 2 and "no_such_imu" in r.stderr and "it has: imu" in r.stderr,
          "a file naming no_such_imu: exit %d, %s" % (r.returncode, r.stderr.strip()[-160:]))

    truth = write_truth(os.path.join(OUT, "truth.yaml"))
    log = os.path.join(OUT, "robot.csv")
    out = os.path.join(OUT, "identified")
    # real time on a shared machine: a stall of the driver longer than the boards' hold time (50
    # ms) makes the boards hold (the emulator's holds=N) and jolts the robot, whose window is then
    # refused as moving; that is the machine's, not what is tested: such a run is run again
    for attempt in range(3):
        d, _ = record(truth, log)
        check(d == 0, "hw_driver exit %s (%s)" % (d, os.path.join(OUT, "driver.out")))
        if d != 0:
            return
        r = subprocess.run([os.path.join(BIN, "ohrp_identify"), log, "--sensors", "--from", str(WINDOW[0]),
                            "--to", str(WINDOW[1]), "--out", out], capture_output=True, text=True, timeout=120)
        holds = re.search(r"holds=(\d+)", open(os.path.join(OUT, "emu.out")).read())
        if r.returncode == 2 and "moves" in r.stderr and holds and int(holds.group(1)) > 0:
            print("run %d: the boards held %s times (the machine stalled the driver): %s; again"
                  % (attempt + 1, holds.group(1), r.stderr.strip()))
            continue
        break
    rows = list(csv.DictReader(open(log)))
    t = [float(x["time"]) for x in rows]
    steps = [b - a for a, b in zip(t, t[1:])]
    cycles = [s / PERIOD for s in steps]
    check(all(s > 0 for s in steps) and all(abs(c - round(c)) < 1e-6 for c in cycles),
          "log time is the boards': %d rows, increasing, in whole %g ms cycles (%.0f %% one cycle)"
          % (len(t), PERIOD * 1e3, 100.0 * sum(1 for c in cycles if round(c) == 1) / max(1, len(cycles))))
    check("dq_RLEG_KNEE" in rows[0], "the log has dq_ columns (--log-dq)")
    print(r.stdout)
    check(r.returncode == 0, "ohrp_identify --sensors exit %d %s" % (r.returncode, r.stderr.strip()))
    if r.returncode != 0:
        return
    j = json.load(open(os.path.join(out, "sensors.json")))
    n = j["samples"]
    rows_in = sum(1 for x in t if WINDOW[0] <= x <= WINDOW[1])
    check(n == rows_in, "identify took the %d rows of the window (%d)" % (n, rows_in))
    dof = n - W

    def near(what, value, true, se):
        z = (value - true) / se
        check(abs(z) <= K, "%-28s %.6g against %.6g: %+.2f of the stated se %.3g" % (what, value, true, z, se))

    joints = {x["joint"]: x for x in j["joints"]}
    for name in ENCODER:
        x = joints[name]
        near(name + " encoder noise", x["encoder_noise"]["value"], ENCODER[name], ENCODER[name] / math.sqrt(2 * dof))
        near(name + " velocity noise", x["velocity_noise"]["value"], VELOCITY[name], VELOCITY[name] / math.sqrt(2 * dof))
        near(name + " torque noise", x["torque_noise"]["value"], TORQUE[name], TORQUE[name] / math.sqrt(2 * dof))
    clean = [x for name, x in joints.items() if name not in ENCODER]
    worst_v = max(x["velocity_noise"]["value"] for x in clean)
    worst_t = max(x["torque_noise"]["value"] for x in clean)
    # the robot's own motion beyond the fit: up to 1e-5 rad/s and 6e-4 N m on a loaded machine
    floor_v, floor_t = 0.05 * min(VELOCITY.values()), 0.05 * min(TORQUE.values())
    check(worst_v < floor_v and worst_t < floor_t,
          "the %d joints without noise: velocity noise <= %.3g rad/s, torque noise <= %.3g N m "
          "(below 5 %% of the smallest set: %.3g, %.3g)" % (len(clean), worst_v, worst_t, floor_v, floor_t))
    u = j["imus"][0]
    for k, axis in enumerate("xyz"):
        near("gyro bias " + axis, u["gyro_bias_" + axis]["value"], GYRO_BIAS[k], GYRO_NOISE[k] / math.sqrt(dof))
        near("gyro noise " + axis, u["gyro_noise_" + axis]["value"], GYRO_NOISE[k], GYRO_NOISE[k] / math.sqrt(2 * dof))
        near("accel noise " + axis, u["accel_noise_" + axis]["value"], ACCEL_NOISE[k], ACCEL_NOISE[k] / math.sqrt(2 * dof))
        # the bias is the mean less R^T g at each row's logged orientation, whose noise moves the
        # horizontal axes by g sigma_o: the mean's std is that and the accelerometer's together
        tilt = G * ORIENTATION if axis != "z" else 0.0
        near("accel bias " + axis, u["accel_bias_" + axis]["value"], ACCEL_BIAS[k],
             math.hypot(ACCEL_NOISE[k], tilt) / math.sqrt(dof))
    near("orientation noise (pooled)", u["orientation_noise"]["value"], ORIENTATION, ORIENTATION / math.sqrt(6 * dof))
    f = {x["name"]: x for x in j["force_torque"]}["rfsensor"]
    for k, axis in enumerate(("fx", "fy", "fz", "tx", "ty", "tz")):
        near("rfsensor noise " + axis, f["noise_" + axis]["value"], FT_NOISE[k], FT_NOISE[k] / math.sqrt(2 * dof))


if __name__ == "__main__":
    started = time.time()
    main()
    print("%.1f s" % (time.time() - started))
    if failures:
        print("%d FAILED" % len(failures))
        sys.exit(1)
    print("all passed")
