// ohrp identify --joints on a data log (hw_driver --log, sim_host --log) instead of excite's own:
// the joints whose reference moved, each with the rows in which its board reported a new state.
// (see identify/joints.h, ReadJointLog)
#include "identify/joints.h"

#include <cmath>
#include <fstream>

#include "datalog/table.h"
#include "shm_bridge/layout.h"

namespace ohrp::identify {
namespace {

// one joint's columns of the data log; false when a column is missing
struct Columns {
  int q = -1, ref = -1, tau = -1, dq = -1, dref = -1;
};

Columns Find(const datalog::Table& t, const std::string& joint) {
  return {t.Column("q_" + joint), t.Column("qref_" + joint), t.Column("tau_" + joint),
          t.Column("dq_" + joint), t.Column("dqref_" + joint)};
}

// A row whose q, dq and tau are those of the row before, bit for bit, is a board that had no new
// state for this joint (its packet a cycle old while another board's was new: the row's time is
// the newest board's): it is left out, a gap in the joint's time like a row the driver missed.
bool Repeated(const datalog::Table& t, const Columns& c, size_t r) {
  if (r == 0) return false;
  const auto same = [&](int col) { return col < 0 || t.col(col)[r] == t.col(col)[r - 1]; };
  return same(c.q) && same(c.dq) && same(c.tau);
}

// the rows in which the controller drove the servos (the status column's bits, when the log has
// it): not before a controller attached or the servos were on, nor in a hold, an emergency stop
// or the producer's last cycle, where the servo's law is not the controller's references'
constexpr uint32_t kNotDriven = shm::status::kNoController | shm::status::kHolding |
                                shm::status::kServoOff | shm::status::kEmergencyStop |
                                shm::status::kShuttingDown | shm::status::kDiverged;

}  // namespace

bool ReadJointDataLog(const std::string& path, std::vector<JointLog>* joints, size_t* repeated,
                      std::string* error) {
  datalog::Table t;
  if (!t.Load(path, error)) return false;
  const int time = t.Column("time");
  if (time != 0) return *error = path + ": not a data log (its first column is not time)", false;
  joints->clear();
  *repeated = 0;
  std::vector<std::string> still;
  for (const std::string& name : t.names()) {
    if (name.rfind("qref_", 0) != 0) continue;
    const std::string joint = name.substr(5);
    const Columns c = Find(t, joint);
    if (c.q < 0 || c.tau < 0) {
      *error = path + ": " + name + " without q_" + joint + " and tau_" + joint;
      return false;
    }
    // the excited joints: a reference that moved (the others held where they were)
    // (over many rows: a controller taking over steps a held joint's reference once)
    double lo = INFINITY, hi = -INFINITY;
    size_t moves = 0;
    const std::vector<double>& ref = t.col(c.ref);
    for (size_t r = 0; r < ref.size(); ++r) {
      lo = std::fmin(lo, ref[r]), hi = std::fmax(hi, ref[r]);
      moves += r > 0 && ref[r] != ref[r - 1];
    }
    if (!(hi - lo > kExcitedSpan) || moves < kExcitedRows) {
      still.push_back(joint);
      continue;
    }
    JointLog& l = joints->emplace_back();
    l.joint = joint;
    const int status = t.Column("status");
    for (size_t r = 0; r < t.rows(); ++r) {
      if (status >= 0 && (static_cast<uint32_t>(t.col(status)[r]) & kNotDriven)) continue;
      if (Repeated(t, c, r)) {
        ++*repeated;
        continue;
      }
      l.t.push_back(t.col(time)[r]);
      l.ref.push_back(t.col(c.ref)[r]);
      l.q.push_back(t.col(c.q)[r]);
      l.tau.push_back(t.col(c.tau)[r]);
      l.dq.push_back(c.dq >= 0 ? t.col(c.dq)[r] : NAN);
      if (c.dref >= 0) l.dref.push_back(t.col(c.dref)[r]);
    }
    // without dq_ (no --log-dq): the velocity as the encoder's difference over the interval
    // that ends at the row (the mean velocity over it; the first row and a row after a gap are
    // not differenced and stay out of the fits, which take consecutive cycles only)
    if (c.dq < 0)
      for (size_t k = 1; k < l.t.size(); ++k) l.dq[k] = (l.q[k] - l.q[k - 1]) / (l.t[k] - l.t[k - 1]);
  }
  if (joints->empty()) {
    *error = path + ": no joint's reference spans more than " + std::to_string(kExcitedSpan) +
             " rad over " + std::to_string(kExcitedRows) + " rows or more (" +
             std::to_string(still.size()) + " joints held): not an excitation";
    return false;
  }
  return true;
}

bool ReadJointLog(const std::string& path, std::vector<JointLog>* joints, std::string* note,
                  std::string* error) {
  std::ifstream in(path);
  std::string header;
  if (!in || !std::getline(in, header)) return *error = "cannot read " + path, false;
  note->clear();
  const bool excite = header.find("_ref,") != std::string::npos ||
                      (header.size() > 4 && header.compare(header.size() - 4, 4, "_ref") == 0);
  if (excite)
    return ReadExciteLog(path, joints, error);
  size_t repeated = 0;
  if (!ReadJointDataLog(path, joints, &repeated, error)) return false;
  *note = "a data log: " + std::to_string(joints->size()) + " joint(s) whose reference moved";
  if (repeated > 0)
    *note += ", " + std::to_string(repeated) + " rows without a new board state left out";
  return true;
}

}  // namespace ohrp::identify
