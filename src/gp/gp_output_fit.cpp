#include "odometry_calibration/gp/gp_output_fit.h"

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
  if (run.iterations == 0)
    return "no iteration of its budget of " + std::to_string(budget) + ": " + run.termination;
  return "stopped after " + std::to_string(run.iterations) + " of " + std::to_string(budget) +
         " iterations: " + run.termination;
}

/// The hyperparameters an output is fitted with, how they were found (in words) and the
/// optimiser's iterations.
struct GpSearch
{
  GpOptimizationResult best;
  std::string how;
  int iterations = 0;
};

/// The warm start kept as it is (posterior only): its likelihood on `objective`.
GpSearch keptHyperparameters(const Eigen::VectorXd& warm_start, const GpOutputObjective& objective)
{
  GpSearch search;
  GpOptimizationResult& best = search.best;
  best.hyperparameters = warm_start;
  best.converged = true;
  best.termination = "hyperparameters kept";
  if (!objective.evaluate(best.hyperparameters, &best.log_likelihood, nullptr)) {
    throw std::runtime_error("gp: the marginal likelihood failed at the kept hyperparameters");
  }
  search.how = "refitted with the previous hyperparameters";
  return search;
}

/// One run from the warm start: on the exact likelihood when all inputs fit it (`use_subset`
/// false), else within the refinement budget on the VFE bound (or kept without a budget).
GpSearch warmStartSearch(const Eigen::VectorXd& warm_start, bool use_subset,
                         const GpOptions& options, const GpOutputObjective& exact_objective,
                         const GpOutputObjective& vfe_objective)
{
  GpSearch search;
  GpOptimizationResult& best = search.best;
  if (!use_subset) {
    best = maximizeLogLikelihood(exact_objective, warm_start, options.max_iterations);
  } else if (options.refine_iterations > 0) {
    best = maximizeLogLikelihood(vfe_objective, warm_start, options.refine_iterations);
    best.converged = true;  // a budget, not a convergence criterion: say so
    best.termination = budgetTermination(best, options.refine_iterations);
  } else {
    best.hyperparameters = warm_start;
    best.converged = true;
    best.termination = "kept";
  }
  search.iterations = best.iterations;
  search.how = "warm start";
  return search;
}

/// The best of options.starts runs on the exact likelihood of at most likelihood_subset of the
/// distinct inputs of `problem` (`exact_problem`: the same without inducing inputs). Throws
/// std::runtime_error (the last failure) when no start could be evaluated.
GpSearch multiStartSearch(const GpOutputProblem& problem, const GpOutputProblem& exact_problem,
                          const GpOptions& options, unsigned seed, bool use_subset)
{
  GpSearch search;
  GpOutputProblem subset_problem = exact_problem;
  subset_problem.groups =
      subsetGroups(problem.groups, static_cast<Eigen::Index>(options.likelihood_subset), seed);
  const GpOutputObjective subset_objective(subset_problem);
  std::string failures;
  bool have_best = false;
  for (const Eigen::VectorXd& start :
       startingHyperparameters(subset_problem, options.starts, seed + 1)) {
    try {
      GpOptimizationResult run =
          maximizeLogLikelihood(subset_objective, start, options.max_iterations);
      search.iterations += run.iterations;
      if (!have_best || run.log_likelihood > search.best.log_likelihood) {
        search.best = std::move(run);
        have_best = true;
      }
    } catch (const std::runtime_error& error) {
      failures = error.what();
    }
  }
  if (!have_best) {
    throw std::runtime_error(failures);
  }
  search.how = "best of " + std::to_string(options.starts) + " starts on " +
               (use_subset ? "a subset of " + std::to_string(options.likelihood_subset) + " of "
                           : std::string()) +
               std::to_string(problem.groups.size()) + " distinct inputs";
  return search;
}

/// Refines the search's best hyperparameters on the VFE bound within refine_iterations (a
/// budget: convergence stays the search's), with `inducing_count` inducing inputs over
/// `vfe_inputs` inputs.
void refineOnVfeBound(const GpOutputObjective& vfe_objective, const GpOptions& options,
                      Eigen::Index inducing_count, Eigen::Index vfe_inputs, GpSearch* search)
{
  GpOptimizationResult refined =
      maximizeLogLikelihood(vfe_objective, search->best.hyperparameters, options.refine_iterations);
  search->iterations += refined.iterations;
  // The search decides convergence; the refinement has a budget, not a criterion.
  refined.converged = search->best.converged;
  refined.termination = "search: " + search->best.termination +
                        "; refinement: " + budgetTermination(refined, options.refine_iterations);
  search->best = std::move(refined);
  search->how += ", refined on the VFE bound with " + std::to_string(inducing_count) +
                 " inducing inputs over " + std::to_string(vfe_inputs) + " inputs";
}

/// The fitted output at the search's hyperparameters: the noise, the posterior (sparse on the
/// inducing inputs, or exact) with the mean coefficients, and how it was found.
GpOutputModel gpOutputAt(const GpSearch& search, const GpKernel& kernel,
                         const GpOutputObjective& exact_objective,
                         const Eigen::MatrixXd& inducing_inputs, bool sparse)
{
  const GpOptimizationResult& best = search.best;
  GpOutputModel model;
  model.iterations = search.iterations;
  model.hyperparameters = best.hyperparameters;
  model.converged = best.converged;
  model.sparse = sparse;
  model.noise_variance = exact_objective.noiseVariance(best.hyperparameters);
  model.log_likelihood = best.log_likelihood;
  const GpRegressionData data = exact_objective.regressionData(best.hyperparameters);
  const Eigen::VectorXd kernel_parameters = best.hyperparameters.head(kernel.parameterCount());
  model.posterior =
      sparse ? GpPosterior::sparse(kernel, kernel_parameters, data, inducing_inputs,
                                   &model.mean_coefficients)
             : GpPosterior::exact(kernel, kernel_parameters, data, &model.mean_coefficients);
  model.termination =
      (sparse ? "sparse GP (" + std::to_string(inducing_inputs.cols()) + " inducing inputs), "
              : std::string("exact GP, ")) +
      search.how + ": " + best.termination;
  return model;
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

  GpSearch search;
  if (warm_start != nullptr && !optimise) {
    search = keptHyperparameters(*warm_start, use_subset ? vfe_objective : exact_objective);
  } else if (warm_start != nullptr) {
    search = warmStartSearch(*warm_start, use_subset, options, exact_objective, vfe_objective);
  } else {
    search = multiStartSearch(problem, exact_problem, options, seed, use_subset);
    if (use_subset && options.refine_iterations > 0) {
      refineOnVfeBound(vfe_objective, options, inducing_inputs.cols(), vfe_problem.groups.size(),
                       &search);
    }
  }
  return gpOutputAt(search, problem.kernel, exact_objective, inducing_inputs, sparse);
}

}  // namespace odometry_calibration
