// LiveSource: a running segment seen through an observer, turned into frames at a bounded rate
// (source.h). The observer never writes the segment, so a slow or stopped viewer cannot slow
// the producer or the controller; when this program falls behind it skips cycles.
#include <time.h>

#include <cmath>
#include <cstring>

#include "robot_model/model_hash.h"
#include "view/source.h"
#include "shm_bridge/clock.h"

namespace ohrp::view {

namespace {

// the status bits by name, for the page
nlohmann::json StatusNames(uint32_t bits) {
  static const std::pair<uint32_t, const char*> kNames[] = {
      {shm::status::kRunning, "running"},         {shm::status::kNoController, "no controller"},
      {shm::status::kHolding, "holding"},         {shm::status::kCommandRejected, "command rejected"},
      {shm::status::kCommandLate, "command late"}, {shm::status::kShuttingDown, "shutting down"},
      {shm::status::kDiverged, "diverged"},       {shm::status::kServoOff, "servo off"},
      {shm::status::kBoardFault, "board fault"},  {shm::status::kEmergencyStop, "emergency stop"},
      {shm::status::kSimulated, "simulated"},     {shm::status::kPaused, "paused"}};
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [bit, name] : kNames)
    if (bits & bit) out.push_back(name);
  return out;
}

}  // namespace

std::unique_ptr<LiveSource> LiveSource::Open(const std::string& segment, const std::string& scene,
                                             double rate, double image_rate, double attach_timeout,
                                             std::string* error) {
  std::unique_ptr<LiveSource> src(new LiveSource());
  src->segment_ = segment;
  src->period_ = 1.0 / rate;
  src->image_period_ = 1.0 / image_rate;
  // the segment first (retrying while it is not there yet), then the scene
  const double deadline = MonotonicSeconds() + attach_timeout;
  for (;;) {
    const shm::Status s = src->observer_.open(segment);
    if (s.ok()) break;
    if (s.code != shm::Error::kNoSegment || MonotonicSeconds() >= deadline) {
      *error = s.code == shm::Error::kNoSegment
                   ? "no segment '" + segment + "' (no producer is running under that name: start "
                     "one, e.g. 'sim_host --segment " + segment + " SCENE', or give its --segment)"
                   : "segment '" + segment + "': " + s.message;
      return nullptr;
    }
    usleep(20000);
  }
  src->geometry_ = SceneGeometry::Load(scene, error);
  if (!src->geometry_) return nullptr;
  // the scene must hold the producer's robot
  const std::string mismatch =
      model::CheckModelMatches(src->geometry_->model(), src->geometry_->robot(), src->observer_.header());
  if (!mismatch.empty()) {
    *error = "the scene '" + scene + "' does not hold the robot of segment '" + segment + "': " +
             mismatch + " (pass the producer's scene with --scene FILE)";
    return nullptr;
  }
  src->thread_ = std::thread([s = src.get()] { s->Loop(); });
  if (src->observer_.header().ncamera > 0) src->image_thread_ = std::thread([s = src.get()] { s->ImageLoop(); });
  return src;
}

LiveSource::~LiveSource() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (image_thread_.joinable()) image_thread_.join();
  // the observer's close() (its destructor) withdraws any image request left
}

nlohmann::json LiveSource::Hello() {
  const shm::SegmentHeader& h = observer_.header();
  nlohmann::json j;
  j["mode"] = "live";
  // walk.csv is written when the walk ends (controllers/src/walk_report.cc): the plan overlays
  // are replay-only
  j["plan"] = {{"note", "replay only: the walk writes walk.csv when it ends"}};
  j["reach"] = {{"note", "replay only: reach writes its plan log when it ends"}};
  j["title"] = "segment " + segment_;
  j["scene"] = geometry_->Describe();
  j["producer"] = h.producer_kind == shm::ProducerKind::kSimulation ? "simulation"
                  : h.producer_kind == shm::ProducerKind::kHardware ? "hardware"
                  : h.producer_kind == shm::ProducerKind::kReplay   ? "replay"
                                                                    : "unknown";
  j["control_period"] = h.control_period;
  j["cameras"] = h.ncamera;
  nlohmann::json cams = nlohmann::json::array();
  for (int c = 0; c < h.ncamera; ++c)
    cams.push_back({{"name", h.cameras[c].name}, {"width", h.cameras[c].width}, {"height", h.cameras[c].height}});
  j["camera_list"] = cams;
  j["image_rate"] = 1.0 / image_period_;
  return j;
}

void LiveSource::WatchImages(int delta) { image_watchers_ += delta; }

bool LiveSource::NewestImages(uint64_t sent[shm::kMaxCameras], double timeout,
                              std::shared_ptr<const std::string> out[shm::kMaxCameras]) {
  std::unique_lock lock(mutex_);
  auto fresh = [&] {
    for (int c = 0; c < shm::kMaxCameras; ++c)
      if (image_version_[c] > sent[c]) return true;
    return false;
  };
  cv_.wait_for(lock, std::chrono::duration<double>(timeout), fresh);
  bool any = false;
  for (int c = 0; c < shm::kMaxCameras; ++c) {
    out[c] = nullptr;
    if (image_version_[c] > sent[c]) {
      out[c] = image_[c];
      sent[c] = image_version_[c];
      any = true;
    }
  }
  return any;
}

