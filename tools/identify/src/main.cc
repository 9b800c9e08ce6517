// ohrp_identify: the soft soles' stiffness and damping from a recording of the standing robot's
// damped rocking (see identify/identify.h, docs/identify.md).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "cli/command_line.h"
#include "cli/data_dir.h"
#include "compare/compare.h"
#include "identify/identify.h"
#include "identify/joints.h"
#include "identify/sensors.h"
#include "runner/scenario.h"
#include "sweep/executor_options.h"
#include "tool_process/run_command.h"

namespace {

std::string G(double v, int digits = 9) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
  return buf;
}

// DIR/soles.yaml: the identified soles as sim_host --contact-file takes them (contact/params_file.h),
// with where they came from and the RMS before and after
void WriteSolesFile(const ohrp::identify::IdentifyOptions& o, const ohrp::identify::IdentifyResult& r,
                    const std::string& path) {
  const auto quoted = [](const std::string& text) { return nlohmann::json(text).dump(); };
  std::ofstream f(path);
  f << "# The soles identified by ohrp identify. `sim_host --contact-file " << path << "` applies them\n"
    << "# (in a scenario: sim_args [--contact-file, FILE], or the same keys under contact_params).\n"
    << "contact_params:\n"
    << "  stiffness: " << G(r.refined.k) << "  # [N/m] +- " << G(r.refined.k_se, 3) << "\n"
    << "  damping: " << G(r.refined.d) << "  # [s/m] +- " << G(r.refined.d_se, 3) << "\n"
    << "identified:\n"
    << "  stiffness_se: " << G(r.refined.k_se, 6) << "\n"
    << "  damping_se: " << G(r.refined.d_se, 6) << "\n"
    << "  recording: " << quoted(o.recording) << "\n"
    << "  scenario: " << quoted(o.scenario) << "\n"
    << "  channel: " << quoted(o.channel) << "\n"
    << "  window: [" << G(r.from, 6) << ", " << G(r.to, 6) << "]  # [s] of the simulations\n"
    << "  rms_nominal: " << G(r.nominal_rms, 6) << "  # recording - simulation at sim_host's default soles\n"
    << "  rms_identified: " << G(r.final_rms, 6) << "  # recording - simulation at the identified soles\n";
  if (!f) std::fprintf(stderr, "ohrp_identify: cannot write %s\n", path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  ohrp::identify::IdentifyOptions o;
  o.source_dir = ohrp::cli::DataDir();
  o.scenario = o.source_dir + "/scenarios/rocking_fig12.yaml";
  o.out_dir = "identify";
  CLI::App app{
      "ohrp_identify: estimates the soft soles' stiffness K [N/m] and damping D [s/m] from a\n"
      "recording of the standing robot's damped rocking after a push (the paper's figure 12,\n"
      "the experiment of --scenario). (a) The recording's rocking frequency and log decrement\n"
      "on --channel through the linearised rigid-body-on-springs model with the robot's mass,\n"
      "inertia and centre of mass in the recorded posture; (b) simulations of the experiment\n"
      "(ohrp_run) around that estimate bring the simulated frequency and decay onto the\n"
      "recording's; (c) uncertainties from the measurement's standard errors through the\n"
      "simulated slopes. Each stage's simulations are one sweep (ohrp sweep's library), run\n"
      "in parallel (--jobs) or as a Slurm array job (--slurm). Writes DIR/identify.json, the\n"
      "sweeps in DIR/{nominal,k,d,final}/ (sweep.csv, table.md, variants/vNNN/run) and the last\n"
      "run against the recording in DIR/compare/ (ohrp_compare_logs: compare.png).",
      "ohrp_identify"};
  app.add_option("recording", o.recording, "the robot's data log (hw_driver --log)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("--scenario", o.scenario, "the experiment, as ohrp_run takes it")
      ->capture_default_str()->check(CLI::ExistingFile);
  app.add_option("--channel", o.channel,
                 "oscillating channel measured in both; a comma-separated list measures their sum")
      ->capture_default_str();
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  app.add_option("--settle", o.settle, "[s] after the push's end before the measured window")
      ->capture_default_str()->check(ohrp::cli::Plausible("wait"));
  app.add_option("--window", o.window, "[s] of free rocking measured")
      ->capture_default_str()->check(ohrp::cli::Plausible("duration"));
  app.add_option("--step", o.step, "relative step of the simulations around the estimate")
      ->capture_default_str()->check(ohrp::cli::Plausible("fraction"))
      ->check(ohrp::cli::InRange(0.01, 0.5));
  app.add_option("--out", o.out_dir, "folder for identify.json and the simulations")->capture_default_str();
  app.add_flag("--quiet,-q", o.quiet, "print the result only");
  bool joints = false;
  app.add_flag("--joints", joints,
               "the recording is an excite log (controllers/excite.h) or a data log of the excitation "
               "(hw_driver --log --log-dq --log-time board: the joints whose reference moved): per "
               "joint, inertia, viscous and Coulomb friction, the servo's lag and realised gains, "
               "with bootstrap standard errors (identify/joints.h); writes DIR/joints.json");
  bool sensors = false;
  ohrp::identify::SensorOptions sensor_options;
  app.add_flag("--sensors", sensors,
               "the recording is a data log of the robot standing still (hw_driver --log, sim_host "
               "--log while posture holds): the IMUs' gyro bias and noise, accelerometer noise and "
               "bias, the F/T sensors' and the encoders' noise, with standard errors "
               "(identify/sensors.h); writes DIR/sensors.json and DIR/sensors.yaml (sim_host --sensor-file)");
  app.add_option("--from", sensor_options.from, "--sensors: [s] the still window's start (log time)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--to", sensor_options.to, "--sensors: [s] the still window's end (log time)")
      ->check(CLI::PositiveNumber);
  ohrp::identify::JointModel joint_model;
  app.add_option("--model", joint_model.model,
                 "--joints: the model the excitation ran on (MJCF, VRML, URDF or robot profile): "
                 "also writes DIR/joints.yaml, the joints' armature (the identified inertia less "
                 "the links'), damping and frictionloss for sim_host --joint-file; --sensors: the "
                 "encoders' biases (the servos' steady torques against the model's gravity torques) "
                 "and the F/T sensors' offsets (against the static load of what hangs below them), "
                 "the robot on the rig (e.g. mjcf/hrp1s/scene_hung.xml --keyframe rig)")
      ->check(CLI::ExistingFile);
  app.add_option("--keyframe", joint_model.keyframe,
                 "--joints --model: the keyframe the other joints held (default: the model's "
                 "initial posture)");
  app.add_option("--draws-for", joint_model.draws_for,
                 "--joints --model: also writes DIR/joints_draws.yaml, a sweep of this scenario (a "
                 "name in scenarios/ or a file) with each identified parameter drawn about its "
                 "estimate within its standard error (ohrp sweep DIR/joints_draws.yaml)");
  app.add_option("--draws", joint_model.draws, "--draws-for: how many draws (variants)")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  ohrp::sweep::AddExecutorOptions(&app, &o.executor, "simulations of a stage");
  app.footer(
      "Exit codes: 0 identified, 1 a simulation failed or the refinement could not proceed,\n"
      "2 bad option or input (a missing or malformed recording, an unknown channel, a scenario\n"
      "without a push, no oscillation in the recording). docs/identify.md has the method.");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  if (sensors) {
    if (joints || sensor_options.to <= sensor_options.from) {
      std::fprintf(stderr, "ohrp_identify: --sensors goes without --joints, and --to after --from\n");
      return 2;
    }
    std::error_code made;
    fs::create_directories(o.out_dir, made);
    return ohrp::identify::IdentifySensors(o.recording, o.out_dir, sensor_options, joint_model);
  }
  if (joints) {
    if (!joint_model.draws_for.empty()) {
      // the scenario the draws are for, read before the fit (a name in scenarios/ or a file)
      if (joint_model.model.empty()) {
        std::fprintf(stderr, "ohrp_identify: --draws-for needs --model (the parameters it draws "
                     "are the model's)\n");
        return 2;
      }
      const std::string& s = joint_model.draws_for;
      const bool file = s.find('/') != std::string::npos || (s.size() > 5 && s.substr(s.size() - 5) == ".yaml");
      ohrp::runner::Scenario scenario;
      std::string error;
      if (!ohrp::runner::LoadScenario(file ? s : ohrp::cli::DataDir() + "/scenarios/" + s + ".yaml",
                                      &scenario, &error)) {
        std::fprintf(stderr, "ohrp_identify: --draws-for %s: %s\n", s.c_str(), error.c_str());
        return 2;
      }
    }
    std::error_code made;
    fs::create_directories(o.out_dir, made);
    return ohrp::identify::IdentifyJoints(o.recording, o.out_dir, ohrp::identify::JointFitOptions{},
                                          joint_model);
  }
  if (!joint_model.model.empty() || !joint_model.keyframe.empty() || !joint_model.draws_for.empty()) {
    std::fprintf(stderr, "ohrp_identify: --model, --keyframe and --draws-for go with --joints\n");
    return 2;
  }
  o.bin_dir = fs::canonical("/proc/self/exe").parent_path().string();
  o.executor.progress = !o.quiet;
  for (const char* program : {"ohrp_run", "ohrp_sweep"}) {
    // ohrp_run runs each simulation; a Slurm array task runs it through ohrp_sweep --task
    if (std::string(program) == "ohrp_sweep" && o.executor.kind != ohrp::sweep::Executor::kSlurm) continue;
    if (!fs::exists(fs::path(o.bin_dir) / program)) {
      std::fprintf(stderr, "ohrp_identify: %s/%s is not built (it runs the simulations)\n",
                   o.bin_dir.c_str(), program);
      return 2;
    }
  }
  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  o.out_dir = fs::absolute(o.out_dir).string();
  ohrp::identify::IdentifyResult r;
  std::string error;
  const int code = ohrp::identify::Identify(o, &r, &error);
  if (code != 0) {
    std::fprintf(stderr, "ohrp_identify: %s\n", error.c_str());
    return code;
  }
  nlohmann::json j;
  j["recording"] = o.recording;
  j["scenario"] = o.scenario;
  j["channel"] = o.channel;
  j["lag"] = r.lag;
  j["first"] = {{"lag", r.first_lag}, {"k", r.first.k}, {"d", r.first.d}};
  j["noise"] = r.noise;
  j["window"] = {r.from, r.to};
  j["recorded"] = {{"frequency", r.f}, {"frequency_se", r.f_se}, {"log_decrement", r.delta},
                   {"log_decrement_se", r.delta_se}};
  j["closed_form"] = {{"k", r.closed_form.k}, {"k_se", r.closed_form.k_se},
                      {"d", r.closed_form.d}, {"d_se", r.closed_form.d_se}};
  j["refined"] = {{"k", r.refined.k}, {"k_se", r.refined.k_se}, {"d", r.refined.d},
                  {"d_se", r.refined.d_se}};
  j["noise_spread"] = {{"frequency", r.spread_f}, {"log_decrement", r.spread_delta}};
  j["final"] = {{"frequency", r.final_f}, {"log_decrement", r.final_delta}, {"rms", r.final_rms},
                {"rms_nominal", r.nominal_rms}};
  j["runs"] = r.runs;
  j["sweeps"] = r.sweeps;
  std::ofstream(o.out_dir + "/identify.json") << j.dump(2) << "\n";
  WriteSolesFile(o, r, o.out_dir + "/soles.yaml");
  // the paper's figure 12: the run at the identified K, D and the recording on the same axes
  // (ohrp_compare_logs, aligned by the lag found: DIR/compare/compare.png)
  const std::string compare = (fs::path(o.bin_dir) / "ohrp_compare_logs").string();
  if (fs::exists(compare) && !r.runs.empty()) {
    char from[32], to[32];
    std::snprintf(from, sizeof(from), "%.6f", r.from);
    std::snprintf(to, sizeof(to), "%.6f", r.to);
    const std::string compare_txt = o.out_dir + "/compare.txt";
    std::remove(compare_txt.c_str());
    std::string why;  // an argument vector, no shell (tool_process/run_command.h)
    const int compared = ohrp::tool::RunCommand(
        {compare, r.runs.back()["dir"].get<std::string>() + "/run/log.csv", o.recording, "--channels",
         o.channel, "--oscillation", o.channel, "--from", from, "--to", to, "--labels",
         "simulation,robot", "--out", o.out_dir + "/compare"},
        compare_txt, &why);
    if (compared == ohrp::compare::kExitDifferent)  // written, but not the same experiment
      std::fprintf(stderr, "ohrp_identify: compare-logs finds the last run and the recording are not the "
                   "same experiment (see %s/compare.txt)\n", o.out_dir.c_str());
    else if (compared != 0)
      std::fprintf(stderr, "ohrp_identify: the comparison plot could not be made (see %s/compare.txt)\n",
                   o.out_dir.c_str());
  }
  std::printf("K = %.4g +- %.2g N/m, D = %.4g +- %.2g s/m  (closed form: K %.4g +- %.2g, D %.4g +- %.2g; %s/identify.json)\n",
              r.refined.k, r.refined.k_se, r.refined.d, r.refined.d_se, r.closed_form.k,
              r.closed_form.k_se, r.closed_form.d, r.closed_form.d_se, o.out_dir.c_str());
  return 0;
}
