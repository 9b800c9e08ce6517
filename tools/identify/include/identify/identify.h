// ohrp identify: the soft soles' stiffness K and damping D from a recording of the standing
// robot's damped rocking (the paper's figure 12 experiment, scenarios/rocking_fig12.yaml):
//   (a) the recording's rocking frequency and decay (compare/oscillation.h on one channel over
//       the free oscillation after the push) through the linearised model (rocking.h, with the
//       robot's mass, inertia and centre of mass from the model in the recorded posture):
//       K_a, D_a, their standard errors propagated from the measurement's;
//   (b) simulations of the same experiment (the scenario with the soles' K and D set as its
//       contact_params.stiffness and .damping) around the estimate, each stage one sweep
//       (ohrp::sweep, its runs in parallel locally or as a Slurm array job): the simulated
//       frequency against K at D_a (three runs, a line through them:
//       K where it equals the recording's), then the simulated log decrement against D at that
//       K (three runs): the mismatch of frequency and decay brought to zero. The simulations
//       are measured with the recording's noise added (its sigma from the channel, the mean of
//       8 seeded draws), so that noise biases both measurements alike;
//   (c) their uncertainty: the measurement's standard error through the slopes of (b)
//       (sigma_K = sigma_f / |df/dK|, sigma_D = sigma_delta / |d delta/dD|), and a final run at
//       (K, D) compared with the recording (compare-logs RMS, frequency and decay differences).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sweep/sweep.h"

namespace ohrp::identify {

struct IdentifyOptions {
  std::string recording;          // the robot's data log (hw_driver --log)
  std::string scenario;           // the experiment (scenarios/rocking_fig12.yaml)
  std::string source_dir;         // data folder (cli::DataDir()): the scene is relative to it
  std::string bin_dir;            // ohrp_run, sim_host, the controllers (and ohrp_sweep for Slurm)
  sweep::Executor executor;       // how each stage's simulations run (local: in parallel)
  std::string channel = "rfsensor_ty,lfsensor_ty";  // the oscillating channel measured (a
                                  // comma-separated list: their sum, here both ankles' pitch
                                  // moments: twice the swing, sqrt 2 the noise)
  double settle = 0.15;           // [s] after the push's end before the free oscillation
  double window = 3.0;            // [s] of free oscillation measured
  double step = 0.15;             // relative step of the K and D runs around the estimate
  std::string out_dir;            // the stages' sweep folders, identify.json
  bool quiet = false;
};

struct Estimate {
  double k = 0, k_se = 0, d = 0, d_se = 0;
};

struct IdentifyResult {
  double lag = 0;                   // recording's time minus the simulation's (aligned on
                                    // the K stage's middle run)
  double first_lag = 0;             // the same aligned on the nominal run (default soles)
  Estimate first;                   // the closed form on that first alignment: the K stage's
                                    // centre
  double noise = 0;                 // the recording's noise on the channel (1 sigma), which
                                    // the simulations' channel gets too before it is measured
  double from = 0, to = 0;          // the simulation's window [s]
  double f = 0, f_se = 0, delta = 0, delta_se = 0;  // the recording's oscillation
  Estimate closed_form;             // (a), on the recording aligned again (lag)
  Estimate refined;                 // (b), (c); its k_se, d_se from the larger of the
                                    // measurement's standard errors and the noise's spread (d)
  double spread_f = 0, spread_delta = 0;  // (d) what the recording's noise alone moves f, delta
  double final_f = 0, final_delta = 0, final_rms = 0;  // the run at the refined K, D
  double nominal_rms = 0;           // the recording against the nominal run (sim_host's default
                                    // soles) over the window: the RMS before identification
  nlohmann::json runs = nlohmann::json::array();      // every simulation: K, D, f, delta, dir
  nlohmann::json sweeps = nlohmann::json::array();    // every stage's sweep: folder, wall time
};

// Exit code 0, or 2 (bad input: files, channel, no oscillation in the recording) or 1 (a
// simulation failed) with *error.
int Identify(const IdentifyOptions& o, IdentifyResult* r, std::string* error);

}  // namespace ohrp::identify
