// sim_host's set-up (host_run.h): the scene and its robot, the effects and the soles, the
// watches, the data log and the segment; every refusal before anything runs.
#include <cstdio>

#include "cli/plausible.h"
#include "host_run.h"
#include "robot_model/log_names.h"
#include "robot_model/model_hash.h"
#include "sim_host/host_text.h"
#include "sim_host/period.h"

namespace ohrp::sim {
namespace {

bool ApplyOverrides(const HostOptions& o, mjModel* m, std::string* error) {
  if (o.physics_dt > 0) m->opt.timestep = o.physics_dt;
  // the step, the scene's or ours, is plausible (cli/plausible.h): 1e308 or 1e-300 never runs
  *error = cli::CheckPlausible("physics_dt", m->opt.timestep,
                               o.physics_dt > 0 ? "--physics-dt" : o.scene + ": <option timestep>");
  if (!error->empty()) return false;
  if (!o.integrator.empty()) {
    if (o.integrator == "euler") m->opt.integrator = mjINT_EULER;
    else if (o.integrator == "rk4") m->opt.integrator = mjINT_RK4;
    else if (o.integrator == "implicit") m->opt.integrator = mjINT_IMPLICIT;
    else {
      *error = "unknown integrator '" + o.integrator + "' (use euler, rk4 or implicit)";
      return false;
    }
  }
  return true;
}

}  // namespace

HostRun::HostRun(const HostOptions& options, const std::atomic<int>* sig, char* object,
                 size_t object_size)
    : o(options), given(options), signal(sig), segment_object(object),
      segment_object_size(object_size) {}

HostRun::~HostRun() {
  if (filter_set) ClearContactFilter();  // before the model it filters goes
}

int HostRun::SetUp(bool* ran_enough) {
  *ran_enough = false;
  if (!LoadScene(&error) || !SetUpWatches(&error) || !ApplyJointFile(&error)) {
    std::fprintf(stderr, "sim_host: %s\n", error.c_str());
    return kExitUsage;
  }
  const HostText text{o, robot, effects, self_collision.get(), soft.get(), m, steps_per_cycle,
                      given.control_period <= 0, contact_model};
  if (o.explain) {
    PrintExplain(text);
    std::printf("%s\n", fall->Describe().c_str());
    *ran_enough = true;
    return kExitOk;
  }
  if (!OpenLog(&error)) {
    std::fprintf(stderr, "sim_host: --log: %s\n", error.c_str());
    return kExitUsage;
  }
  selection = SelectSensors(effects);
  if (!SetUpSensorModel(&error)) {
    std::fprintf(stderr, "sim_host: %s\n", error.c_str());
    return kExitUsage;
  }
  if (!CreateSegment(&error)) {
    std::fprintf(stderr, "sim_host: %s\n", error.c_str());
    return kExitUsage;
  }
  // the summary, before the run: a provisional one (outcome "running") until the end
  if (!o.summary_path.empty() &&
      !model::PrepareOutputFile(o.summary_path, ProvisionalSummary(o), &error)) {
    std::fprintf(stderr, "sim_host: --summary: %s\n", error.c_str());
    return kExitUsage;  // the segment is removed on the way out
  }
  if (!o.control_socket.empty() && !OpenControl(&error)) {
    std::fprintf(stderr, "sim_host: %s\n", error.c_str());
    return kExitUsage;
  }
  cameras = std::make_unique<Cameras>(robot, o.cameras, effects.on(Effect::kCameras));
  if (!o.record_images.empty() && !OpenImages(&error)) {
    std::fprintf(stderr, "sim_host: --record-images: %s\n", error.c_str());
    return kExitUsage;  // the segment is removed on the way out
  }
  servo = std::make_unique<model::Servo>(robot);
  servo->HoldCurrent(d);
  SetUpCommandDelay();
  if (!o.quiet) PrintStart(text);
  if (!o.quiet) std::fprintf(stderr, "sim_host: %s\n", fall->Describe().c_str());
  return kExitOk;
}

// the scene, its robot, the effects and the soles, the initial state, the control period
bool HostRun::LoadScene(std::string* why) {
  scene = model::Scene::Load(o.scene, why);
  if (!scene) return false;
  m = scene->m();
  d = scene->d();
  if (!model::MapRobot(m, &robot, why)) {
    why->insert(0, o.scene + ": ");
    return false;
  }
  if (!o.pushes.empty() && robot.base_body < 0) {
    *why = o.scene + ": --push acts on the robot's free-floating base, and this model has none "
                     "(no free joint)";
    return false;
  }
  contact_model = o.feet.model;
  // the effects are decided on the scene as loaded, applied once the soles are set up
  if (!ApplyOverrides(o, m, why) ||
      !ResolveEffects(m, robot, o.feet, !o.log_path.empty(), o.effects, &effects, why) ||
      !SetUpFeet(m, o.feet, robot.total_mass, &soft, why, &contact_model)) {
    return false;
  }
  ApplyEffects(effects, robot, m);
  filter_set = true;
  if (!scene->Reset(o.keyframe, why)) return false;
  // the control period: the scene's step times n (period.h)
  dt = m->opt.timestep;
  return ChooseControlPeriod(dt, given.control_period, &o.control_period, &steps_per_cycle, why);
}

// the fall watch on the initial state (fall.h); the self_collision effect: the controllers'
// checker on the robot's links, once a cycle
bool HostRun::SetUpWatches(std::string* why) {
  fall = FallWatch::Create(m, d, robot, o.feet.soles, o.fall, why);
  if (!fall) return false;
  if (!effects.on(Effect::kSelfCollision)) return true;
  self_collision = SelfCollisionWatch::Create(m, robot, o.self_collision_file, why);
  if (!self_collision) return false;
  self_collision->Start(d);
  return true;
}

// the joints as identified (--joint-file): the robot's dynamics, not its identity. The segment
// publishes the model file's hash, so that the controllers that load that file attach (as they
// do to hw_driver, whose robot's joints differ from the model the same way); the
// self_collision watch was made on the geometry, which the file does not touch. The armature
// changes the model's constants (mj_setConst), so the initial state is set again.
bool HostRun::ApplyJointFile(std::string* why) {
  identity_hash = model::ModelHash(m, robot);
  if (o.joints.empty()) return true;
  std::vector<std::string> names;
  for (const model::JointMap& j : robot.joints) names.push_back(j.name);
  if (!model::ApplyJointParams(o.joints, m, d, why) ||
      !model::JointDelayCycles(o.joints, names, o.control_period, &delay_cycles, why)) {
    why->insert(0, "--joint-file " + o.joint_file + ": ");
    return false;
  }
  return scene->Reset(o.keyframe, why);
}

// the actuators' command delay (the joint file's delay:): the ring starts with what the servo
// holds before the first command
void HostRun::SetUpCommandDelay() {
  shm::CommandBlock initial{};
  initial.njoint = static_cast<int32_t>(robot.joints.size());
  for (int j = 0; j < initial.njoint; ++j) initial.joint[j] = servo->reference(j);
  delay.SetUp(delay_cycles, initial);
}

// the sensors as identified (--sensor-file: the file's names bound to the robot's sensors) and
// the noise effect (--effects noise=on), added: one sensor model. Its seed is --sensor-seed with
// a file, the effect's noise.seed without.
bool HostRun::SetUpSensorModel(std::string* why) {
  for (const model::JointMap& j : robot.joints) {
    q_min.push_back(j.q_min);
    q_max.push_back(j.q_max);
  }
  const bool noise = effects.on(Effect::kNoise);
  if (o.sensor_file.empty() && !noise) return true;
  model::SensorParams bound;  // the file's (none: every sensor as simulated), in the robot's order
  if (!model::BindSensorParams(o.sensor_file.empty() ? model::SensorParams{} : o.sensors, robot,
                               &bound, why)) {
    why->insert(0, "--sensor-file " + o.sensor_file + ": ");
    return false;
  }
  if (noise) model::AddSensorParams(NoiseAsSensorParams(effects.noise, robot), &bound);
  sensors = std::make_unique<model::SensorModel>(std::move(bound),
                                                 o.sensor_file.empty() ? effects.noise.seed : o.sensor_seed);
  return true;
}

// --record-images: the robot's cameras, on, into the run folder (image_recorder.h)
bool HostRun::OpenImages(std::string* why) {
  if (robot.cameras.empty()) {
    *why = "the robot in " + o.scene + " has no camera (a <camera> on one of its bodies)";
    return false;
  }
  if (!effects.on(Effect::kCameras)) {
    *why = "the cameras effect is off (--effects cameras=on)";
    return false;
  }
  std::vector<std::string> names;
  for (const model::CameraMap& c : robot.cameras) names.push_back(c.name);
  images = ImageRecorder::Open(o.record_images, names, o.cameras.width, o.cameras.height,
                               o.cameras.depth, why);
  if (!images) return false;
  cameras->Record(images.get());
  return true;
}

// the data log, before anything runs (its header written: a file that takes none is refused)
bool HostRun::OpenLog(std::string* why) {
  if (!effects.on(Effect::kLog)) return true;
  datalog::RecorderChannels channels;
  channels.base = effects.on(Effect::kLogBase);
  channels.joints = effects.on(Effect::kLogJoints);
  channels.joint_velocities = o.log_dq;
  channels.force_torque = effects.on(Effect::kLogForceTorque);
  channels.imu = effects.on(Effect::kLogImu);
  recorder = datalog::Recorder::Open(o.log_path, model::LogNamesOf(robot), why, 8192, channels, o.log_max);
  return recorder != nullptr;
}

bool HostRun::CreateSegment(std::string* why) {
  shm::Status status;
  shm::ProducerConfig pc = model::MakeProducerConfig(robot, m, o.segment, dt, o.control_period);
  pc.model_hash = identity_hash;  // the model file's, whatever --joint-file changed
  pc.read_timeout_hint = o.controller_timeout;
  for (shm::CameraInfo& c : pc.cameras) {
    c.width = o.cameras.width;
    c.height = o.cameras.height;
  }
  producer = shm::Producer::Create(pc, &status);
  if (!producer) {
    *why = status.message;
    return false;
  }
  if (!status.message.empty()) std::fprintf(stderr, "sim_host: %s\n", status.message.c_str());
  std::snprintf(segment_object, segment_object_size, "%s", producer->object_name().c_str());
  return true;
}

}  // namespace ohrp::sim
