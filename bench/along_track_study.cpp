// Along-track bias of our PLICP and of the reference (CSM) against the simulated truth, under
// each of the simulated laser's sensor effects alone and all together (issue 16). Not a timing
// benchmark: an accuracy study on whole simulated runs (sim::simulate in process, no bag).
//
// For each world (the office and the Mines-like corridors, their shipped scenarios), each
// effect set and each seed, the run's scans are matched as consecutive pairs and as pairs 0.5 s
// apart, by ours with the sweep compensation (the sensor's velocity over the previous scan
// interval, from the truth, as the pairing takes it from odometry), by ours compensated with the
// motion over each scan's own sweep, by ours without compensation, and by CSM (which has none).
// First guess: the true motion scaled by 1.03 and turned by 0.005 rad (a biased odometry). Per
// variant it reports, pooled over the seeds:
//   along-track [%] = 100 (sum_k t_k . u_k / sum_k |T_k| - 1), t_k the matched translation, T_k
//     the true one and u_k its direction, over the pairs the matcher calls valid, with the first
//     guess 3 % too long and 3 % too short (where the scene leaves the motion along a corridor
//     weakly constrained, a matcher's result leans towards its guess: the two differ), and in
//     brackets its standard error over the seeds' runs (guess too long): with 1-2 cm per
//     consecutive pair, a few millimetres of error per pair make one 60 s run's sum uncertain
//     by 0.4-1 %, so a bias of 0.2 % needs tens of seeds to be seen at all;
//   median / 95th percentile of |t_k - T_k| [mm] (guess too long);
//   valid pairs / all pairs (guess too long).
// Usage: study_along_track [--seeds N] [--duration S] [--worlds office,mines_like]
//                          [--effects SETS]  (e.g. sweep+noise,all,all+ripple; default: each alone,
//                          all; ripple, a 2 mm range error fixed to the rays, only when named)
//                          [--pairs-csv FILE]  (every pair's truth and results, guess too long)
//                          [--ours-only]  (only ours with the sweep's own motion: ~20x faster)
//                          [--fallback-max-surface-points N] [--veiling-min-angle-deg D]
//                          [--trim-keep-fraction F] [--tolerance T]  (convergence, m and rad)
//                          (options of ours; default: the defaults)
//                          [--noise-m A] [--noise-per-m B] [--noise-correlation R]  (the noise
//                          effect's sigma = A + B r, correlated by R between neighbouring rays;
//                          default 0.002 m + 0.003 m/m, 0.5, the real URG log's noise rounded
//                          up, as config/sim/scenarios/mines_like.yaml; the tables measured
//                          before it (docs/scan_matching.md) used 0.005, 0.005, 0)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "csm_matcher.h"
#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"
#include "support/sim_recording.h"

namespace {

using namespace odometry_calibration;

using Recorder = test::ScanTruthRecorder;
using test::toScan;
using test::truthAt;

/// The sensor effects switched on by a named set, on top of the scenario's own laser.
struct EffectSet
{
  std::string name;
  bool sweep = false, noise = false, quantise = false, mixed = false, dark = false;
  bool ripple = false;  ///< not part of "all": a candidate effect, not one the issue listed
};

/// Range noise when the set has noise: sigma = at_zero_m + per_m * range, correlated between
/// neighbouring rays by `correlation`. Default: measured on the real URG-04LX log exp1.dat
/// (scripts/measure_scan_noise: 1.2 mm + 0.24 % of the range, 0.49 between neighbours), rounded
/// up to 2 mm + 0.3 %, at or above its estimate in every 0.5 m range bin.
struct NoiseLevel
{
  double at_zero_m = 0.002;
  double per_m = 0.003;
  double correlation = 0.5;
};

void applyEffects(const EffectSet& effects, const NoiseLevel& noise, sim::LaserOptions* laser)
{
  // Values of a Hokuyo URG-04LX-like scanner (config/sim/scenarios/mines_like.yaml).
  laser->sweep = effects.sweep;
  laser->range_noise_per_m = effects.noise ? noise.per_m : 0.0;
  laser->range_noise_correlation = effects.noise ? noise.correlation : 0.0;
  if (effects.noise)
    laser->range_noise_m = noise.at_zero_m;
  laser->range_resolution_m = effects.quantise ? 0.001 : 0.0;
  laser->mixed_pixel_probability = effects.mixed ? 0.5 : 0.0;
  laser->beam_divergence_rad = effects.mixed ? 0.006 : 0.0;
  laser->dark_dropout_probability = effects.dark ? 0.05 : 0.0;
  // A range error fixed to the rays: 2 mm over 40 rays (docs/scan_matching.md, the real log's
  // chained and direct matches).
  laser->range_ripple_m = effects.ripple ? 0.002 : 0.0;
  laser->range_ripple_period_rays = 40.0;
}

/// Errors of one matcher variant over some pairs.
struct Tally
{
  double along_m = 0.0;  ///< sum of matched translations along the true ones
  double truth_m = 0.0;  ///< sum of true distances (of the valid pairs)
  std::vector<double> errors_mm;
  int valid = 0, pairs = 0;
  /// (along_m, truth_m) of each seed's run: the runs are the independent units of the
  /// standard error below (a run's pairs share scans and are not independent).
  std::vector<std::pair<double, double>> runs;

