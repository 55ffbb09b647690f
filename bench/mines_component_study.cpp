// Which component of the calibration pipeline moves the Mines wheel radii (issue 16, "prove or
// fix the scale"). Not a timing benchmark: a study printing a table.
//
// Our pipeline (runBagsAtEstimatedOffset's bag reading and PairCollector, and the calibration job,
// as calibrate_bag runs them, with config/mines.yaml) is run on the real Mines log (exp1.dat,
// converted to a bag as mines_to_bag does) and on simulated Mines-like bags with truth
// (config/sim/scenarios/mines_like.yaml, every sensor effect on), once as it is and once per
// swapped component:
//   matcher: the reference PLICP (CSM, sm_icp with its defaults) in the pairing's matcher slot,
//     for the consecutive and the keyframe matches, on the same (compensated) points;
//   sweep compensation off;
//   time offset fixed at 0, or fixed at our estimate (the pairs then cut there from the start);
//   consistency filter off, or loose (8 cm / 0.05 rad instead of 3 cm / 0.02 rad);
//   encoder values at the keyframes from the nearest reading instead of linear interpolation;
//   loss: plain least squares instead of Huber;
//   keyframe pairs: the composed consecutive matches instead of the direct keyframe match;
// and all of the CSM side's together (the "CSM-like pipeline": CSM, no sweep compensation, no
// consistency filter, nearest reading, plain least squares; time offset estimated).
// Per configuration: pairs, left / right radius [mm], separation [mm], time offset [s], change of
// the mean radius against ours [%]; on the simulated bags also the mean radius error against the
// truth [%] (per seed and the mean).
//
// With --leave-one-out also the CSM-like pipeline with one component at a time back to ours, and
// ours and the CSM-like pipeline with the nominal radius (the matchers' guesses) 4 % off. The
// bags are paired as calibrate_bag pairs them (again at the estimated time offset when the
// configured one is off, ros/bag_runner.h); with --one-pass once at the configured offset, as
// before issue 16's fix.
//
// Usage: study_mines_components [--log exp1.dat] [--seeds N] [--duration S] [--no-sim]
//                               [--no-mines] [--leave-one-out] [--one-pass]
//                               [--only NAME[,NAME...]]
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "csm_matcher.h"
#include "odometry_calibration/calibration/calibration_config.h"
#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/datasets/mines_log.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/ros/bag_runner.h"
#include "odometry_calibration/ros/mines_bag_writer.h"
#include "odometry_calibration/ros/sim_bag_writer.h"
#include "odometry_calibration/sim/scenario.h"

