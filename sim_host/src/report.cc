// End-of-run report and summary (see report.h).
#include "sim_host/report.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <algorithm>
#include <nlohmann/json.hpp>

#include "robot_model/kinematics.h"
#include "robot_model/output_file.h"

namespace ohrp::sim {

const char* IntegratorName(int integrator) {
  switch (integrator) {
    case mjINT_EULER: return "euler";
    case mjINT_RK4: return "rk4";
    case mjINT_IMPLICIT: return "implicit";
  }
  return "unknown";
}

std::vector<SoleRectangle> SoleRectangles(const mjModel* m, const model::RobotMap& robot) {
  std::vector<SoleRectangle> out;
  mjData* d = mj_makeData(m);
  if (!d) return out;
  mj_kinematics(m, d);  // the reference configuration qpos0
  mj_comPos(m, d);      // subtree centres of mass
  for (const model::SoleMap& s : model::FindSoles(m, robot)) {
    if (s.force_sensor < 0) continue;
    const int site = robot.forces[s.force_sensor].site_id;
    const mjtNum* p_WS = d->site_xpos + 3 * site;     // sensor origin in W
    const mjtNum* R_WS = d->site_xmat + 9 * site;     // sensor axes in W (row-major)
    const mjtNum* p_WG = d->geom_xpos + 3 * s.geom_id;
    const mjtNum* R_WG = d->geom_xmat + 9 * s.geom_id;
    SoleRectangle r;
    r.sensor = robot.forces[s.force_sensor].name;
    r.sole = s.name;
    r.x[0] = r.y[0] = 1e300;
    r.x[1] = r.y[1] = -1e300;
    r.z = 0;
    // the four corners of the bottom face, from W into the sensor frame: p_S = R_WS^T (p_W - p_WS)
    for (int c = 0; c < 4; ++c) {
      const double local[3] = {(c & 1 ? 1 : -1) * s.half_size[0], (c & 2 ? 1 : -1) * s.half_size[1],
                               -s.half_size[2]};
      double p_S[3] = {0, 0, 0};
      for (int i = 0; i < 3; ++i) {
        double w = p_WG[i] - p_WS[i];
        for (int k = 0; k < 3; ++k) w += R_WG[3 * i + k] * local[k];
        for (int a = 0; a < 3; ++a) p_S[a] += R_WS[3 * i + a] * w;
      }
      r.x[0] = std::min(r.x[0], p_S[0]);
      r.x[1] = std::max(r.x[1], p_S[0]);
      r.y[0] = std::min(r.y[0], p_S[1]);
      r.y[1] = std::max(r.y[1], p_S[1]);
      r.z += 0.25 * p_S[2];
    }
    // the mass below the sensor and its centre of mass in the sensor frame
    const int b = m->site_bodyid[site];
    r.foot_mass = m->body_subtreemass[b];
    for (int a = 0; a < 3; ++a) {
      r.foot_com[a] = 0;
      for (int i = 0; i < 3; ++i) r.foot_com[a] += R_WS[3 * i + a] * (d->subtree_com[3 * b + i] - p_WS[i]);
    }
    out.push_back(r);
  }
  mj_deleteData(d);
  return out;
}

double RealTimeFactor(double sim_time, const RunStats& st, double now) {
  const double running = now - st.wall_start - st.wall_waiting;
  return running > 0 ? sim_time / running : 0.0;
}

void PrintReport(const RunStats& st) {
  const double wall = st.wall_end - st.wall_start;
  std::fprintf(stderr,
               "sim_host: %s: %.3f s simulated in %.3f s wall (%.3f s of it waiting for a "
               "controller): %.2fx real time while simulating, %lu steps, "
               "%lu cycles, %lu commands, %lu late, %lu rejected, %ld MuJoCo warnings\n",
               st.outcome.c_str(), st.sim_time, wall, st.wall_waiting,
               RealTimeFactor(st.sim_time, st, st.wall_end),
               static_cast<unsigned long>(st.steps), static_cast<unsigned long>(st.cycles),
               static_cast<unsigned long>(st.commands), static_cast<unsigned long>(st.late),
               static_cast<unsigned long>(st.rejected), st.warnings);
  if (st.fall.fell)
    std::fprintf(stderr, "sim_host: FELL at t=%.3f s (cycle %lu): %s\n", st.fall.record.time,
                 static_cast<unsigned long>(st.fall.record.cycle), st.fall.cause.c_str());
  // the self_collision effect: each pair with its first contact and deepest penetration
  if (st.self_collision.on) {
    const SelfCollisionSummary& sc = st.self_collision;
    std::string pairs;
    for (const SelfCollisionHit& h : sc.pairs) {
      char b[256];
      std::snprintf(b, sizeof(b), "%s%s from %.3f s, deepest %.1f mm at %.3f s, %lu cycles",
                    pairs.empty() ? "" : "; ", h.pair.c_str(), h.first_time, 1e3 * h.deepest,
                    h.deepest_time, static_cast<unsigned long>(h.cycles));
      pairs += b;
    }
    char closest[160];
    if (sc.closest_exact)
      std::snprintf(closest, sizeof(closest), "closest approach %.1f mm (%s at %.3f s)",
                    1e3 * sc.closest, sc.closest_pair.c_str(), sc.closest_time);
    else
      std::snprintf(closest, sizeof(closest), "closest approach above %.0f mm", 1e3 * sc.closest);
    std::fprintf(stderr,
                 "sim_host: self-collision: %lu of %lu cycles with links in contact (%d pairs "
                 "checked, %.1f us per check), %s%s%s\n",
                 static_cast<unsigned long>(sc.cycles_in_contact),
                 static_cast<unsigned long>(sc.checks), sc.pairs_checked,
                 sc.checks ? 1e6 * sc.check_seconds / sc.checks : 0.0, closest,
                 pairs.empty() ? "" : ": ", pairs.c_str());
  }
  // the controller's self-collision guard: its holds, the first and the closest
  if (st.guard.episodes > 0) {
    const GuardSummary& g = st.guard;
    std::string what;
    if (!g.holds.empty()) {
      const GuardHold& f = g.holds.front();
      const GuardHold& c = g.holds[g.closest];
      char b[320];
      std::snprintf(b, sizeof(b), ": first %s at %.1f mm (t=%.3f s), closest %s at %.1f mm (t=%.3f s)%s",
                    f.pair, 1e3 * f.distance, f.begin, c.pair, 1e3 * c.closest, c.begin,
                    g.holding_at_end ? "; still holding at the end" : "");
      what = b;
    }
    std::fprintf(stderr, "sim_host: self-collision guard: %lu holds, %lu command blocks held%s\n",
                 static_cast<unsigned long>(g.episodes), static_cast<unsigned long>(g.held_cycles),
                 what.c_str());
  }
  // the actuators that could not give the servo's torque
  if (st.clamped > 0) {
    std::string joints;
    for (const auto& [name, steps] : st.clamped_joints) {
      joints += " " + name + " (" + std::to_string(steps) + ")";
    }
    std::fprintf(stderr,
                 "sim_host: actuators clamped the servo's torque in %lu joint-steps "
                 "(ctrlrange or forcerange):%s\n",
                 static_cast<unsigned long>(st.clamped), joints.c_str());
  }
}

namespace {

// the summary's "self_collision_guard" (report.h)
nlohmann::json GuardJson(const GuardSummary& g) {
  nlohmann::json holds = nlohmann::json::array();
  for (const GuardHold& h : g.holds)
    holds.push_back({{"begin", h.begin}, {"begin_cycle", h.begin_cycle}, {"end", h.end},
                     {"end_cycle", h.end_cycle}, {"pair", h.pair},
                     {"distance_mm", 1e3 * h.distance}, {"closest_mm", 1e3 * h.closest},
                     {"cycles", h.cycles}});
  auto at = [&](const GuardHold& h, double distance) -> nlohmann::json {
    return {{"pair", h.pair}, {"distance_mm", 1e3 * distance}, {"time", h.begin},
            {"cycle", h.begin_cycle}};
  };
  nlohmann::json first = nullptr, closest = nullptr;
  if (!g.holds.empty()) {
    first = at(g.holds.front(), g.holds.front().distance);
    closest = at(g.holds[g.closest], g.holds[g.closest].closest);
  }
  return {{"hold_episodes", g.episodes}, {"held_cycles", g.held_cycles},
          {"controller_holds", g.controller_holds}, {"holding_at_end", g.holding_at_end},
          {"first", first}, {"closest", closest}, {"holds", holds}};
}

}  // namespace

bool WriteSummary(const std::string& path, const HostOptions& o, const model::RobotMap& robot,
                  const mjModel* m, const RunStats& st, int exit_code,
                  const EffectsPlan* effects) {
  const double wall = st.wall_end - st.wall_start;
  nlohmann::json j;
  j["outcome"] = st.outcome;
  j["detail"] = st.detail;
  j["exit_code"] = exit_code;
  j["scene"] = o.scene;
  j["robot"] = robot.name;
  j["robot_mass"] = robot.total_mass;
  j["gravity"] = {m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]};
  j["physics_dt"] = m->opt.timestep;
  j["control_period"] = o.control_period;
  j["integrator"] = IntegratorName(m->opt.integrator);
  j["mode"] = o.realtime ? "realtime" : "lockstep";
  j["contact"] = st.contact;
  if (st.contact == "soft") {
    const auto& cp = o.feet.params;
    j["contact_params"] = {{"stiffness", cp.stiffness},
                           {"exponent", cp.exponent},
                           {"damping", cp.damping},
                           {"friction", cp.friction},
                           {"tangential_stiffness", cp.tangential_stiffness},
                           {"tangential_damping", cp.tangential_damping}};
    j["contact_file"] = o.contact_file;
  }
  if (!o.record_images.empty()) {
    j["images"] = {{"dir", o.record_images}, {"frames", st.images_recorded},
                   {"waited_s", st.images_waited}, {"error", st.images_error},
                   {"index", o.record_images + "/images.csv"}};
  }
  if (!o.joint_file.empty()) {
    // the joints' values as they ran (robot_model/joint_params.h)
    j["joint_file"] = o.joint_file;
    nlohmann::json joints = nlohmann::json::array();
    for (const model::JointParams& p : o.joints) {
      const int dof = m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, p.joint.c_str())];
      joints.push_back({{"joint", p.joint}, {"armature", m->dof_armature[dof]},
                        {"damping", m->dof_damping[dof]}, {"frictionloss", m->dof_frictionloss[dof]},
                        {"delay", std::isnan(p.delay) ? 0.0 : p.delay}});
    }
    j["joint_params"] = joints;
  }
  if (!o.sensor_file.empty()) {
    // the sensors' bias and noise as they ran (robot_model/sensor_params.h) and their seed
    j["sensor_file"] = o.sensor_file;
    j["sensor_seed"] = o.sensor_seed;
  }
  j["fcl_queries"] = st.fcl_queries;
  j["contact_pairs"] = st.contact_pairs;
  j["contact_pairs_bounded"] = st.contact_pairs_bounded;
  j["sim_time"] = st.sim_time;
  j["wall_time"] = wall;
  j["wall_waiting"] = st.wall_waiting;  // of wall_time, waiting for a controller (time frozen)
  j["real_time_factor"] = RealTimeFactor(st.sim_time, st, st.wall_end);
  j["steps"] = st.steps;
  // wall time per control cycle once a controller answers (attach and set-up excluded)
  const uint64_t loop_cycles = st.cycles - st.cycles_at_first_command;
  j["wall_per_cycle"] = st.commands > 0 && loop_cycles > 0
                            ? (st.wall_end - st.wall_first_command) / loop_cycles
                            : 0.0;
  j["cycles"] = st.cycles;
  j["commands"] = st.commands;
  j["late_commands"] = st.late;
  j["rejected_commands"] = st.rejected;
  j["actuator_clamped_steps"] = st.clamped;
  nlohmann::json clamped = nlohmann::json::object();
  for (const auto& [name, steps] : st.clamped_joints) clamped[name] = steps;
  j["actuator_clamped_per_joint"] = clamped;
  j["controller_losses"] = st.controller_losses;
  j["controllers_seen"] = st.controllers_seen;
  j["mujoco_warnings"] = st.warnings;
  nlohmann::json events = nlohmann::json::array();
  for (const HostEvent& e : st.events) {
    events.push_back({{"time", e.time}, {"cycle", e.cycle}, {"event", e.kind}, {"value", e.value}});
    if (std::string(e.kind) == "fall") events.back()["cause"] = st.fall.cause;
    if (std::string(e.kind).rfind("guard_hold_", 0) == 0 && e.value >= 0 &&
        e.value < static_cast<int64_t>(st.guard.holds.size())) {
      const GuardHold& h = st.guard.holds[e.value];
      events.back()["pair"] = h.pair;
      events.back()["distance_mm"] = 1e3 * h.distance;
    }
  }
  j["events"] = events;
  j["self_collision_guard"] = GuardJson(st.guard);
  j["fall_watch"] = {{"on", st.fall.on}, {"text", st.fall.watch},
                     {"start_height", st.fall.start_height}, {"min_height", st.fall.min_height},
                     {"max_tilt_deg", st.fall.max_tilt}, {"on_fall", OnFallName(o.fall.on_fall)},
                     {"allow_contact", o.fall.allow_contact}};
  if (st.fall.fell) {
    const FallRecord& f = st.fall.record;
    j["fall"] = {{"time", f.time}, {"cycle", f.cycle}, {"kind", FallKindName(f.kind)},
                 {"cause", st.fall.cause}, {"body", st.fall.body}, {"geom", st.fall.geom},
                 {"ground", st.fall.ground}, {"depth", f.depth}, {"height", f.height},
                 {"tilt_deg", f.tilt}};
  } else {
    j["fall"] = nullptr;
  }
  j["events_dropped"] = st.events_dropped;
  if (st.divergence.kind != DivergenceKind::kNone) {
    const Diagnosis& x = st.divergence;
    nlohmann::json dofs = nlohmann::json::array();
    for (const auto& r : x.dofs)
      dofs.push_back({{"joint", r.joint}, {"body", r.body}, {"qvel", r.qvel}, {"qacc", r.qacc},
                      {"inertia", r.inertia}});
    j["divergence"] = {{"kind", DivergenceKindName(x.kind)}, {"step", x.step}, {"time", x.time},
                       {"what", x.what}, {"dofs", dofs}, {"bodies", x.bodies},
                       {"contacts", x.contacts}, {"cause", x.cause}, {"suggestion", x.suggestion},
                       {"energy", x.energy}, {"energy_start", x.energy_start},
                       {"input_work", x.input_work}, {"text", x.Text()}};
  }
  j["log_rows"] = st.log_rows;  // on disk
  j["log_dropped"] = st.log_dropped;
  j["log_rows_lost"] = st.log_lost;
  j["log_rows_over_limit"] = st.log_over_limit;
  j["log_bytes"] = st.log_bytes;
  j["log_max_bytes"] = o.log_max;
  j["log_error"] = st.log_error;
  nlohmann::json below = nlohmann::json::object();
  for (const auto& f : robot.forces) below[f.name] = m->body_subtreemass[m->site_bodyid[f.site_id]];
  j["mass_below"] = below;
  nlohmann::json soles = nlohmann::json::object();
  for (const SoleRectangle& r : SoleRectangles(m, robot))
    soles[r.sensor] = {{"sole", r.sole}, {"x", {r.x[0], r.x[1]}}, {"y", {r.y[0], r.y[1]}}, {"z", r.z},
                       {"foot_mass", r.foot_mass},
                       {"foot_com", {r.foot_com[0], r.foot_com[1], r.foot_com[2]}}};
  j["soles"] = soles;
  if (effects) {
    nlohmann::json e = nlohmann::json::object();
    for (int i = 0; i < kEffectCount; ++i) {
      const EffectState& x = effects->effects[i];
      e[EffectName(static_cast<Effect>(i))] = {{"on", x.on}, {"reason", x.reason}};
    }
    j["effects"] = e;
    nlohmann::json pairs = nlohmann::json::array();
    for (const auto& cp : effects->pairs)
      pairs.push_back({{"pair", cp.name}, {"on", cp.on}, {"reason", cp.reason}});
    j["contact_pairs_native"] = pairs;
  }
  if (st.self_collision.on) {
    const SelfCollisionSummary& sc = st.self_collision;
    nlohmann::json pairs = nlohmann::json::array();
    for (const SelfCollisionHit& h : sc.pairs)
      pairs.push_back({{"pair", h.pair}, {"first_time", h.first_time}, {"first_cycle", h.first_cycle},
                       {"deepest", h.deepest}, {"deepest_time", h.deepest_time}, {"cycles", h.cycles}});
    j["self_collision"] = {{"source", sc.source}, {"links", sc.links},
                           {"pairs_checked", sc.pairs_checked}, {"excluded", sc.excluded},
                           {"checks", sc.checks}, {"measured", sc.measured},
                           {"cycles_in_contact", sc.cycles_in_contact},
                           {"check_mean_s", sc.checks ? sc.check_seconds / sc.checks : 0.0},
                           {"check_max_s", sc.check_max}, {"pairs", pairs},
                           {"closest_mm", 1e3 * sc.closest}, {"closest_exact", sc.closest_exact},
                           {"closest_pair", sc.closest_pair}, {"closest_t", sc.closest_time},
                           {"closest_cycle", sc.closest_cycle}};
  }
  std::string error;
  if (model::WriteWholeFile(path, j.dump(2) + "\n", &error)) return true;
  std::fprintf(stderr, "sim_host: --summary: %s\n", error.c_str());
  return false;
}

}  // namespace ohrp::sim
