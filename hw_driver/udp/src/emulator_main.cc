// hw_emulator: the robot's boards on loopback UDP, a MuJoCo robot behind them (see emulator.h).
#include "cli/command_line.h"
#include "emulator.h"

int main(int argc, char** argv) {
  ohrp::hw::udp::EmulatorOptions o;
  CLI::App app{
      "hw_emulator: plays the robot's motor and sensor boards on UDP (protocol:\n"
      "hw_driver/udp/PROTOCOL.md) with a MuJoCo model of the robot running in real time behind\n"
      "them, so that hw_driver (--io lib/libohrp_io_udp.so) runs without the robot. Servos start\n"
      "off; the robot's time starts with the first command packet. Faults can be injected from\n"
      "the command line and, while running, through --control FILE."};
  app.add_option("--model,model", o.model, "MJCF scene, OpenHRP VRML (.wrl), URDF or a robot profile (.yaml) (e.g. mjcf/hrp1s/scene_flat.xml)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("--keyframe", o.keyframe, "initial state: a keyframe of the scene");
  app.add_option("--host", o.host, "IPv4 address to bind")->capture_default_str();
  app.add_option("--port", o.port, "UDP port of the boards (0: any free port, see --port-file)")
      ->capture_default_str()->check(ohrp::cli::InRange(0, 65535));
  app.add_option("--port-file", o.port_file, "write the bound port to this file once bound");
  app.add_option("--boards", o.boards,
                 "motor boards' joint ranges, e.g. 0-5,6-12,13-18,19-25,26-28 (default: limb "
                 "groups from the joint names); the sensor board comes after them");
  app.add_option("--period", o.period, "board cycle [s], a multiple of the model's timestep")
      ->capture_default_str()->check(ohrp::cli::Positive());
  app.add_option("--timestep", o.timestep, "physics step [s] (default: the model's)")
      ->check(ohrp::cli::Positive());
  app.add_option("--contact", o.contact,
                 "under the soles, chosen as sim_host chooses it: soft (the paper's "
                 "spring-dampers), native (MuJoCo's, as the scene defines it), rigid, auto (soft "
                 "when the model has *_SOLE geoms that collide, else native: a robot profile's "
                 "contact: key decides)")
      ->capture_default_str()->check(CLI::IsMember({"soft", "native", "rigid", "auto"}));
  app.add_option("--contact-file", o.contact_file,
                 "soft: the soles' parameters from a file (as sim_host --contact-file); "
                 "--contact-stiffness/--contact-damping given as well win; default: a robot "
                 "profile's contact_file")
      ->check(CLI::ExistingFile);
  app.add_option("--contact-stiffness", o.contact_stiffness,
                 "soft: normal stiffness of one sole [N/m] (default: sim_host's)")
      ->check(ohrp::cli::Positive());
  app.add_option("--contact-damping", o.contact_damping,
                 "soft: Hunt-Crossley damping [s/m] (default: sim_host's)")
      ->check(ohrp::cli::NonNegative());
  app.add_option("--push", o.pushes,
                 "T0,T1,FX,FY,FZ,TX,TY,TZ: a wrench on the base from robot time T0 to T1 [s, N, "
                 "N m], as sim_host --push (repeat)");
  app.add_option("--duration", o.duration, "robot time to run [s]; 0 runs until Ctrl-C")
      ->capture_default_str()->check(ohrp::cli::NonNegative());
  app.add_option("--wait-driver", o.wait_driver,
                 "wall time to wait for the first command [s]; 0 waits for ever")
      ->capture_default_str()->check(ohrp::cli::NonNegative());
  app.add_option("--loss", o.loss, "probability that a packet is lost, either direction")
      ->capture_default_str()->check(ohrp::cli::InRange(0.0, 1.0));
  app.add_option("--late", o.late_rate, "fraction of state packets sent late")
      ->capture_default_str()->check(ohrp::cli::InRange(0.0, 1.0));
  app.add_option("--late-ms", o.late_ms, "how late [ms]")->capture_default_str()
      ->check(ohrp::cli::NonNegative());
  app.add_option("--seed", o.seed, "seed of the loss and late draws and of the sensors' noise")->capture_default_str();
  app.add_option("--silent", o.silent, "BOARD@T[+D]: the board stops answering at robot time T [s]");
  app.add_option("--reset", o.reset, "BOARD@T: the board restarts at T (its servos go off)");
  app.add_option("--stuck", o.stuck, "SENSOR@T: ft0..ft3 or imu0.. repeats its value from T on");
  app.add_option("--saturate", o.saturate, "SENSOR@T: the sensor reads the end of its range from T");
  app.add_option("--estop", o.estop, "T[+D]: the emergency stop is pressed at T (all servos off)");
  app.add_option("--value", o.values,
                 "JOINT=X@T[+D]: joint JOINT's board reads X (nan, inf, 1e300, ...) as its position "
                 "from robot time T [s] (for D seconds)");
  app.add_option("--hold-ms", o.hold_ms,
                 "a motor board without a valid command this long [ms] holds its joints where "
                 "they are (position hold, the model's default gains) until the next command")
      ->capture_default_str()->check(ohrp::cli::InRange(1.0, 10000.0));
  app.add_option("--control", o.control_file,
                 "file of fault commands read while running, one per appended line: loss P | "
                 "late P MS | silent B | talk B | reset B | stuck S | saturate S | sensor-ok S | "
                 "estop on|off | value J X | value off | clear");
  // the robot unlike the model (plant_gap.h), for identification (docs/identify.md)
  app.add_option("--friction", o.gap.friction,
                 "JOINT|all=COULOMB,VISCOUS: the joint's Coulomb friction [N m] and viscous "
                 "friction [N m s/rad] (MuJoCo frictionloss and damping, replacing the model's); "
                 "JOINT a name or index; repeat, later ones override (all=..., then one joint)");
  app.add_option("--armature", o.gap.armature,
                 "JOINT|all=X: rotor inertia X [kg m^2] added to the joint's armature (repeat)");
  app.add_option("--delay-ms", o.gap.delay_ms,
                 "actuator delay [ms]: the motor boards apply each command this long after it "
                 "arrives (a whole number of --period); e-stop, resets and holds act at once")
      ->capture_default_str();
  app.add_option("--encoder-bias", o.gap.encoder_bias,
                 "JOINT|all=X: the joint's encoder reads q + X [rad], and the board's PD acts on "
                 "what it reads (repeat)");
  app.add_option("--encoder-noise", o.gap.encoder_noise,
                 "white noise std [rad] on every reported joint position (the PD's reading is "
                 "noise-free)")->capture_default_str();
  app.add_option("--imu-bias", o.gap.imu_bias,
                 "G,A or GX,GY,GZ,AX,AY,AZ: bias added to the IMUs' rates [rad/s] and "
                 "accelerations [m/s^2]");
  app.add_option("--imu-noise", o.gap.imu_noise,
                 "G,A: white noise std on each IMU rate [rad/s] and acceleration [m/s^2] axis");
  app.add_option("--ft-noise", o.gap.ft_noise,
                 "F,T: white noise std on each F/T force [N] and torque [N m] axis");
  app.add_option("--ft-bias", o.gap.ft_bias,
                 "F,T or FX,FY,FZ,TX,TY,TZ: offset added to every F/T sensor's force [N] and "
                 "torque [N m] (in the sensor's frame)");
  app.add_option("--sensor-file", o.gap.sensor_file,
                 "the sensors as identified (ohrp identify --sensors' sensors.yaml, sim_host "
                 "--sensor-file's format: encoder bias and noise, velocity, torque and orientation "
                 "noise, IMU and F/T bias and noise per sensor), through sim_host's sensor model; "
                 "added to the options above")->check(CLI::ExistingFile);
  app.add_option("--log", o.log_path,
                 "CSV log: robot time, base height and tilt, servos, faults, base x, y and yaw");
  app.add_option("--log-every", o.log_every, "cycles between log rows")->capture_default_str()
      ->check(ohrp::cli::Positive());
  app.add_flag("--quiet,-q", o.quiet, "print errors and the result line only");
  app.footer(
      "Exit codes: 0 completed, 2 bad option, model or port, 3 MuJoCo error, 4 the simulation\n"
      "diverged, 5 no driver within --wait-driver, 130 interrupted (SIGINT/SIGTERM).\n"
      "The last line on stderr is 'hw_emulator: result key=value ...' (base height, losses).");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  return ohrp::hw::udp::RunEmulator(o);
}