  void add(bool ok, const Pose2& estimate, const Pose2& truth)
  {
    ++pairs;
    if (!ok)
      return;
    ++valid;
    const Eigen::Vector2d t(estimate.x(), estimate.y()), T(truth.x(), truth.y());
    if (T.norm() > 1e-4) {
      along_m += t.dot(T) / T.norm();
      truth_m += T.norm();
    }
    errors_mm.push_back(1e3 * (t - T).norm());
  }
  double alongPct() const { return truth_m > 0.0 ? 100.0 * (along_m / truth_m - 1.0) : NAN; }
  /// Standard error of alongPct() over the runs [%]: the ratio estimator's cluster standard
  /// error, 100 sqrt(n / (n - 1) sum_s (a_s - R d_s)^2) / sum_s d_s with a_s, d_s a run's sums
  /// and R = sum a / sum d (NaN with fewer than two runs).
  double alongStandardErrorPct() const
  {
    const double n = static_cast<double>(runs.size());
    if (runs.size() < 2 || !(truth_m > 0.0))
      return NAN;
    const double ratio = along_m / truth_m;
    double sum2 = 0.0;
    for (const auto& [along, truth] : runs)
      sum2 += (along - ratio * truth) * (along - ratio * truth);
    return 100.0 * std::sqrt(n / (n - 1.0) * sum2) / truth_m;
  }
};

double quantile(std::vector<double> values, double q)
{
  if (values.empty())
    return NAN;
  const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(q * values.size()));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

enum Variant
{
  kOursCompensated,
  kOursOwnSweep,
  kOursRaw,
  kCsm,
  kVariants
};

/// Matches one run's pairs `step` scans apart with every variant.
void matchRun(const Recorder& run, const sim::Scenario& scenario, std::size_t step,
              double guess_scale, const PlicpOptions& options, bool quick, Tally tallies[kVariants],
              std::ostream* pairs_csv)
{
  const double period = 1.0 / scenario.laser.rate_hz;
  std::vector<Scan> scans;
  std::vector<Pose2> T_world_laser;
  for (const sim::ScanSample& sample : run.scans) {
    scans.push_back(toScan(sample));
    T_world_laser.push_back(truthAt(run.truth, sample.stamp_s) * scenario.laser.T_base_laser);
  }
  // The sweep's velocity for each scan: its motion since the previous scan over that time.
  // The sweep's velocity for each scan as the pairing takes it (pair_collector.cpp): its
  // motion since the previous scan over that time, which lags the sweep by about 0.08 s ...
  auto velocity = [&](std::size_t k) {
    const Eigen::Vector3d xi = se2Log(between(T_world_laser[k - 1], T_world_laser[k])) / period;
    return SensorVelocity{xi(0), xi(1), xi(2)};
  };
  // ... and the motion over the sweep itself (what a compensation could use with the encoders
  // up to the sweep's end).
  auto ownVelocity = [&](std::size_t k) {
    const double sweep_s = scans[k].time_increment_s * (scans[k].ranges_m.size() - 1);
    if (sweep_s <= 0.0)
      return SensorVelocity{};
    const Pose2 end =
        truthAt(run.truth, run.scans[k].stamp_s + sweep_s) * scenario.laser.T_base_laser;
    const Eigen::Vector3d xi = se2Log(between(T_world_laser[k], end)) / sweep_s;
    return SensorVelocity{xi(0), xi(1), xi(2)};
  };
  for (std::size_t k = 1; k + step < scans.size(); k += step) {
    const Pose2 truth = between(T_world_laser[k], T_world_laser[k + step]);
    const Pose2 guess =  // a biased odometry
        se2Exp(guess_scale * se2Log(truth)) * Pose2(0.0, 0.0, 0.005);
    const PlicpResult own = matchScans(
        prepareScan(scans[k], options.line_fit, ownVelocity(k)),
        prepareScan(scans[k + step], options.line_fit, ownVelocity(k + step)), guess, options);
    tallies[kOursOwnSweep].add(own.valid(), own.T_ref_new, truth);
    if (quick)
      continue;
    const PreparedScan ref_comp = prepareScan(scans[k], options.line_fit, velocity(k));
    const PreparedScan cur_comp =
        prepareScan(scans[k + step], options.line_fit, velocity(k + step));
    const PlicpResult ours = matchScans(ref_comp, cur_comp, guess, options);
    tallies[kOursCompensated].add(ours.valid(), ours.T_ref_new, truth);
    const PreparedScan ref_raw = prepareScan(scans[k], options.line_fit);
    const PreparedScan cur_raw = prepareScan(scans[k + step], options.line_fit);
    const PlicpResult raw = matchScans(ref_raw, cur_raw, guess, options);
    tallies[kOursRaw].add(raw.valid(), raw.T_ref_new, truth);
    const csm_reference::CsmOutcome csm =
        csm_reference::matchWithCsm(scans[k], scans[k + step], guess, false);
    tallies[kCsm].add(csm.valid, csm.T_ref_new, truth);
    if (pairs_csv) {
      const SensorVelocity v = velocity(k);
      *pairs_csv << step << ',' << run.scans[k].stamp_s << ',' << truth.x() << ',' << truth.y()
                 << ',' << truth.theta() << ',' << v.vx_mps << ',' << v.vy_mps << ','
                 << v.omega_radps << ',' << ours.valid() << ',' << ours.T_ref_new.x() << ','
                 << ours.T_ref_new.y() << ',' << ours.T_ref_new.theta() << ',' << raw.valid() << ','
                 << raw.T_ref_new.x() << ',' << raw.T_ref_new.y() << ',' << raw.T_ref_new.theta()
                 << ',' << csm.valid << ',' << csm.T_ref_new.x() << ',' << csm.T_ref_new.y() << ','
                 << csm.T_ref_new.theta() << '\n';
    }
  }
}

/// "along-track with the guess too long / too short [%] (standard error over the runs, long
/// guess); median / p95 error [mm]; valid".
std::string format(const Tally& long_guess, const Tally& short_guess)
{
  if (long_guess.pairs == 0)
    return "not run";  // --ours-only
  char text[192];
  std::snprintf(text, sizeof(text), "%+.2f / %+.2f (±%.2f); %.1f / %.1f; %d/%d",
                long_guess.alongPct(), short_guess.alongPct(), long_guess.alongStandardErrorPct(),
                quantile(long_guess.errors_mm, 0.5), quantile(long_guess.errors_mm, 0.95),
                long_guess.valid, long_guess.pairs);
  return text;
}

}  // namespace

