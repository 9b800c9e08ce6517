// A robot simulated in-process (see in_process.h).
#include "sim_host/in_process.h"

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstring>

namespace ohrp::sim {
namespace {

std::string UniqueSegmentName() {
  static std::atomic<int> counter{0};
  return "inproc_" + std::to_string(getpid()) + "_" + std::to_string(counter++);
}

}  // namespace

std::unique_ptr<InProcessRobot> InProcessRobot::Create(const InProcessOptions& o,
                                                       std::string* error) {
  std::unique_ptr<InProcessRobot> r(new InProcessRobot());
  r->options_ = o;
  r->scene_ = model::Scene::Load(o.scene, error);
  if (!r->scene_) return nullptr;
  mjModel* m = r->scene_->m();
  if (o.physics_dt > 0) m->opt.timestep = o.physics_dt;
  const double ratio = o.control_period / m->opt.timestep;
  r->steps_per_cycle_ = static_cast<int>(std::lround(ratio));
  if (r->steps_per_cycle_ < 1 || std::fabs(ratio - r->steps_per_cycle_) > 1e-6) {
    *error = "control period " + std::to_string(o.control_period) +
             " s is not a whole number of physics steps of " + std::to_string(m->opt.timestep) + " s";
    return nullptr;
  }
  if (!model::MapRobot(m, &r->robot_, error)) return nullptr;
  if (!SetUpFeet(m, o.feet, r->robot_.total_mass, &r->soft_, error)) return nullptr;
  if (!r->scene_->Reset(o.keyframe, error)) return nullptr;
  for (const Perturbation& p : o.pushes) {
    if (!(p.t1 > p.t0)) {
      *error = "a push must end after it starts (t1 > t0)";
      return nullptr;
    }
  }
  r->servo_ = std::make_unique<model::Servo>(r->robot_);
  r->servo_->HoldCurrent(r->scene_->d());
  r->step_ = std::make_unique<PhysicsStep>(
      r->scene_->m(), r->scene_->d(),
      PhysicsStep::Parts{r->servo_.get(), r->soft_.get(), &r->options_.pushes,
                         r->robot_.base_body, nullptr});
  shm::Status status;
  r->producer_ = shm::Producer::Create(
      model::MakeProducerConfig(r->robot_, m, UniqueSegmentName(), m->opt.timestep, o.control_period),
      &status);
  if (!r->producer_) {
    *error = status.message;
    return nullptr;
  }
  r->Publish();
  return r;
}

InProcessRobot::~InProcessRobot() = default;

void InProcessRobot::Publish() {
  model::FillSensors(robot_, m(), d(), &sensors_);
  sensors_.cycle = cycle_;
  sensors_.time = d()->time;
  sensors_.status = shm::status::kRunning | shm::status::kSimulated;
  sensors_.rejected_commands = servo_->rejected_total();
}

int InProcessRobot::Cycle(const shm::CommandBlock& commands) {
  const int rejected = servo_->Accept(commands);
  for (int s = 0; s < steps_per_cycle_; ++s) step_->Step(s == steps_per_cycle_ - 1);
  ++cycle_;
  Publish();
  return rejected;
}

}  // namespace ohrp::sim
