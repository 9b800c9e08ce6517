// ohrp identify --sensors --model: the F/T sensors' offsets from a log where what hangs below each
// sensor is free (the rig: mjcf/hrp1s/scene_hung.xml, keyframe rig), against the model's static
// load (identify/sensors.h).
//
// Closed form: still, the sensor carries the weight of its subtree (the bodies below its site's
// body), mass M, centre of mass c, hanging from the site at p with orientation R (world z up):
//   force  = R^T (0, 0, -M g)              (MuJoCo's force and torque sensors: the load the
//   torque = R^T ((c - p) x (0, 0, -M g))   subtree puts on the site, its weight and moment)
// the joints at their logged means less their encoders' biases where EstimateEncoderBias found
// them (a biased reading puts the subtree elsewhere), the rest at the keyframe. The offset is the logged mean less
// that; its standard error the mean's (batch means). A subtree touching anything (a foot on the
// floor) carries other loads: its offset is not this (refused: a contact on the subtree).
#include <mujoco/mujoco.h>

#include <cmath>

#include "identify/sensors.h"
#include "robot_model/model.h"

namespace ohrp::identify {

bool EstimateForceBias(const JointModel& model_in, double gravity, SensorEstimates* s,
                       std::string* error) {
  auto scene = model::Scene::Load(model_in.model, error);
  if (!scene || !scene->Reset(model_in.keyframe, error)) return false;
  mjModel* m = scene->m();
  mjData* d = scene->d();
  for (size_t k = 0; k < s->joints.size(); ++k) {
    const int j = mj_name2id(m, mjOBJ_JOINT, s->joints[k].c_str());
    if (j < 0) return *error = s->joints[k] + ": " + model_in.model + " has no such joint", false;
    // the joint where it is: its reading less the encoder's bias when that was identified
    const bool biased = k < s->encoder_bias.size() && s->encoder_observable[k];
    d->qpos[m->jnt_qposadr[j]] = s->joint_mean[k] - (biased ? s->encoder_bias[k].value : 0.0);
  }
  mju_zero(d->qvel, m->nv);
  mj_forward(m, d);
  s->ft_expected.assign(6 * s->forces.size(), 0.0);
  s->ft_bias.assign(6 * s->forces.size(), Stat{});
  for (size_t f = 0; f < s->forces.size(); ++f) {
    const int site = mj_name2id(m, mjOBJ_SITE, s->forces[f].c_str());
    if (site < 0) return *error = s->forces[f] + ": " + model_in.model + " has no such site", false;
    const int body = m->site_bodyid[site];
    // a contact on the subtree: the sensor carries more than its weight
    for (int c = 0; c < d->ncon; ++c)
      for (int g : {d->contact[c].geom1, d->contact[c].geom2})
        for (int b = m->geom_bodyid[g]; b > 0; b = m->body_parentid[b])
          if (b == body)
            return *error = "F/T " + s->forces[f] + ": the model at the logged posture has a "
                            "contact below the sensor (a foot on the floor?): its offset needs "
                            "the subtree hanging free (the rig: scene_hung.xml --keyframe rig)", false;
    const double mass = m->body_subtreemass[body];
    const double weight[3] = {0, 0, -mass * gravity};
    double lever[3], moment[3];
    mju_sub3(lever, d->subtree_com + 3 * body, d->site_xpos + 3 * site);
    mju_cross(moment, lever, weight);
    double fs[3], ts[3];
    mju_mulMatTVec(fs, d->site_xmat + 9 * site, weight, 3, 3);  // R^T
    mju_mulMatTVec(ts, d->site_xmat + 9 * site, moment, 3, 3);
    for (int k = 0; k < 3; ++k) {
      s->ft_expected[6 * f + k] = fs[k], s->ft_expected[6 * f + 3 + k] = ts[k];
    }
    for (int k = 0; k < 6; ++k) {
      const Stat& mean = s->ft_mean[6 * f + k];
      s->ft_bias[6 * f + k] = {mean.value - s->ft_expected[6 * f + k], mean.se};
    }
  }
  return true;
}

}  // namespace ohrp::identify
