// sim_host's command line (see command_line.h). The options a scenario can set are registered from
// their table (cli/host_options.h: name, range, help); the others are written here.
#include "command_line.h"

#include <cstdio>

#include "cli/command_line.h"
#include "cli/host_options.h"
#include "robot_model/profile.h"
#include "sim_host/contact_choice.h"

namespace ohrp::sim {
namespace {

// the scene, the segment, the initial state and the steps
void AddModelOptions(CLI::App* app, HostOptions* o) {
  app->add_option("--scene,scene", o->scene, "MJCF scene file, OpenHRP VRML (.wrl, read directly), URDF, or a robot profile (.yaml, docs/robots.md) (e.g. mjcf/hrp1s/scene_flat.xml, mjcf/hrp1s/scene_bush.wrl, robots/g1.yaml)")
      ->required()->check(CLI::ExistingFile);
  app->add_option("--segment", o->segment, "segment name the controller attaches to")
      ->capture_default_str();
  ohrp::cli::AddTableOption(app, "keyframe", &o->keyframe);
  ohrp::cli::AddTableOption(app, "physics_dt", &o->physics_dt);
  ohrp::cli::AddTableOption(app, "control_period", &o->control_period);
  ohrp::cli::AddTableOption(app, "integrator", &o->integrator);
}

// the contact under the soles and the soft soles' parameters
void AddContactOptions(CLI::App* app, HostOptions* o, RawHostOptions* r) {
  ohrp::cli::AddTableOption(app, "contact", &r->contact);
  app->add_option("--soles", o->feet.soles, "sole geoms (default: every geom named *_SOLE)")
      ->delimiter(',');
  auto& cp = o->feet.params;
  app->add_option("--contact-stiffness", cp.stiffness, "soft: normal stiffness of one sole [N/m^n]")
      ->capture_default_str();
  app->add_option("--contact-exponent", cp.exponent, "soft: force ~ k delta^n, n in [1, 3]")
      ->capture_default_str()->check(ohrp::cli::InRange(1, 3));
  app->add_option("--contact-damping", cp.damping, "soft: Hunt-Crossley damping [s/m]")
      ->capture_default_str();
  app->add_option("--contact-friction", cp.friction, "soft: Coulomb friction coefficient")
      ->capture_default_str()->check(ohrp::cli::Plausible("friction"));
  app->add_option("--contact-tangential-stiffness", cp.tangential_stiffness,
                 "soft: shear stiffness of one sole while it sticks [N/m]")
      ->capture_default_str()->check(ohrp::cli::Plausible("sole_stiffness"));
  app->add_option("--contact-tangential-damping", cp.tangential_damping,
                 "soft: shear damping of one sole while it sticks [N s/m]")
      ->capture_default_str()->check(ohrp::cli::Plausible("sole_damping"));
  app->add_option("--contact-file", o->contact_file,
                 "soft: the soles' parameters from a file (contact_params: {stiffness: ..., "
                 "damping: ...}, as `ohrp identify` writes DIR/soles.yaml); a --contact-* option "
                 "given as well wins; default: a robot profile's contact_file")
      ->check(CLI::ExistingFile);
}

// the joints and sensors as identified
void AddIdentifiedOptions(CLI::App* app, HostOptions* o) {
  app->add_option("--joint-file", o->joint_file,
                 "the joints as identified (joints: {NAME: {armature: ..., damping: ..., "
                 "frictionloss: ...}}, as `ohrp identify --joints --model ...` writes "
                 "DIR/joints.yaml): replace the model's values of those joints; default: a robot "
                 "profile's joint_file")
      ->check(CLI::ExistingFile);
  app->add_option("--sensor-file", o->sensor_file,
                 "the sensors as identified (encoders: {NAME: {bias: ..., noise: ...}}, imus: "
                 "{NAME: {gyro_bias: [3], gyro_noise: [3], accel_bias: [3], accel_noise: [3]}}, "
                 "force_torque: {NAME: {bias: [6], noise: [6]}}, as `ohrp identify --sensors` "
                 "writes DIR/sensors.yaml): each reading gets its bias and white noise; a position "
                 "reference is taken in the biased encoder's frame; default: a robot profile's "
                 "sensor_file")
      ->check(CLI::ExistingFile);
  app->add_option("--sensor-seed", o->sensor_seed,
                 "the seed of --sensor-file's noise (same seed, same noise; in the summary)")
      ->capture_default_str();
}

// pushes, the control channel, timing and the controller's loss
void AddRunOptions(CLI::App* app, HostOptions* o, RawHostOptions* r) {
  ohrp::cli::AddTableOption(app, "pushes", &r->pushes)
      ->expected(1)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app->add_option("--control-socket", o->control_socket,
                 "a local stream socket for control lines (pause, resume, step [N], reset "
                 "[KEYFRAME], push BODY FX FY FZ DURATION, status), applied between control cycles "
                 "and recorded in actions.jsonl beside --summary (docs/architecture.md \"Control "
                 "channel\"); default: none");
  ohrp::cli::AddTableOption(app, "duration", &o->duration);
  ohrp::cli::AddTableOption(app, "realtime", &o->realtime);
  app->add_option("--wait-controller", o->wait_controller,
                 "wall time to wait for the first controller [s]; 0 runs without one (joints hold)")
      ->capture_default_str()->check(ohrp::cli::InRange(0, 0) | ohrp::cli::Plausible("timeout"));
  ohrp::cli::AddTableOption(app, "controller_timeout", &o->controller_timeout);
  ohrp::cli::AddTableOption(app, "on_controller_loss", &r->loss);
}

// the data log, the summary and progress
void AddOutputOptions(CLI::App* app, HostOptions* o, RawHostOptions* r) {
  app->add_option("--log", o->log_path,
                 "CSV data log (base pose, joints, F/T, IMU per cycle), checked writable before "
                 "the run; a failed write (disk full...) ends the run with exit code 9");
  app->add_flag("--log-dq", o->log_dq,
               "the data log also records each joint's velocity as the controller reads it "
               "(dq_<joint>, after tau_: ohrp identify --sensors estimates its noise)");
  ohrp::cli::AddTableOption(app, "log_every", &o->log_every);
  app->add_option("--log-max", r->log_max,
                 "bound on the data log's size: bytes, or with k, M, G (e.g. 50M); the rows past "
                 "it are not written, and the report and summary say how many (the log keeps the "
                 "run's start; about 0.31 MB per simulated second with HRP-1S's columns)");
  app->add_option("--summary", o->summary_path,
                 "JSON summary written at the end (checked writable before the run; says "
                 "\"running\" until the end)");
  app->add_option("--progress", o->progress, "wall seconds between progress lines; 0: none")
      ->capture_default_str()->check(ohrp::cli::InRange(0, 0) | ohrp::cli::Plausible("timeout"));
  app->add_flag("--quiet,-q", o->quiet, "print errors only");
  ohrp::cli::AddTableOption(app, "on_fall", &r->on_fall);
  ohrp::cli::AddTableOption(app, "fall_allow_contact", &o->fall.allow_contact);
}

// effects, self-collision, cameras, --explain
void AddEffectOptions(CLI::App* app, HostOptions* o, RawHostOptions* r) {
  ohrp::cli::AddTableOption(app, "effects", &r->effects);
  app->add_option("--self-collision", o->self_collision_file,
                 "check the robot's link pairs listed in this file of ohrp_selfcollision every "
                 "control cycle and report those in contact after the run (switches the "
                 "self_collision effect on; without it, self_collision=on checks every "
                 "non-adjacent pair; docs/selfcollision.md)")
      ->check(CLI::ExistingFile);
  ohrp::cli::AddTableOption(app, "camera_rate", &o->cameras.rate);
  app->add_option("--camera-size", r->camera_size,
                 "size WIDTHxHEIGHT of the cameras' images, at most 640x480")
      ->capture_default_str();
  app->add_option_function<std::string>(
         "--camera-depth", [o](const std::string& v) { o->cameras.depth = v == "on"; },
         "publish a depth image [m] beside each RGB image: on | off (default on)")
      ->check(CLI::IsMember({"on", "off"}));
  app->add_option("--record-images", o->record_images,
                 "write every image of every camera, rendered at --camera-rate whether asked or "
                 "not, to this folder: CAMERA/NNNNNN.png (RGB), CAMERA/NNNNNN_depth.png (16-bit "
                 "depth in mm) and images.csv (time, camera, files), for replays (ohrp view)");
  app->add_flag("--explain", o->explain,
               "print each effect (on or off, and why), the control period, and each joint's "
               "actuator and how its torque is mapped onto it, for this scene and these "
               "options, then exit 0 without creating a segment");
}

int Refuse(const std::string& what) {
  std::fprintf(stderr, "sim_host: %s\n", what.c_str());
  return kExitUsage;
}

// a robot profile's joints and sensors files, when no --joint-file / --sensor-file is given;
// then both files read
int ResolveIdentifiedFiles(HostOptions* o) {
  if ((o->joint_file.empty() || o->sensor_file.empty()) && model::IsProfilePath(o->scene)) {
    model::RobotProfile profile;
    std::string error;
    if (!model::ReadProfile(o->scene, &profile, &error)) return Refuse("--scene: " + error);
    if (o->joint_file.empty()) o->joint_file = profile.joint_file;
    if (o->sensor_file.empty()) o->sensor_file = profile.sensor_file;
  }
  if (std::string error; !o->sensor_file.empty() &&
                         !model::ReadSensorParamsFile(o->sensor_file, &o->sensors, &error))
    return Refuse("--sensor-file: " + error);
  if (std::string error; !o->joint_file.empty() &&
                         !model::ReadJointParamsFile(o->joint_file, &o->joints, &error))
    return Refuse("--joint-file: " + error);
  return -1;
}

// the contact under the soles: as hw_emulator chooses it (sim_host/contact_choice.h)
int ResolveContact(const CLI::App& app, const RawHostOptions& r, HostOptions* o) {
  ContactChoice choice{r.contact, o->contact_file, {}};
  for (const auto& [key, flag] : ContactParamFlags())
    if (app.count(flag) > 0) choice.given.insert(key);
  if (std::string error; !ChooseContact(o->scene, choice, &o->feet, &o->contact_file, &error))
    return Refuse(error);
  return -1;
}

// the camera size, the log's bound
int ResolveSizes(const RawHostOptions& r, HostOptions* o) {
  if (std::string error; !ParseCameraSize(r.camera_size, &o->cameras.width, &o->cameras.height, &error))
    return Refuse("--camera-size: " + error);
  if (!r.log_max.empty() && o->log_path.empty())
    return Refuse("--log-max bounds the data log: give --log FILE too");
  if (std::string error; !r.log_max.empty() && !model::ParseByteSize(r.log_max, &o->log_max, &error))
    return Refuse("--log-max: " + error);
  return -1;
}

// --effects, and the self_collision effect --self-collision asks for
int ResolveEffects(const RawHostOptions& r, HostOptions* o) {
  for (const auto& spec : r.effects) {
    std::string error;
    if (!ParseEffectRequests(spec, &o->effects, &error)) return Refuse(error);
  }
  if (o->self_collision_file.empty()) return -1;
  int8_t& request = o->effects.request[static_cast<int>(Effect::kSelfCollision)];
  if (request == 0)
    return Refuse("--self-collision " + o->self_collision_file +
                  " asks for the self_collision effect, which --effects switches off: drop one "
                  "of the two");
  request = 1;
  return -1;
}

// pushes, checked here, before the segment exists
int ResolvePushes(const RawHostOptions& r, HostOptions* o) {
  for (const auto& spec : r.pushes) {
    Perturbation p;
    std::string error;
    if (!ParsePerturbation(spec, &p, &error)) return Refuse(error);
    o->pushes.push_back(p);
  }
  return -1;
}

}  // namespace

void AddHostOptions(CLI::App* app, HostOptions* o, RawHostOptions* r) {
  AddModelOptions(app, o);
  AddContactOptions(app, o, r);
  AddIdentifiedOptions(app, o);
  AddRunOptions(app, o, r);
  AddOutputOptions(app, o, r);
  AddEffectOptions(app, o, r);
  app->footer(
      "Exit codes: 0 completed, 2 bad option, model, keyframe or segment, 3 MuJoCo error,\n"
      "4 the simulation diverged, 5 the controller was lost (or never attached, or another process\n"
      "overwrote the segment's wake-up words), 6 the robot fell (--on-fall end or continue; also\n"
      "when interrupted after a fall), 9 the data log or the summary could not be written\n"
      "completely (disk full, I/O error: the file and the error are named), 130 interrupted.\n"
      "Architecture and the segment's protocol: docs/architecture.md.");
}

int ResolveHostOptions(const CLI::App& app, const RawHostOptions& r, HostOptions* o) {
  if (const int code = ResolveIdentifiedFiles(o); code >= 0) return code;
  if (const int code = ResolveContact(app, r, o); code >= 0) return code;
  if (const int code = ResolveSizes(r, o); code >= 0) return code;
  if (const int code = ResolveEffects(r, o); code >= 0) return code;
  if (const int code = ResolvePushes(r, o); code >= 0) return code;
  shm::ParseControllerLoss(r.loss, &o->on_loss);  // one of the choices checked by CLI11
  ParseOnFall(r.on_fall, &o->fall.on_fall);       // the same
  return -1;
}

}  // namespace ohrp::sim
