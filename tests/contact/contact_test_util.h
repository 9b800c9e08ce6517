// Helpers for the soft-foot contact tests: inline MJCF models of a sole-sized block.
#pragma once

#include <mujoco/mujoco.h>

#include <cstring>
#include <memory>
#include <string>

namespace ohrp::contact::testing {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// Loads an MJCF given as a string (through a MuJoCo virtual file system, no temp files).
inline ModelPtr LoadString(const std::string& xml, std::string* error) {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* name = "inline_model.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
    *error = "cannot make the VFS file";
    return nullptr;
  }
  std::memcpy(vfs->filedata[vfs->nfile - 1], xml.data(), xml.size());
  char err[1000] = "";
  ModelPtr m(mj_loadXML(name, vfs.get(), err, sizeof(err)));
  mj_deleteVFS(vfs.get());
  if (!m) *error = err;
  return m;
}

// The sole of mjcf/hrp1s/hrp1s.xml: a 0.25 x 0.14 x 0.02 m box.
inline constexpr double kSoleHalf[3] = {0.125, 0.07, 0.01};

// A free block with the sole's box as its only geom, `mass` kg (inertia of a solid box), over
// an environment given as MJCF geoms (MuJoCo's own contact off everywhere: contype=0).
inline std::string BlockModel(double dt, double mass, const std::string& environment,
                              const std::string& gravity = "0 0 -9.81",
                              const std::string& assets = "",
                              const std::string& integrator = "Euler") {
  const double a = 2 * kSoleHalf[0], b = 2 * kSoleHalf[1], c = 2 * kSoleHalf[2];
  const double ixx = mass * (b * b + c * c) / 12, iyy = mass * (a * a + c * c) / 12,
               izz = mass * (a * a + b * b) / 12;
  std::string xml = "<mujoco><option timestep=\"" + std::to_string(dt) +
                    "\" integrator=\"" + integrator + "\" gravity=\"" + gravity + "\"/>";
  xml += "<default><geom contype=\"0\" conaffinity=\"0\"/></default>";
  if (!assets.empty()) xml += "<asset>" + assets + "</asset>";
  xml += "<worldbody>" + environment;
  xml += "<body name=\"block\" pos=\"0 0 0.5\"><freejoint name=\"free\"/>";
  xml += "<inertial pos=\"0 0 0\" mass=\"" + std::to_string(mass) + "\" diaginertia=\"" +
         std::to_string(ixx) + " " + std::to_string(iyy) + " " + std::to_string(izz) + "\"/>";
  xml += "<geom name=\"sole\" type=\"box\" size=\"0.125 0.07 0.01\"/>";
  xml += "</body></worldbody></mujoco>";
  return xml;
}

inline const std::string kPlaneFloor = "<geom name=\"floor\" type=\"plane\" size=\"5 5 0.1\"/>";
// A 2 x 2 x 0.1 m box whose top face is at z = 0.
inline const std::string kBoxFloor =
    "<geom name=\"floor\" type=\"box\" size=\"1 1 0.05\" pos=\"0 0 -0.05\"/>";
// The same slab as a mesh (MuJoCo recentres it; its convex hull goes to fcl::Convex).
inline const std::string kMeshAsset =
    "<mesh name=\"slab\" vertex=\"-1 -1 -0.1  1 -1 -0.1  1 1 -0.1  -1 1 -0.1  "
    "-1 -1 0  1 -1 0  1 1 0  -1 1 0\"/>";
inline const std::string kMeshFloor = "<geom name=\"floor\" type=\"mesh\" mesh=\"slab\"/>";

}  // namespace ohrp::contact::testing