namespace {

using namespace odometry_calibration;

/// One configuration: how it changes the configuration (given ours' estimated time offset).
struct Variant
{
  std::string name;
  std::function<void(CalibrationConfig&, double our_offset_s)> apply;
};

void useCsm(CalibrationConfig& c)
{
  c.collector.matcher = [](const PreparedScan& reference, const PreparedScan& current,
                           const Pose2& guess, const PlicpOptions& options) {
    return csm_reference::matchPreparedWithCsm(reference, current, guess,
                                               options.compute_covariance);
  };
}

void csmLike(CalibrationConfig& c)
{
  useCsm(c);
  c.collector.compensate_sweep = false;
  c.collector.check_consistency = false;
  c.collector.encoder_interpolation = EncoderInterpolation::kNearest;
  c.models.diff_drive.huber_threshold = 0.0;
}

std::vector<Variant> variants()
{
  return {
      {"ours (config/mines.yaml, calibrate_bag)", [](CalibrationConfig&, double) {}},
      {"matcher: CSM", [](CalibrationConfig& c, double) { useCsm(c); }},
      {"sweep compensation off",
       [](CalibrationConfig& c, double) { c.collector.compensate_sweep = false; }},
      {"time offset fixed 0",
       [](CalibrationConfig& c, double) {
         c.estimate_time_offset = false;
         c.collector.time_offset_s = 0.0;
       }},
      {"time offset fixed at ours' estimate",
       [](CalibrationConfig& c, double ours) {
         c.estimate_time_offset = false;
         c.collector.time_offset_s = ours;
       }},
      {"consistency filter off",
       [](CalibrationConfig& c, double) { c.collector.check_consistency = false; }},
      {"consistency filter loose (8 cm, 0.05 rad)",
       [](CalibrationConfig& c, double) {
         c.collector.consistency_translation_m = 0.08;
         c.collector.consistency_rotation_rad = 0.05;
       }},
      {"encoders: nearest reading",
       [](CalibrationConfig& c, double) {
         c.collector.encoder_interpolation = EncoderInterpolation::kNearest;
       }},
      {"loss: plain least squares",
       [](CalibrationConfig& c, double) { c.models.diff_drive.huber_threshold = 0.0; }},
      {"keyframe pairs: chained consecutive matches",
       [](CalibrationConfig& c, double) { c.collector.pair_motion_from_chain = true; }},
      {"CSM-like pipeline (all swapped)", [](CalibrationConfig& c, double) { csmLike(c); }},
      {"CSM-like, time offset fixed 0",
       [](CalibrationConfig& c, double) {
         csmLike(c);
         c.estimate_time_offset = false;
         c.collector.time_offset_s = 0.0;
       }},
  };
}

/// The CSM-like pipeline (time offset estimated, or fixed at 0) with one component back to ours:
/// which of the CSM side's components make its result.
std::vector<Variant> leaveOneOutVariants()
{
  const std::vector<std::pair<std::string, std::function<void(CalibrationConfig&)>>> ours_back = {
      {"our matcher", [](CalibrationConfig& c) { c.collector.matcher = nullptr; }},
      {"sweep compensation", [](CalibrationConfig& c) { c.collector.compensate_sweep = true; }},
      {"consistency filter", [](CalibrationConfig& c) { c.collector.check_consistency = true; }},
      {"linear interpolation",
       [](CalibrationConfig& c) {
         c.collector.encoder_interpolation = EncoderInterpolation::kLinear;
       }},
      {"Huber loss", [](CalibrationConfig& c) { c.models.diff_drive.huber_threshold = 3.0; }},
  };
  std::vector<Variant> result;
  // The nominal radius (the matchers' guesses and the fit's start) 4 % smaller or larger.
  for (const double radius : {0.074, 0.080}) {
    const auto nominal = [radius](CalibrationConfig& c) {
      c.models.diff_drive.initial_left_radius_m = radius;
      c.models.diff_drive.initial_right_radius_m = radius;
    };
    const std::string text = ", nominal radius " + std::to_string(radius).substr(0, 5) + " m";
    result.push_back({"ours" + text, [nominal](CalibrationConfig& c, double) { nominal(c); }});
    result.push_back({"CSM-like" + text, [nominal](CalibrationConfig& c, double) {
                        csmLike(c);
                        nominal(c);
                      }});
    result.push_back({"CSM-like, time offset 0" + text, [nominal](CalibrationConfig& c, double) {
                        csmLike(c);
                        c.estimate_time_offset = false;
                        c.collector.time_offset_s = 0.0;
                        nominal(c);
                      }});
  }
  for (const bool zero_offset : {false, true}) {
    for (const auto& [name, back] : ours_back) {
      result.push_back(
          {std::string("CSM-like") + (zero_offset ? ", time offset 0" : "") + ", with " + name,
           [zero_offset, back = back](CalibrationConfig& c, double) {
             csmLike(c);
             if (zero_offset) {
               c.estimate_time_offset = false;
               c.collector.time_offset_s = 0.0;
             }
             back(c);
           }});
    }
  }
  return result;
}

/// What one run of the pipeline gave.
struct Outcome
{
  bool ok = false;
  std::string error;
  std::size_t pairs = 0;
  std::size_t rejected_inconsistent = 0;
  double left_m = NAN, right_m = NAN, separation_m = NAN, offset_s = NAN;
};

/// calibrate_bag's pairing and fit (the session's: paired again at the estimated time offset
/// when it differs from the configured one), or with `one_pass` the fit of the pairs made at
/// the configured offset.
Outcome runPipeline(const std::string& bag, const CalibrationConfig& config, bool one_pass)
{
  Outcome outcome;
  try {
    const BagRunResult run = runBags({bag}, config);
    CalibrationJobResult job;
    if (one_pass) {
      CalibrationJobOptions options;
      options.compare_trajectories = false;
      job = runCalibrationJob(config, run.pairs, run.encoder_history, options);
    } else {
      const CalibrateOutcome fitted = run.session->calibrate({}).outcome;
      if (!fitted.fit)
        throw std::runtime_error(fitted.message);
      job = fitted.fit->job;
    }
    const auto* model = dynamic_cast<const DiffDriveModel*>(job.model.get());
    if (!model)
      throw std::runtime_error("the configuration does not fit diff_drive");
    outcome.ok = true;
    outcome.pairs = job.pairs.size();
    const auto rejected =
        run.counts.statistics.rejected.find("keyframe match disagrees with consecutive matches");
    if (rejected != run.counts.statistics.rejected.end())
      outcome.rejected_inconsistent = rejected->second;
    outcome.left_m = model->intrinsics()(0);
    outcome.right_m = model->intrinsics()(1);
    outcome.separation_m = model->intrinsics()(2);
    outcome.offset_s = job.time_offset_s;
  } catch (const std::exception& error) {
    outcome.error = error.what();
  }
  return outcome;
}

double meanRadius(const Outcome& o)
{
  return 0.5 * (o.left_m + o.right_m);
}

/// One data set: a bag, and the true radii when known.
struct DataSet
{
  std::string name;
  std::string bag;
  double true_left_m = NAN, true_right_m = NAN;
};

std::vector<std::string> splitList(const std::string& text)
{
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ','))
    items.push_back(item);
  return items;
}

}  // namespace

