// Loading any model the project takes (see load.h).
#include "robot_model/load.h"

#include <algorithm>
#include <memory>

#include "robot_model/profile.h"
#include "vrml/vrml.h"

namespace ohrp::model {
namespace {

struct VfsDeleter {
  void operator()(mjVFS* vfs) const {
    mj_deleteVFS(vfs);
    delete vfs;
  }
};

}  // namespace

mjModel* LoadMjcfText(const std::string& text, const std::string& vfs_name,
                      const std::string& what, std::string* error) {
  // MuJoCo 2.2.2 keeps a VFS file under its name without the folder and looks a file up the same
  // way; the model's folder (from the name) is where its meshdir and asset files are found on
  // disk. The name is one no author's asset file plausibly has.
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), vfs_name.c_str(), static_cast<int>(text.size())) != 0) {
    *error = "cannot make the in-memory MJCF of " + what + " (MuJoCo's VFS is full)";
    return nullptr;
  }
  const int file = mj_findFileVFS(vfs.get(), vfs_name.c_str());
  std::copy(text.begin(), text.end(), static_cast<char*>(vfs->filedata[file]));
  char err[1024] = "";
  mjModel* m = mj_loadXML(vfs_name.c_str(), vfs.get(), err, sizeof(err));
  if (!m) *error = "cannot load " + what + ": " + (err[0] ? err : "unknown MuJoCo error");
  return m;
}

mjModel* LoadMujocoModel(const std::string& path, std::string* error) {
  if (IsProfilePath(path)) {
    RobotProfile profile;
    std::string mjcf, vfs_name;
    if (!ReadProfile(path, &profile, error) || !ApplyProfile(profile, &mjcf, &vfs_name, error))
      return nullptr;
    return LoadMjcfText(mjcf, vfs_name, "'" + profile.model + "' with profile '" + path + "'",
                        error);
  }
  if (vrml::IsVrmlPath(path)) return vrml::LoadModel(path, error);
  char err[1024] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
  if (!m) *error = "cannot load '" + path + "': " + (err[0] ? err : "unknown MuJoCo error");
  return m;
}

}  // namespace ohrp::model
