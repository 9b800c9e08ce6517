// sim_host's names for the producers' data log, which lives in the lower layer
// (robot_model/recorder.h) so that hw_driver writes the same format.
#pragma once

#include "robot_model/recorder.h"
#include "sim_host/model.h"

namespace ohrp::sim {

using model::Recorder;
using model::RecorderChannels;

}  // namespace ohrp::sim