// Asks the producer for every camera while some page watches (and withdraws when none does),
// copies the newest frame of each camera at most every image_period_ and turns it into an
// image message. read_image is a seqlocked copy: the producer never waits for it, and nothing
// is held while the pages' threads send.
void LiveSource::ImageLoop() {
  const int ncamera = observer_.header().ncamera;
  const uint32_t all = (1u << ncamera) - 1;
  auto slot = std::make_unique<shm::ImageSlot>();  // about 2 MB, once
  uint32_t asked = 0;
  uint64_t last[shm::kMaxCameras] = {};
  double next[shm::kMaxCameras] = {};
  while (!stop_) {
    const uint32_t want = image_watchers_ > 0 && !ended_ ? all : 0;
    if (want != asked) {
      if (observer_.request_images(want)) {
        asked = want;
        image_request_failed_ = false;
      } else {
        image_request_failed_ = true;  // every request entry is held: retried
      }
    }
    if (!asked) {
      usleep(20000);
      continue;
    }
    const double now = MonotonicSeconds();
    for (int c = 0; c < ncamera; ++c) {
      if (now < next[c] || observer_.read_image(c, last[c], slot.get()) != shm::ImageResult::kOk) continue;
      last[c] = slot->frame;
      next[c] = now + image_period_;
      const int32_t head[4] = {c, slot->width, slot->height, 0};
      const double stamp[2] = {slot->time, static_cast<double>(slot->frame)};
      const size_t n = static_cast<size_t>(slot->width) * slot->height * 3;
      auto msg = std::make_shared<std::string>(sizeof head + sizeof stamp + n, '\0');
      std::memcpy(msg->data(), head, sizeof head);
      std::memcpy(msg->data() + sizeof head, stamp, sizeof stamp);
      std::memcpy(msg->data() + sizeof head + sizeof stamp, slot->rgb, n);
      {
        std::lock_guard lock(mutex_);
        image_[c] = std::move(msg);
        ++image_version_[c];
      }
      cv_.notify_all();
    }
    usleep(10000);
  }
  if (asked) observer_.request_images(0);
}

std::shared_ptr<const std::string> LiveSource::Newest(uint64_t after, double timeout, uint64_t* version) {
  std::unique_lock lock(mutex_);
  cv_.wait_for(lock, std::chrono::duration<double>(timeout), [&] { return version_.load() > after; });
  *version = version_.load();
  return frame_;
}

// reads every block it can, makes a frame at most every period_ (and the last one)
void LiveSource::Loop() {
  shm::SensorBlock block{};
  double next = 0;
  bool have = false, ended = false;
  while (!stop_ && !ended) {
    const shm::ReadResult r = observer_.read(&block, 0.1);
    if (r == shm::ReadResult::kOk) have = true;
    ended = r == shm::ReadResult::kProducerGone || r == shm::ReadResult::kProducerStopped ||
            r == shm::ReadResult::kNotOpen;
    const double now = MonotonicSeconds();
    if (!have || (now < next && !ended)) continue;
    next = now + period_;
    auto frame = std::make_shared<const std::string>(MakeFrame(block, ended));
    {
      std::lock_guard lock(mutex_);
      frame_ = std::move(frame);
      ++version_;
    }
    cv_.notify_all();
  }
  ended_ = true;
}

std::string LiveSource::MakeFrame(const shm::SensorBlock& s, bool ended) {
  const shm::SegmentHeader& h = observer_.header();
  RobotState state;
  const bool simulated = s.status & shm::status::kSimulated;
  // the base: ground truth in simulation, else the first IMU's orientation at the model's height
  if (simulated) {
    for (int k = 0; k < 3; ++k) state.p_WB[k] = s.sim_truth.p_WB[k];
    for (int k = 0; k < 4; ++k) state.quat_WB[k] = s.sim_truth.quat_WB[k];
  } else {
    const mjModel* m = geometry_->model();
    const int adr = geometry_->robot().base_qpos;
    if (adr >= 0)
      for (int k = 0; k < 3; ++k) state.p_WB[k] = m->qpos0[adr + k];
    if (h.nimu > 0)
      for (int k = 0; k < 4; ++k) state.quat_WB[k] = s.imu[0].quat_WI[k];
  }
  state.q.assign(s.q, s.q + h.njoint);
  state.ft.assign(s.force, s.force + h.nforce);
  nlohmann::json j;
  j["t"] = s.time;
  j["cycle"] = s.cycle;
  j["poses"] = geometry_->Poses(state);
  j["q"] = state.q;
  // the references: the last command block the controller wrote
  shm::CommandBlock cmd{};
  if (observer_.commands(&cmd)) {
    nlohmann::json qref = nlohmann::json::array();
    for (int i = 0; i < h.njoint; ++i)
      qref.push_back(cmd.joint[i].mode == shm::JointMode::kPosition ? cmd.joint[i].q_ref : NAN);
    j["qref"] = qref;
  }
  nlohmann::json fz = nlohmann::json::array();
  for (int i = 0; i < h.nforce; ++i) fz.push_back(s.force[i].force[2]);
  j["fz"] = fz;
  double zmp[2];
  j["zmp"] = geometry_->Zmp(state, zmp) ? nlohmann::json{zmp[0], zmp[1]} : nlohmann::json(nullptr);
  j["balance"] = geometry_->Balance(state);
  j["status"] = StatusNames(s.status);
  j["counters"] = {{"late_commands", s.late_commands},
                   {"rejected_commands", s.rejected_commands},
                   {"last_command_cycle", s.last_command_cycle}};
  j["base"] = simulated ? "ground truth" : "estimated from IMU";
  j["ended"] = ended;
  if (h.ncamera > 0)
    j["images"] = image_request_failed_ ? "refused (every image request entry of the segment is held)"
                  : image_watchers_ > 0 ? "asked" : "not asked";
  // NaN (no reference) is not JSON: it is written as null
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace ohrp::view
