#include "odometry_calibration/models/gp_output_fit.h"

#include <stdexcept>

namespace odometry_calibration {

void GpOutputModel::predict(const Eigen::VectorXd& x, bool with_noise, double* mean,
                            double* variance) const
{
  posterior.predict(x, mean, variance);
  if (mean_coefficients.size() > 0) {
    *mean += mean_coefficients.dot(x);
  }
  if (with_noise) {
    *variance += noise_variance;
  }
}

Eigen::VectorXd GpOutputModel::means(const Eigen::MatrixXd& inputs) const
{
  Eigen::VectorXd out = posterior.means(inputs);
  if (mean_coefficients.size() > 0) {
    out.noalias() += inputs.transpose() * mean_coefficients;
  }
  return out;
}

namespace {

/// The end of a refinement with a fixed iteration budget, in words: using the budget up is its
/// normal end, not a failure to converge.
std::string budgetTermination(const GpOptimizationResult& run, int budget)
{
  if (run.iterations >= budget) {
    return "used its budget of " + std::to_string(budget) +
           " iterations (refine_iterations; a budget, not a convergence test)";
  }
  return "stopped after " + std::to_string(run.iterations) + " of " + std::to_string(budget) +
         " iterations: " + run.termination;
}

}  // namespace

GpOutputModel fitGpOutput(const GpOutputProblem& problem, const GpOptions& options,
                          const Eigen::MatrixXd& inducing_inputs, unsigned seed,
                          const Eigen::VectorXd* warm_start, bool optimise)
{
  const Eigen::Index distinct = problem.groups.size();
  const bool use_subset = distinct > static_cast<Eigen::Index>(options.likelihood_subset);
  const bool sparse = distinct > static_cast<Eigen::Index>(options.max_exact_pairs);

  GpOutputProblem exact_problem = problem;
  exact_problem.inducing_inputs.resize(exact_problem.groups.inputs.rows(), 0);
  GpOutputProblem vfe_problem = exact_problem;
  vfe_problem.inducing_inputs = inducing_inputs;
  vfe_problem.groups =
      subsetGroups(problem.groups, static_cast<Eigen::Index>(options.refine_subset), seed + 2);
  const GpOutputObjective exact_objective(exact_problem);
  const GpOutputObjective vfe_objective(vfe_problem);

  GpOutputModel model;
  GpOptimizationResult best;
  std::string how;
  bool have_best = false;
  if (warm_start != nullptr && !optimise) {
    best.hyperparameters = *warm_start;
    best.converged = true;
    best.termination = "hyperparameters kept";
    const GpOutputObjective& objective = use_subset ? vfe_objective : exact_objective;
    if (!objective.evaluate(best.hyperparameters, &best.log_likelihood, nullptr)) {
      throw std::runtime_error("gp: the marginal likelihood failed at the kept hyperparameters");
    }
    how = "refitted with the previous hyperparameters";
    have_best = true;
  } else if (warm_start != nullptr) {
    if (!use_subset) {
      best = maximizeLogLikelihood(exact_objective, *warm_start, options.max_iterations);
    } else if (options.refine_iterations > 0) {
      best = maximizeLogLikelihood(vfe_objective, *warm_start, options.refine_iterations);
      best.converged = true;  // a budget, not a convergence criterion: say so
      best.termination = budgetTermination(best, options.refine_iterations);
    } else {
      best.hyperparameters = *warm_start;
      best.converged = true;
      best.termination = "kept";
    }
    model.iterations = best.iterations;
    how = "warm start";
    have_best = true;
  } else {
    GpOutputProblem subset_problem = exact_problem;
    subset_problem.groups =
        subsetGroups(problem.groups, static_cast<Eigen::Index>(options.likelihood_subset), seed);
    const GpOutputObjective subset_objective(subset_problem);
    std::string failures;
    for (const Eigen::VectorXd& start :
         startingHyperparameters(subset_problem, options.starts, seed + 1)) {
      try {
        GpOptimizationResult run =
            maximizeLogLikelihood(subset_objective, start, options.max_iterations);
        model.iterations += run.iterations;
        if (!have_best || run.log_likelihood > best.log_likelihood) {
          best = std::move(run);
          have_best = true;
        }
      } catch (const std::runtime_error& error) {
        failures = error.what();
      }
    }
    if (!have_best) {
      throw std::runtime_error(failures);
    }
    how = "best of " + std::to_string(options.starts) + " starts on " +
          (use_subset ? "a subset of " + std::to_string(options.likelihood_subset) + " of "
                      : std::string()) +
          std::to_string(distinct) + " distinct inputs";
    if (use_subset && options.refine_iterations > 0) {
      GpOptimizationResult refined =
          maximizeLogLikelihood(vfe_objective, best.hyperparameters, options.refine_iterations);
      model.iterations += refined.iterations;
      // The search decides convergence; the refinement has a budget, not a criterion.
      refined.converged = best.converged;
      refined.termination = "search: " + best.termination + "; refinement: " +
                            budgetTermination(refined, options.refine_iterations);
      best = std::move(refined);
      how += ", refined on the VFE bound with " + std::to_string(inducing_inputs.cols()) +
             " inducing inputs over " + std::to_string(vfe_problem.groups.size()) + " inputs";
    }
  }

  model.hyperparameters = best.hyperparameters;
  model.converged = best.converged;
  model.sparse = sparse;
  model.noise_variance = exact_objective.noiseVariance(best.hyperparameters);
  model.log_likelihood = best.log_likelihood;
  const GpRegressionData data = exact_objective.regressionData(best.hyperparameters);
  const Eigen::VectorXd kernel_parameters =
      best.hyperparameters.head(problem.kernel.parameterCount());
  model.posterior = sparse ? GpPosterior::sparse(problem.kernel, kernel_parameters, data,
                                                 inducing_inputs, &model.mean_coefficients)
                           : GpPosterior::exact(problem.kernel, kernel_parameters, data,
                                                &model.mean_coefficients);
  model.termination =
      (sparse ? "sparse GP (" + std::to_string(inducing_inputs.cols()) + " inducing inputs), "
              : std::string("exact GP, ")) +
      how + ": " + best.termination;
  return model;
}

}  // namespace odometry_calibration
