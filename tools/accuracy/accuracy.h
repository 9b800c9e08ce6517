// Speed-accuracy measurement in the manner of Erez, Tassa and Todorov, "Simulation tools for
// model-based robotics" (ICRA 2015): per scene, a reference trajectory at a very small step;
// per setting, short pieces restarted from reference states, integrated with that setting and
// compared with the reference (body positions after mj_kinematics, window-averaged contact
// normal force), against the real-time factor achieved (simulated time / thread CPU time).
//
// A restart copies qpos, qvel, act, time, qacc_warmstart, xfrc_applied (and qfrc_applied) and
// the soft-foot contact's own state (friction anchors, its share of xfrc_applied): restarting
// the reference setting from a reference state reproduces the reference bit for bit.
// Controls are a function of simulated time (d->time), never of the step count, so that every
// setting sees the same references at the same instants.
#pragma once

#include <mujoco/mujoco.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "contact/soft_contact.h"
#include "controllers/trajectory.h"
#include "sim_host/feet.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "sim_host/step.h"

namespace ohrp::accuracy {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

enum class Integrator { kEuler, kRK4, kImplicit };
const char* IntegratorName(Integrator i);
bool ParseIntegrator(const std::string& name, Integrator* out);

// "none" (no contact in the scene), "soft", "native", "rigid" (see sim_host/feet.h).
enum class Contact { kNone, kSoft, kNative, kRigid };
const char* ContactName(Contact c);
bool ParseContact(const std::string& name, Contact* out);

// One simulator setting.
struct Setting {
  Integrator integrator = Integrator::kEuler;
  double dt = 1e-3;               // [s]
  Contact contact = Contact::kNone;
  int iterations = -1;            // solver iterations, -1: the model's
  double tolerance = -1;          // solver tolerance, -1: the model's
  std::string geometry;           // collision geometry variant, "" = the scene's first
};
std::string Describe(const Setting& s);

// The SamplePD walk: joint references as a function of simulated time (linear interpolation of
// angle.dat / vel.dat at t = d->time, data time = simulated time), PD gains from PDgain.dat.
struct Walk {
  controllers::Trajectory angles, velocities;
  controllers::Gains gains;
};
// Loads the three files from `dir`; false with a message naming the file when one is missing or
// bad.
bool LoadWalk(const std::string& dir, Walk* walk, std::string* error);

// A scene of the benchmark.
struct SceneSpec {
  std::string name;
  std::string description;
  std::string path;                     // MJCF file, or
  std::string xml;                      // MJCF text (when path is empty)
  std::string keyframe;                 // initial state ("" = qpos0)
  std::vector<Contact> contacts;        // contact models that apply (first: the main one)
  // collision geometry variants: a variant is a geom name; that geom collides, the other
  // variants' geoms do not. Empty: no variants ("primitive").
  std::vector<std::string> geometries;
  std::vector<std::string> soles;       // geoms the soft/rigid contact acts on
  double soft_mass = 0;                 // mass riding on one sole [kg] (soft: parameter check)
  bool servo = false;                   // robot joints held by the Servo (references: keyframe)
  const Walk* walk = nullptr;           // references from the walk instead
  double preroll = 0;                   // [s] simulated at 1 ms Euler before the reference
  double duration = 1.0;                // [s] of reference trajectory
};

// The state a restart copies.
struct Snapshot {
  double time = 0;
  std::vector<double> qpos, qvel, act, warmstart, xfrc, qfrc;
  bool has_soft = false;
  contact::SoftFootContact::State soft;
};

// One model + data stepping a scene with a setting, as sim_host steps it:
// controls(t) -> servo -> soft contact -> mj_step -> commit.
class Sim {
 public:
  // null with *error on failure; *error starts with "refused:" when the soft-foot contact's
  // parameter check refuses the step (the setting is unstable for it by its own criterion).
  static std::unique_ptr<Sim> Create(const SceneSpec& scene, const Setting& setting,
                                     std::string* error);
  ~Sim();
  Sim(const Sim&) = delete;
  Sim& operator=(const Sim&) = delete;

  mjModel* m() const { return m_; }
  mjData* d() const { return d_; }
  const Setting& setting() const { return setting_; }

  // One physics step. Returns the total contact normal force [N] acting over it (soft: the
  // sum of the soles' normal forces held over the step; MuJoCo: the sum of the contacts'
  // normal forces of the step's last evaluation).
  double Step();
  // Steps n times; returns the time average of the normal force.
  double Advance(int n);

  Snapshot Save() const;
  void Restore(const Snapshot& s);
  // Body positions (xpos of bodies 1..nbody-1, 3 each) after mj_kinematics at the current qpos.
  void Positions(std::vector<double>* out);
  bool Finite() const;

