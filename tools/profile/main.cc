// ohrp_profile: the robot profile's tool (robot_model/profile.h, docs/robots.md "Robot
// profiles"): --init drafts one from a model for the user to review, --check loads a profile (or
// a model) as every program does and lists what the applications find and what is missing, all
// at once; --print-mjcf prints the MJCF the profile makes in memory.
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "cli/command_line.h"
#include "robot_model/kinematics.h"
#include "robot_model/load.h"
#include "robot_model/profile.h"

namespace {

using ohrp::model::Kinematics;

// what balance and walk look for (docs/balance.md), found or missing; the number missing
int Check(const std::string& path) {
  std::string error;
  std::unique_ptr<Kinematics> k = Kinematics::Load(path, &error);
  if (!k) {
    std::fprintf(stderr, "ohrp_profile: %s\n", error.c_str());
    return -1;
  }
  int missing = 0;
  auto miss = [&missing](const std::string& what) {
    std::printf("  MISSING %s\n", what.c_str());
    ++missing;
  };
  std::printf("%s: %d joints, %.3f kg\n", path.c_str(), k->njoint(), k->robot().total_mass);
  if (!k->floating()) miss("a floating base (a free joint)");
  for (int side : {k->left_sole(), k->right_sole()}) {
    if (side < 0) continue;
    const auto& s = k->soles()[side];
    std::printf("  %s sole %s: %.3f x %.3f m, F/T sensor %s\n", side == k->left_sole() ? "left" : "right",
                s.name.c_str(), 2 * s.half_size[0], 2 * s.half_size[1],
                s.force_sensor >= 0 ? k->robot().forces[s.force_sensor].name.c_str() : "none");
    if (s.force_sensor < 0) miss("a force/torque sensor above sole " + s.name);
  }
  if (k->left_sole() < 0 || k->right_sole() < 0)
    miss("two soles (box geoms named *_SOLE, found " + std::to_string(k->soles().size()) + ")");
  for (const auto& imu : k->robot().imus) std::printf("  IMU %s\n", imu.name.c_str());
  if (k->robot().imus.empty()) miss("an IMU (a gyro and an accelerometer on one site)");
  if (mj_name2id(k->m(), mjOBJ_KEY, "stand") >= 0) {
    std::printf("  stance: keyframe 'stand'\n");
  } else {
    miss("a stance: the keyframe 'stand'");
  }
  return missing;
}

bool WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return static_cast<bool>(out.flush());
}

}  // namespace

int main(int argc, char** argv) {
  std::string init, output, check, print;
  CLI::App app{
      "ohrp_profile: robot profiles, the YAML file beside a robot's model that gives the\n"
      "applications what the model lacks (soles, F/T sensors, an IMU, the stance) without\n"
      "editing it. Every program takes a profile wherever it takes a model (docs/robots.md)."};
  auto* o_init = app.add_option("--init", init, "draft a profile from this model (MJCF, VRML, URDF)")
                     ->check(CLI::ExistingFile);
  app.add_option("-o,--output", output, "with --init: the profile to write (default: standard output)");
  auto* o_check = app.add_option("--check", check, "load a profile or model as the programs do and "
                                 "list what balance and walk find and miss")->check(CLI::ExistingFile);
  auto* o_print = app.add_option("--print-mjcf", print, "print the MJCF a profile makes in memory")
                      ->check(CLI::ExistingFile);
  o_init->excludes(o_check)->excludes(o_print);
  o_check->excludes(o_print);
  app.footer(
      "Exit codes: 0 done (--check: nothing missing), 1 the output could not be written, 2 bad\n"
      "option, a model or profile that cannot be read (file:line: key: what), requirements\n"
      "that cannot be derived (--init) or are missing (--check), all listed.");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  std::string error;
  if (!check.empty()) {
    const int missing = Check(check);
    if (missing != 0) {
      if (missing > 0) std::fprintf(stderr, "ohrp_profile: %d requirement%s missing (listed above)\n",
                                    missing, missing > 1 ? "s" : "");
      return 2;
    }
    return 0;
  }
  if (!print.empty()) {
    ohrp::model::RobotProfile p;
    std::string mjcf, name;
    if (!ohrp::model::ReadProfile(print, &p, &error) ||
        !ohrp::model::ApplyProfile(p, &mjcf, &name, &error)) {
      std::fprintf(stderr, "ohrp_profile: %s\n", error.c_str());
      return 2;
    }
    std::fputs(mjcf.c_str(), stdout);
    return 0;
  }
  if (init.empty()) {
    std::fprintf(stderr, "ohrp_profile: give --init MODEL, --check FILE or --print-mjcf PROFILE\n");
    return 2;
  }
  std::string yaml;
  if (!ohrp::model::DraftProfile(init, output.empty() ? "profile.yaml" : output, &yaml, &error)) {
    std::fprintf(stderr, "ohrp_profile: %s\n", error.c_str());
    return 2;
  }
  if (output.empty()) {
    std::fputs(yaml.c_str(), stdout);
    return 0;
  }
  if (!WriteText(output, yaml)) {
    std::fprintf(stderr, "ohrp_profile: cannot write '%s'\n", output.c_str());
    return 1;
  }
  // what was written is checked as the programs will load it
  return Check(output) == 0 ? 0 : 2;
}
