// reach's hand-pose goal: the group's joints by the shared limb IK from the stance pose, one
// limb per hand (two hands: two chains of the group, each solved for its own site).
#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "controllers/reach.h"
#include "robot_model/ik.h"

namespace ohrp::controllers {
namespace {

// where the hand is: a site, else a body's frame (a robot without hand sites, as menagerie's G1)
struct Hand {
  int site = -1, body = -1;
  Eigen::Vector3d p_TipT = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_TipT = Eigen::Quaterniond::Identity();
};

// `name` as a site or a body; "" or the reason
std::string FindHand(const mjModel* m, const model::Kinematics& kin, const std::string& name,
                     Hand* h) {
  h->site = kin.SiteId(name);
  h->body = h->site >= 0 ? m->site_bodyid[h->site] : mj_name2id(m, mjOBJ_BODY, name.c_str());
  if (h->body < 0) {
    std::string known;
    for (int i = 0; i < m->nsite; ++i) {
      const char* n = mj_id2name(m, mjOBJ_SITE, i);
      if (n) known += std::string(known.empty() ? "" : ", ") + n;
    }
    return "the robot has no site or body '" + name + "' (its sites: " + known + ")";
  }
  if (h->site >= 0) {
    const mjtNum* p = m->site_pos + 3 * h->site;
    const mjtNum* q = m->site_quat + 4 * h->site;
    h->p_TipT = Eigen::Vector3d(p[0], p[1], p[2]);
    h->q_TipT = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
  }
  return "";
}

// the limb's root: the parent of the body nearest the base, on the way from the hand up, whose
// joint is one of the group's (`ids`: joint ids); -1 when no joint of the group moves the hand
int ChainRoot(const mjModel* m, const model::Kinematics& kin, const std::vector<int>& ids, int tip) {
  int root = -1;
  for (int b = tip; b > 0; b = m->body_parentid[b])
    for (int id : ids)
      if (id >= 0 && m->jnt_bodyid[kin.robot().joints[id].joint_id] == b) root = m->body_parentid[b];
  return root;
}

Eigen::Matrix3d Rpy(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace

ConfigStatus GoalFromHandPose(model::Kinematics& kin, const planning::JointGroup& group,
                              const std::vector<HandGoal>& hands, const std::vector<double>& stance,
                              std::vector<double>* goal) {
  auto bad = [](const std::string& what) {
    return ConfigStatus::Fail(ConfigError::kOption, "--goal-pose: " + what);
  };
  const mjModel* m = kin.m();
  std::vector<int> ids;
  for (const std::string& n : group.names) ids.push_back(kin.JointId(n));
  for (size_t i = 0; i < ids.size(); ++i)
    if (ids[i] < 0) return bad("the model has no joint '" + group.names[i] + "'");
  std::vector<double> q = stance;
  q.resize(kin.njoint());
  std::vector<int> taken(kin.njoint(), -1);  // per joint: the hand whose chain holds it
  for (size_t k = 0; k < hands.size(); ++k) {
    const HandGoal& hand = hands[k];
    Hand h;
    if (std::string why = FindHand(m, kin, hand.site, &h); !why.empty()) return bad(why);
    const int root = ChainRoot(m, kin, ids, h.body);
    if (root < 0) return bad("no joint of the group moves '" + hand.site + "'");
    model::IkOptions options;
    options.max_iterations = 200;
    if (!hand.orientation) {  // the position only: the rotation error neither weighed nor judged
      options.orientation_weight = 0;
      options.orientation_tolerance = 4;
    }
    try {
      model::LimbIk ik(kin, root, h.body, h.p_TipT, h.q_TipT.toRotationMatrix(), options);
      std::string chain;
      bool inside = true;
      for (int j : ik.chain()) {
        chain += (chain.empty() ? "" : ",") + kin.robot().joints[j].name;
        inside = inside && std::find(ids.begin(), ids.end(), j) != ids.end();
        if (taken[j] >= 0)
          return bad("the chains to '" + hands[taken[j]].site + "' and '" + hand.site +
                     "' share joint " + kin.robot().joints[j].name + ": one hand per limb");
        taken[j] = static_cast<int>(k);
      }
      if (!inside)
        return bad("the joints to '" + hand.site + "' (" + chain +
                   ") are not all in the group (--group must hold that chain; its other joints "
                   "keep their stance values)");
      kin.SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
      kin.SetJointPositions(q.data());
      kin.UpdatePositions();
      const model::IkResult r = ik.Solve(kin, hand.p_B, Rpy(hand.rpy), q.data());
      if (r.status != model::IkStatus::kConverged) {
        char text[360];
        const Eigen::Vector3d p = ik.p_WT(kin);
        std::snprintf(text, sizeof text,
                      "'%s' out of reach (%s): the closest pose found leaves the site %.1f mm%s "
                      "from it, at (%.3f, %.3f, %.3f) m in the base frame",
                      hand.site.c_str(), model::IkStatusName(r.status), 1e3 * r.position_error,
                      hand.orientation ? (" and " + std::to_string(r.orientation_error) + " rad").c_str() : "",
                      p.x(), p.y(), p.z());
        return bad(text);
      }
    } catch (const std::invalid_argument& e) {
      return bad(e.what());
    }
  }
  goal->clear();
  for (int id : ids) goal->push_back(q[id]);
  return ConfigStatus::Ok();
}

}  // namespace ohrp::controllers