int main(int argc, char** argv)
{
  int seeds = 3;
  double duration_s = 60.0;
  std::string worlds = "office,mines_like";
  std::string pairs_csv_path;
  std::string effects_list;
  NoiseLevel noise;
  PlicpOptions options;  // the defaults, but for the line-fit options given
  bool quick = false;    // --ours-only: only ours compensated with the sweep's own motion
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--ours-only") {
      quick = true;
      continue;
    }
    if ((arg == "--fallback-max-surface-points" || arg == "--veiling-min-angle-deg" ||
         arg == "--noise-m" || arg == "--noise-per-m" || arg == "--noise-correlation" ||
         arg == "--trim-keep-fraction" || arg == "--tolerance") &&
        i + 1 < argc) {
      const double value = std::atof(argv[++i]);
      if (arg == "--noise-m")
        noise.at_zero_m = value;
      else if (arg == "--trim-keep-fraction")
        options.trim_keep_fraction = value;
      else if (arg == "--tolerance")
        options.translation_tolerance_m = options.rotation_tolerance_rad = value;
      else if (arg == "--noise-per-m")
        noise.per_m = value;
      else if (arg == "--noise-correlation")
        noise.correlation = value;
      else if (arg == "--veiling-min-angle-deg")
        options.line_fit.veiling_min_angle_rad = value * M_PI / 180.0;
      else
        options.line_fit.segment_fallback_max_surface_points = static_cast<int>(value);
      continue;
    }
    if ((arg == "--seeds" || arg == "--duration" || arg == "--worlds" || arg == "--pairs-csv" ||
         arg == "--effects") &&
        i + 1 < argc) {
      const std::string value = argv[++i];
      if (arg == "--seeds")
        seeds = std::atoi(value.c_str());
      else if (arg == "--duration")
        duration_s = std::atof(value.c_str());
      else if (arg == "--worlds")
        worlds = value;
      else if (arg == "--effects")
        effects_list = value;
      else
        pairs_csv_path = value;
    } else {
      std::cerr << "usage: study_along_track [--seeds N] [--duration S] [--worlds a,b] "
                   "[--effects sweep+noise,...] [--pairs-csv FILE] [--ours-only] "
                   "[--fallback-max-surface-points N] [--veiling-min-angle-deg D] "
                   "[--noise-m A] [--noise-per-m B] [--noise-correlation R] "
                   "[--trim-keep-fraction F] [--tolerance T]\n";
      return arg == "-h" || arg == "--help" ? 0 : 2;
    }
  }
  try {
    validate(options);
  } catch (const std::invalid_argument& error) {
    std::cerr << "study_along_track: " << error.what() << "\n";
    return 2;
  }
  if (quick && !pairs_csv_path.empty()) {
    std::cerr << "study_along_track: --pairs-csv needs every variant (not --ours-only)\n";
    return 2;
  }
  if (!(noise.at_zero_m >= 0.0) || !(noise.per_m >= 0.0) || !(noise.correlation >= 0.0) ||
      !(noise.correlation <= 0.95)) {
    std::cerr << "study_along_track: --noise-m and --noise-per-m must be >= 0, "
                 "--noise-correlation in [0, 0.95]\n";
    return 2;
  }
  if (seeds < 1 || !(duration_s > 1.0)) {
    std::cerr << "study_along_track: --seeds must be >= 1 and --duration > 1 s\n";
    return 2;
  }
  std::ofstream pairs_csv;
  if (!pairs_csv_path.empty()) {
    pairs_csv.open(pairs_csv_path);
    if (!pairs_csv) {
      std::cerr << "study_along_track: cannot write " << pairs_csv_path << "\n";
      return 2;
    }
    pairs_csv << "world,effects,seed,step,stamp_s,true_x,true_y,true_theta,v_x,v_y,omega,"
                 "ours_valid,ours_x,ours_y,ours_theta,raw_valid,raw_x,raw_y,raw_theta,"
                 "csm_valid,csm_x,csm_y,csm_theta\n";
    pairs_csv.precision(9);
  }
  sm_debug_write(0);
  const std::string config = ODOMETRY_CALIBRATION_CONFIG_DIR;
  const std::map<std::string, std::string> scenario_files = {{"office", "diff_drive_office.yaml"},
                                                             {"mines_like", "mines_like.yaml"}};
  std::vector<EffectSet> effect_sets;
  if (effects_list.empty()) {
    effect_sets = {{"none", false, false, false, false, false},
                   {"sweep", true, false, false, false, false},
                   {"noise a+br", false, true, false, false, false},
                   {"1 mm steps", false, false, true, false, false},
                   {"mixed pixels", false, false, false, true, false},
                   {"dark dropouts", false, false, false, false, true},
                   {"all", true, true, true, true, true}};
  } else {
    // "sweep+noise,all,...": each entry a set of sweep, noise, steps, mixed, dark, all, none.
    std::stringstream entries(effects_list);
    for (std::string entry; std::getline(entries, entry, ',');) {
      EffectSet set{entry};
      std::stringstream parts(entry);
      for (std::string part; std::getline(parts, part, '+');) {
        const bool all = part == "all";
        if (!all && part != "none" && part != "sweep" && part != "noise" && part != "steps" &&
            part != "mixed" && part != "dark" && part != "ripple") {
          std::cerr << "study_along_track: unknown effect '" << part
                    << "' (sweep, noise, steps, mixed, dark, ripple, all, none)\n";
          return 2;
        }
        set.sweep = set.sweep || all || part == "sweep";
        set.noise = set.noise || all || part == "noise";
        set.quantise = set.quantise || all || part == "steps";
        set.mixed = set.mixed || all || part == "mixed";
        set.dark = set.dark || all || part == "dark";
        set.ripple = set.ripple || part == "ripple";
      }
      effect_sets.push_back(set);
    }
  }
  std::cout << "Along-track [%] with the guess +3 % / -3 % (standard error over the seeds); "
               "median / p95 translation error [mm]; valid pairs. "
            << seeds << " seeds x " << duration_s
            << " s per world; noise sigma = " << noise.at_zero_m * 1000.0 << " mm + "
            << noise.per_m * 100.0 << " % of the range, correlated " << noise.correlation
            << " between neighbours.\n\n"
            << "| world | effects | pairs | ours, sweep compensated (as the pairing) | ours, "
               "compensated with the sweep's own motion | ours, uncompensated | CSM |\n"
            << "|---|---|---|---|---|---|---|\n";
  std::stringstream names(worlds);
  std::string world_name;
  while (std::getline(names, world_name, ',')) {
    const auto file = scenario_files.find(world_name);
    if (file == scenario_files.end()) {
      std::cerr << "study_along_track: unknown world '" << world_name << "' (office, mines_like)\n";
      return 2;
    }
    const sim::Scenario base =
        sim::loadScenarioYaml(config + "/sim/scenarios/" + file->second, config + "/sim/worlds");
    const sim::World world = sim::loadWorldYaml(base.world_path);
    for (const EffectSet& effects : effect_sets) {
      const std::size_t steps[2] = {1, 5};     // consecutive, 0.5 s at 10 Hz
      const double guesses[2] = {1.03, 0.97};  // odometry 3 % long, 3 % short
      Tally pooled[2][2][kVariants];           // [guess][step][variant]
      for (int seed = 1; seed <= seeds; ++seed) {
        sim::Scenario scenario = base;
        scenario.seed = static_cast<unsigned>(seed);
        scenario.duration_s = duration_s;
        scenario.encoders.rate_hz = 500.0;  // truth every 2 ms
        applyEffects(effects, noise, &scenario.laser);
        const auto robot = sim::makeRobot(scenario.robot);
        Recorder run;
        sim::simulate(scenario, world, *robot, run);
        for (int g = 0; g < 2; ++g) {
          for (int s = 0; s < 2; ++s) {
            std::ostringstream rows;
            const bool dump = pairs_csv.is_open() && g == 0;
            Tally tallies[kVariants];
            matchRun(run, scenario, steps[s], guesses[g], options, quick, tallies,
                     dump ? &rows : nullptr);
            if (dump) {
              std::istringstream lines(rows.str());
              for (std::string line; std::getline(lines, line);)
                pairs_csv << world_name << ',' << effects.name << ',' << seed << ',' << line
                          << '\n';
            }
            for (int v = 0; v < kVariants; ++v) {
              Tally& p = pooled[g][s][v];
              p.along_m += tallies[v].along_m;
              p.truth_m += tallies[v].truth_m;
              p.runs.emplace_back(tallies[v].along_m, tallies[v].truth_m);
              p.valid += tallies[v].valid;
              p.pairs += tallies[v].pairs;
              p.errors_mm.insert(p.errors_mm.end(), tallies[v].errors_mm.begin(),
                                 tallies[v].errors_mm.end());
            }
          }
        }
      }
      for (int s = 0; s < 2; ++s) {
        std::cout << "| " << world_name << " | " << effects.name << " | "
                  << (s == 0 ? "consecutive" : "0.5 s") << " | "
                  << format(pooled[0][s][kOursCompensated], pooled[1][s][kOursCompensated]) << " | "
                  << format(pooled[0][s][kOursOwnSweep], pooled[1][s][kOursOwnSweep]) << " | "
                  << format(pooled[0][s][kOursRaw], pooled[1][s][kOursRaw]) << " | "
                  << format(pooled[0][s][kCsm], pooled[1][s][kCsm]) << " |" << std::endl;
      }
    }
  }
  return 0;
}