 private:
  Sim() = default;
  void Controls();
  double NormalForce() const;
  Setting setting_;
  const SceneSpec* scene_ = nullptr;
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  model::RobotMap robot_;
  std::unique_ptr<model::Servo> servo_;
  std::unique_ptr<contact::SoftFootContact> soft_;
  std::unique_ptr<sim::PhysicsStep> step_;  // sim_host's physics step over the parts above
  std::vector<double> q_ref_, dq_ref_;
  shm::CommandBlock commands_{};
};

// Mean Euclidean distance between corresponding bodies (3-vectors) [m].
double PositionError(const std::vector<double>& a, const std::vector<double>& b);

// The reference trajectory: snapshots, body positions and window-averaged normal force at every
// window boundary (window = `window` seconds, a multiple of the reference step).
struct Reference {
  Setting setting;
  double window = 0.016;
  std::vector<Snapshot> states;               // at window k (k = 0..n)
  std::vector<std::vector<double>> positions;  // at window k
  std::vector<double> force;                   // average over window k-1..k (force[0] = 0)
  double cpu = 0;                              // thread CPU seconds spent integrating
  double sim_time = 0;                         // simulated seconds integrated
};

bool MakeReference(const SceneSpec& scene, const Setting& setting, double window,
                   Reference* ref, std::string* error);

struct PieceResult {
  double pos_error = kInf;    // mean over the compared windows and restarts [m]
  double force_error = kInf;  // mean |F - F_ref| [N]
  double cpu = 0;             // thread CPU seconds integrating
  double sim_time = 0;        // simulated seconds integrated
  bool diverged = false;
  std::string note;           // why diverged / refused
  int iterations = 0;         // the solver settings in force (the model's when not set)
  double tolerance = 0;
  // MuJoCo's refsafe raises the time constant of a colliding geom's contact (its solref[0] <
  // 2 dt): the contact is then not the one the model specifies
  bool refsafe = false;
  double rtf() const { return cpu > 0 ? sim_time / cpu : 0; }
};

// Restarts `setting` from the reference at `restarts` points spread along it, integrates
// `piece_windows` windows from each and compares each window boundary with the reference.
PieceResult RunPieces(const SceneSpec& scene, const Setting& setting, const Reference& ref,
                      int restarts, int piece_windows);

// ---- closed forms ----

// Exact period of a rigid pendulum (pivot inertia I, mass m, pivot-to-centre-of-mass d) released
// at rest from amplitude theta0: 4 sqrt(I/(m g d)) K(sin(theta0/2)) (complete elliptic integral
// of the first kind, by the arithmetic-geometric mean).
double PendulumPeriod(double inertia, double mass, double g, double d, double theta0);
// Period measured on mjcf/bench/pendulum_single.xml with a setting (mean of the intervals between
// successive downward zero crossings over `periods` periods); NaN when it diverged.
double MeasurePendulumPeriod(const std::string& path, const Setting& setting, int periods);


// Icosphere of radius r with `level` subdivisions (12, 42, 162, 642 vertices): the vertex list
// for an MJCF <mesh vertex="...">.
std::string IcosphereVertices(double r, int level);

// Closed forms on the benchmark's scenes, each run with `s` from the scene's initial state
// (NaN when the setting cannot be built, e.g. refused; *note says why):
// the block of mjcf/bench/box_slide.xml falling for 0.096 s: |z - (z0 - g t^2 / 2)| [m];
double FreeFallError(const SceneSpec& scene, const Setting& s, double* value, double* exact);
// the block resting 1.5 s on the soft soles: |sink - (m g / k)^(1/n)| / (m g / k)^(1/n);
double StaticSink(const SceneSpec& scene, const Setting& s, double* value, double* exact,
                  std::string* note);
// the block entering the soft soles at 0.1 m/s without gravity: |e - e_law| / e_law, e_law from
// HuntCrossleyRestitution at a 1e-7 s step;
double Restitution(const SceneSpec& scene, const Setting& s, double* value, double* exact,
                   std::string* note);
// the ball set down sliding at v0 without spin, after 1 s: |v - 5/7 v0| [m/s].
double RollingError(const SceneSpec& scene, const Setting& s, double* value, double* exact);
// The ball scene's MJCF: a sphere primitive "sphere" and icospheres "ico0".."ico3" (12..642
// vertices) of the same radius 0.1 m, 1 kg, inertia 2/5 m r^2, key "slide" (2 m/s, no spin).
std::string BallXml();

}  // namespace ohrp::accuracy
