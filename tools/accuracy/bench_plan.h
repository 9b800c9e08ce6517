// What bench_accuracy measures (bench_accuracy.cc): its scenes, the settings swept against each
// reference, and the closed forms measured beside them.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "accuracy.h"
#include "report.h"

namespace ohrp::accuracy {

inline constexpr double kG = 9.81;
inline constexpr double kWindow = 0.016;  // comparison window = the largest step swept [s]

struct BenchOptions {
  bool quick = false;
  std::string out;
  std::string docs;  // write docs here when not empty
  std::vector<std::string> scenes;
  bool plot = true;
  int restarts = 10;
  int piece_windows = 8;
  double ref_dt = 1.0 / 16000;
};

// the scenes asked for (all when o.scenes is empty); false with a message in *error when one
// cannot be set up (a missing external file, a model that does not load)
bool MakeScenes(const BenchOptions& o, const std::string& source_dir, Walk* walk,
                std::vector<SceneSpec>* scenes, std::string* error);

// a model with some joint damping (the implicit integrator differs from Euler only there)
bool HasDamping(const SceneSpec& scene);

// the reference setting of a scene's contact model: RK4 at ref_dt, 200 iterations, 1e-12
Setting ReferenceSetting(const BenchOptions& o, const SceneSpec& scene, Contact c);

// the settings compared with that reference, each with the sweep it belongs to
std::vector<std::pair<std::string, Setting>> SettingsFor(const BenchOptions& o,
                                                         const SceneSpec& scene,
                                                         const Setting& reference,
                                                         const std::vector<double>& dts,
                                                         bool damping);

// the closed forms of the scene measured with the row's setting: the row's own error and the
// rows of closed_forms.csv
void MeasureClosedForms(const SceneSpec& scene, const std::string& source_dir, Row* row,
                        std::vector<ClosedRow>* closed);

}  // namespace ohrp::accuracy
