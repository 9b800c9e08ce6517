// reach's hand-pose goal: the group's joints by the shared limb IK from the stance pose.
#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "controllers/reach.h"
#include "robot_model/ik.h"

namespace ohrp::controllers {

ConfigStatus GoalFromHandPose(model::Kinematics& kin, const planning::JointGroup& group,
                              const HandGoal& hand, const std::vector<double>& stance,
                              std::vector<double>* goal) {
  auto bad = [](const std::string& what) {
    return ConfigStatus::Fail(ConfigError::kOption, "--goal-pose: " + what);
  };
  const mjModel* m = kin.m();
  // the hand: a site, else a body (its frame; a robot without hand sites, as menagerie's G1)
  const int site = kin.SiteId(hand.site);
  const int body = site < 0 ? mj_name2id(m, mjOBJ_BODY, hand.site.c_str()) : -1;
  if (site < 0 && body < 0) {
    std::string known;
    for (int i = 0; i < m->nsite; ++i) {
      const char* n = mj_id2name(m, mjOBJ_SITE, i);
      if (n) known += std::string(known.empty() ? "" : ", ") + n;
    }
    return bad("the robot has no site or body '" + hand.site + "' (its sites: " + known + ")");
  }
  const int first = kin.JointId(group.names[0]);
  if (first < 0) return bad("the model has no joint '" + group.names[0] + "'");
  const int root = m->body_parentid[m->jnt_bodyid[kin.robot().joints[first].joint_id]];
  const int tip = site >= 0 ? m->site_bodyid[site] : body;
  Eigen::Vector3d p_TipT = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_TipT = Eigen::Quaterniond::Identity();
  if (site >= 0) {
    p_TipT = Eigen::Vector3d(m->site_pos[3 * site], m->site_pos[3 * site + 1], m->site_pos[3 * site + 2]);
    q_TipT = Eigen::Quaterniond(m->site_quat[4 * site], m->site_quat[4 * site + 1],
                                m->site_quat[4 * site + 2], m->site_quat[4 * site + 3]);
  }
  model::IkOptions options;
  options.max_iterations = 200;
  if (!hand.orientation) {  // the position only: the rotation error neither weighed nor judged
    options.orientation_weight = 0;
    options.orientation_tolerance = 4;
  }
  try {
    model::LimbIk ik(kin, root, tip, p_TipT, q_TipT.normalized().toRotationMatrix(), options);
    std::vector<int> ids;
    for (const std::string& n : group.names) ids.push_back(kin.JointId(n));
    bool inside = true;
    for (int j : ik.chain()) inside = inside && std::find(ids.begin(), ids.end(), j) != ids.end();
    if (!inside) {
      std::string chain;
      for (int j : ik.chain()) chain += (chain.empty() ? "" : ",") + kin.robot().joints[j].name;
      return bad("the joints from '" + group.names[0] + "' to site '" + hand.site + "' (" + chain +
                 ") are not all in the group (--group must hold that chain; its other joints keep their stance values)");
    }
    std::vector<double> q = stance;
    q.resize(kin.njoint());
    kin.SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
    kin.SetJointPositions(q.data());
    kin.UpdatePositions();
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(hand.rpy.z(), Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(hand.rpy.y(), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(hand.rpy.x(), Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    const model::IkResult r = ik.Solve(kin, hand.p_B, R, q.data());
    if (r.status != model::IkStatus::kConverged) {
      char text[320];
      const Eigen::Vector3d p = ik.p_WT(kin);
      std::snprintf(text, sizeof text,
                    "out of reach (%s): the closest pose found leaves the site %.1f mm%s from it, "
                    "at (%.3f, %.3f, %.3f) m in the base frame",
                    model::IkStatusName(r.status), 1e3 * r.position_error,
                    hand.orientation ? (" and " + std::to_string(r.orientation_error) + " rad").c_str() : "",
                    p.x(), p.y(), p.z());
      return bad(text);
    }
    goal->clear();
    for (int id : ids) goal->push_back(q[id]);
  } catch (const std::invalid_argument& e) {
    return bad(e.what());
  }
  return ConfigStatus::Ok();
}

}  // namespace ohrp::controllers
