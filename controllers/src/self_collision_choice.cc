// Which self-collision file a controller's runner loads (self_collision_choice.h).
#include "self_collision_choice.h"

#include <algorithm>
#include <cstring>
#include <filesystem>

#include <yaml-cpp/yaml.h>

#include "cli/data_dir.h"
#include "controllers/self_collision_guard.h"

namespace ohrp::controllers {

std::vector<std::string> ProfileSelfCollisionFiles() {
  // only this key of each profile, relative to its folder (the profile's reader, in robot_model,
  // checks the whole profile; this library stays MuJoCo-free); an unreadable profile has none
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(cli::DataPath("robots"), ec)) {
    const std::filesystem::path& path = e.path();
    if (path.extension() != ".yaml" && path.extension() != ".yml") continue;
    try {
      const YAML::Node file = YAML::LoadFile(path.string())["self_collision"];
      if (!file || !file.IsScalar()) continue;
      const std::filesystem::path f = file.as<std::string>();
      files.push_back(f.is_absolute() ? f.string() : (path.parent_path() / f).lexically_normal().string());
    } catch (const YAML::Exception&) {
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string SelfCollisionFileFor(const RunOptions& options, const shm::SegmentHeader& header,
                                 const std::string& prog, std::ostream& err) {
  if (options.self_collision.empty() || !options.self_collision_is_default) return options.self_collision;
  using Owner = SelfCollisionGuard::Owner;
  std::string robot, variants;
  for (const std::string& f : ProfileSelfCollisionFiles()) {
    const Owner owner = SelfCollisionGuard::FileOwner(f, header, &robot);
    if (owner == Owner::kThisModel) return f;
    if (owner == Owner::kThisRobot) variants += " " + f;
  }
  const Owner owner = SelfCollisionGuard::FileOwner(options.self_collision, header, &robot);
  if (owner == Owner::kAnotherRobot) {
    const std::string here(header.robot_name, strnlen(header.robot_name, sizeof(header.robot_name)));
    err << prog << ": WARNING: no self-collision check: there is no self-collision file for "
        << "robot " << here << " (the default " << options.self_collision << " is for " << robot
        << ", other joints";
    if (!variants.empty())
      err << "; the robot profiles' file(s)" << variants
          << " are for this robot as its profile makes it, another model";
    err << "; make one with ohrp_selfcollision --model MJCF_OR_PROFILE --out FILE and give "
        << "--self-collision FILE)\n";
    return "";
  }
  if (owner == Owner::kUnpublished) {
    err << prog << ": WARNING: no self-collision check: the producer publishes no model hash, "
        << "so no self-collision file can be checked against its robot (give "
        << "--no-self-collision to say so, or run a producer that publishes its model)\n";
    return "";
  }
  return options.self_collision;
}

}  // namespace ohrp::controllers