int main(int argc, char** argv)
{
  std::string log = std::string(ODOMETRY_CALIBRATION_SHARED_DATA_DIR) + "/mines/exp1.dat";
  int seeds = 2;
  double duration_s = 120.0;
  bool sim = true, mines = true, leave_one_out = false, one_pass = false;
  std::vector<std::string> only;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--log" && has_value) {
      log = argv[++i];
    } else if (arg == "--seeds" && has_value) {
      seeds = std::atoi(argv[++i]);
    } else if (arg == "--duration" && has_value) {
      duration_s = std::atof(argv[++i]);
    } else if (arg == "--no-sim") {
      sim = false;
    } else if (arg == "--one-pass") {
      one_pass = true;
    } else if (arg == "--leave-one-out") {
      leave_one_out = true;
    } else if (arg == "--no-mines") {
      mines = false;
    } else if (arg == "--only" && has_value) {
      only = splitList(argv[++i]);
    } else {
      std::cerr << "usage: study_mines_components [--log exp1.dat] [--seeds N] [--duration S] "
                   "[--no-sim] [--no-mines] [--leave-one-out] [--one-pass] [--only NAME,...]\n";
      return 2;
    }
  }
  if (seeds < 0 || !(duration_s > 0.0)) {
    std::cerr << "error: --seeds must be >= 0 and --duration > 0\n";
    return 2;
  }
  char pattern[] = "/tmp/study_mines_components.XXXXXX";
  if (!mkdtemp(pattern)) {
    std::cerr << "error: cannot create a temporary folder\n";
    return 1;
  }
  const std::string directory = pattern;
  const std::string config_dir = ODOMETRY_CALIBRATION_CONFIG_DIR;
  std::vector<DataSet> data;
  try {
    if (mines) {
      if (std::filesystem::is_regular_file(log)) {
        data.push_back({"Mines exp1", directory + "/mines.bag"});
        writeMinesBag(loadMinesLog(log), data.back().bag);
      } else {
        std::cout << "no Mines log at " << log << " (../shared/data is not there): skipped\n";
      }
    }
    for (int seed = 1; sim && seed <= seeds; ++seed) {
      sim::ScenarioOverrides overrides;
      overrides.seed = seed;
      overrides.duration_s = duration_s;
      const sim::Scenario scenario = sim::loadScenarioYaml(
          config_dir + "/sim/scenarios/mines_like.yaml", config_dir + "/sim/worlds", overrides);
      DataSet set{"mines_like seed " + std::to_string(seed),
                  directory + "/mines_like_" + std::to_string(seed) + ".bag"};
      set.true_left_m = scenario.robot.parameters.at("wheel_radius_left_m");
      set.true_right_m = scenario.robot.parameters.at("wheel_radius_right_m");
      simulateToBag(scenario, set.bag, "");
      data.push_back(set);
    }
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    std::filesystem::remove_all(directory);
    return 1;
  }

  CalibrationConfig base = loadCalibrationConfig(config_dir + "/mines.yaml");
  // CSM keeps global state (its matrix contexts): one matching thread for every configuration
  // (the pairs are the same either way, pair_collector.h).
  base.collector.background_matching = false;
  std::vector<Variant> all = variants();
  if (leave_one_out) {
    for (Variant& variant : leaveOneOutVariants())
      all.push_back(std::move(variant));
  }
  std::vector<Variant> chosen;
  for (const Variant& variant : all) {
    bool wanted = only.empty() || &variant == &all.front();  // ours: the reference row
    for (const std::string& name : only)
      wanted = wanted || variant.name.find(name) != std::string::npos;
    if (wanted)
      chosen.push_back(variant);
  }

  // results[data set][variant]
  std::vector<std::vector<Outcome>> results(data.size());
  for (std::size_t d = 0; d < data.size(); ++d) {
    double our_offset_s = base.collector.time_offset_s;
    for (const Variant& variant : chosen) {
      CalibrationConfig config = base;
      variant.apply(config, our_offset_s);
      results[d].push_back(runPipeline(data[d].bag, config, one_pass));
      const Outcome& o = results[d].back();
      if (&variant == &chosen.front() && o.ok)
        our_offset_s = o.offset_s;
      std::fprintf(stderr, "%s | %s: %s\n", data[d].name.c_str(), variant.name.c_str(),
                   o.ok ? "done" : o.error.c_str());
    }
  }

  for (std::size_t d = 0; d < data.size(); ++d) {
    const bool truth = std::isfinite(data[d].true_left_m);
    std::printf("\n### %s%s\n\n", data[d].name.c_str(),
                truth ? " (simulated, truth known)" : " (real, no truth)");
    if (truth) {
      std::printf("true radii %.2f / %.2f mm\n\n", 1e3 * data[d].true_left_m,
                  1e3 * data[d].true_right_m);
    }
    std::printf(
        "| configuration | pairs (inconsistent rejected) | left / right radius [mm] | "
        "separation [mm] | time offset [s] | change vs ours [%%] |%s\n",
        truth ? " mean radius vs truth [%] |" : "");
    std::printf("|---|---|---|---|---|---|%s\n", truth ? "---|" : "");
    const Outcome& ours = results[d].front();
    for (std::size_t v = 0; v < chosen.size(); ++v) {
      const Outcome& o = results[d][v];
      if (!o.ok) {
        std::printf("| %s | failed: %s |\n", chosen[v].name.c_str(), o.error.c_str());
        continue;
      }
      std::printf("| %s | %zu (%zu) | %.2f / %.2f | %.1f | %+.3f | %+.2f |", chosen[v].name.c_str(),
                  o.pairs, o.rejected_inconsistent, 1e3 * o.left_m, 1e3 * o.right_m,
                  1e3 * o.separation_m, o.offset_s,
                  ours.ok ? 100.0 * (meanRadius(o) / meanRadius(ours) - 1.0) : NAN);
      if (truth) {
        const double true_mean = 0.5 * (data[d].true_left_m + data[d].true_right_m);
        std::printf(" %+.2f |", 100.0 * (meanRadius(o) / true_mean - 1.0));
      }
      std::printf("\n");
    }
  }
  // The simulated seeds together: mean radius error against the truth per configuration.
  std::vector<std::size_t> simulated;
  for (std::size_t d = 0; d < data.size(); ++d)
    if (std::isfinite(data[d].true_left_m))
      simulated.push_back(d);
  if (!simulated.empty()) {
    std::printf("\n### mines_like, %zu seeds: mean radius error against the truth [%%]\n\n",
                simulated.size());
    std::printf("| configuration | per seed | mean |\n|---|---|---|\n");
    for (std::size_t v = 0; v < chosen.size(); ++v) {
      std::ostringstream per_seed;
      double sum = 0.0;
      std::size_t count = 0;
      for (const std::size_t d : simulated) {
        const Outcome& o = results[d][v];
        const double true_mean = 0.5 * (data[d].true_left_m + data[d].true_right_m);
        char cell[32];
        std::snprintf(cell, sizeof(cell), "%s%+.2f", count ? ", " : "",
                      o.ok ? 100.0 * (meanRadius(o) / true_mean - 1.0) : NAN);
        per_seed << cell;
        if (o.ok) {
          sum += 100.0 * (meanRadius(o) / true_mean - 1.0);
          ++count;
        }
      }
      std::printf("| %s | %s | %+.2f |\n", chosen[v].name.c_str(), per_seed.str().c_str(),
                  count ? sum / static_cast<double>(count) : NAN);
    }
  }
  std::filesystem::remove_all(directory);
  return 0;
}
