// What sim_host prints before a run (see host_text.h).
#include "sim_host/host_text.h"

#include <cstdio>
#include <string>

#include "shm_bridge/controller_loss.h"
#include "sim_host/period.h"
#include "sim_host/report.h"

namespace ohrp::sim {

void PrintExplain(const HostText& t) {
  const HostOptions& o = t.o;
  const double dt = t.m->opt.timestep;
  std::printf("effects of %s (sim_host --explain):\n%s", o.scene.c_str(), t.effects.Table().c_str());
  if (t.self_collision) std::printf("self_collision: %s\n", t.self_collision->Describe().c_str());
  std::printf("%s", DescribeControlPeriod(dt, o.control_period, t.steps_per_cycle,
                                          t.period_defaulted).c_str());
  std::printf("%s", model::DescribeActuation(t.robot).c_str());
  for (const std::string& u : t.robot.unpublished) std::printf("note: %s\n", u.c_str());
  if (t.soft && !t.soft->impact_note().empty())
    std::printf("note: %s\n", t.soft->impact_note().c_str());
  if (!t.robot.cameras.empty()) {
    std::printf("cameras: %zu (%s first), %dx%d RGB%s, %g frames per simulated second, %s\n",
                t.robot.cameras.size(), t.robot.cameras[0].name.c_str(), o.cameras.width,
                o.cameras.height, o.cameras.depth ? " + depth" : "", o.cameras.rate,
                t.effects.on(Effect::kCameras)
                    ? "rendered only while an attached program asks for them"
                    : "never rendered (the cameras effect is off)");
  }
}

void PrintStart(const HostText& t) {
  const HostOptions& o = t.o;
  const model::RobotMap& robot = t.robot;
  std::fprintf(stderr,
               "sim_host: robot '%s' (%zu joints, %zu F/T, %zu IMU, %zu cameras, %.2f kg) from "
               "%s\nsim_host: segment '%s', physics %g s (%s), control %g s, %s, "
               "%s contact, controller loss: %s\n",
               robot.name.c_str(), robot.joints.size(), robot.forces.size(), robot.imus.size(),
               robot.cameras.size(), robot.total_mass, o.scene.c_str(), o.segment.c_str(),
               t.m->opt.timestep, IntegratorName(t.m->opt.integrator), o.control_period,
               o.realtime ? "real time" : "lock-step", ContactModelName(t.contact),
               shm::ControllerLossName(o.on_loss));
  for (const std::string& u : robot.unpublished) std::fprintf(stderr, "sim_host: note: %s\n", u.c_str());
  if (!o.joints.empty())
    std::fprintf(stderr, "sim_host: joints from %s: %s\n", o.joint_file.c_str(),
                 model::DescribeJointParams(o.joints).c_str());
  if (!o.sensor_file.empty())
    std::fprintf(stderr, "sim_host: sensors from %s (seed %llu): %s\n", o.sensor_file.c_str(),
                 static_cast<unsigned long long>(o.sensor_seed),
                 model::DescribeSensorParams(o.sensors).c_str());
  if (t.self_collision)
    std::fprintf(stderr, "sim_host: self_collision: %s\n", t.self_collision->Describe().c_str());
  if (t.soft && !t.soft->impact_note().empty())
    std::fprintf(stderr, "sim_host: note: %s\n", t.soft->impact_note().c_str());
  const std::string lines = t.effects.Short();
  for (size_t at = 0, nl; at < lines.size(); at = nl + 1) {
    nl = lines.find('\n', at);
    if (nl == std::string::npos) nl = lines.size();
    std::fprintf(stderr, "sim_host: %s\n", lines.substr(at, nl - at).c_str());
  }
}

}  // namespace ohrp::sim
