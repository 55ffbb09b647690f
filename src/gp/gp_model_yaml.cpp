// Save / load of GaussianProcessModel: options, joints, input scale, and per output the
// hyperparameters, the mean coefficients and the posterior's state (exact: training inputs,
// alpha and noise variances, the Cholesky factor is recomputed on load; sparse: inducing
// inputs, w and V). Doubles are written with 17 significant digits, so they load bit-exact.
#include <stdexcept>
#include <type_traits>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/common/yaml_reading.h"
#include "odometry_calibration/gp/gp_model.h"
#include "odometry_calibration/models/model_yaml.h"

namespace odometry_calibration {
namespace {

const char* const kAxisNames[3] = {"x", "y", "theta"};

void emitVector(YAML::Emitter& out, const Eigen::VectorXd& v)
{
  out << YAML::Flow << YAML::BeginSeq;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    out << v(i);
  }
  out << YAML::EndSeq;
}

/// Columns of a matrix, one flow sequence each.
void emitColumns(YAML::Emitter& out, const Eigen::MatrixXd& matrix)
{
  out << YAML::BeginSeq;
  for (Eigen::Index c = 0; c < matrix.cols(); ++c) {
    emitVector(out, matrix.col(c));
  }
  out << YAML::EndSeq;
}

YAML::Node require(const YAML::Node& node, const std::string& key, const std::string& where)
{
  const YAML::Node value = node[key];
  if (!value) {
    throw std::runtime_error("gp yaml: missing '" + key + "' in " + where);
  }
  return value;
}

Eigen::VectorXd readVector(const YAML::Node& node, const std::string& key, const std::string& where)
{
  const auto values = require(node, key, where).as<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

Eigen::MatrixXd readColumns(const YAML::Node& node, const std::string& key, Eigen::Index rows,
                            const std::string& where)
{
  const YAML::Node columns = require(node, key, where);
  Eigen::MatrixXd matrix(rows, static_cast<Eigen::Index>(columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const auto values = columns[c].as<std::vector<double>>();
    if (static_cast<Eigen::Index>(values.size()) != rows) {
      throw std::runtime_error("gp yaml: '" + key + "' in " + where + " needs " +
                               std::to_string(rows) + " values per entry");
    }
    matrix.col(static_cast<Eigen::Index>(c)) =
        Eigen::Map<const Eigen::VectorXd>(values.data(), rows);
  }
  return matrix;
}

/// The options a fitted GP saves, each key once: `visit(key, value)` for each, in the file's
/// order (after `mean` and `kernel`, which are saved by name). `Options` is GpOptions or const
/// GpOptions, so that writing and reading go through the same table.
template <class Options, class Visit>
void visitSavedGpOptions(Options& options, Visit&& visit)
{
  visit("learn_noise", options.learn_noise);
  visit("starts", options.starts);
  visit("max_iterations", options.max_iterations);
  visit("seed", options.seed);
  visit("max_exact_pairs", options.max_exact_pairs);
  visit("likelihood_subset", options.likelihood_subset);
  visit("refine_iterations", options.refine_iterations);
  visit("refine_subset", options.refine_subset);
  visit("inducing_points", options.inducing_points);
  visit("outlier_threshold", options.outlier_threshold);
  visit("prefit_huber_threshold", options.prefit_huber_threshold);
  visit("outlier_passes", options.outlier_passes);
  visit("predict_learned_noise", options.predict_learned_noise);
  visit("num_threads", options.num_threads);
}

void emitGpOptions(YAML::Emitter& out, const GpOptions& options)
{
  out << YAML::Key << "options" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "mean" << YAML::Value << toString(options.mean);
  out << YAML::Key << "kernel" << YAML::Value << toString(options.kernel);
  visitSavedGpOptions(options, YamlKeyWriter(out));
  out << YAML::EndMap;
}

/// One output's map: its axis, hyperparameters, noise, mean and the posterior's state.
void emitGpOutput(YAML::Emitter& out, int axis, const GpOutputModel& output)
{
  const GpPosterior& posterior = output.posterior;
  const bool exact = posterior.kind() == GpPosterior::Kind::kExact;
  out << YAML::BeginMap;
  out << YAML::Key << "axis" << YAML::Value << kAxisNames[axis];
  out << YAML::Key << "posterior" << YAML::Value << (exact ? "exact" : "sparse");
  out << YAML::Key << "hyperparameters" << YAML::Value;
  emitVector(out, output.hyperparameters);
  out << YAML::Key << "noise_variance" << YAML::Value << output.noise_variance;
  out << YAML::Key << "mean_coefficients" << YAML::Value;
  emitVector(out, output.mean_coefficients);
  out << YAML::Key << "log_likelihood" << YAML::Value << output.log_likelihood;
  out << YAML::Key << (exact ? "training_inputs" : "inducing_inputs") << YAML::Value;
  emitColumns(out, posterior.basis());
  out << YAML::Key << "weights" << YAML::Value;
  emitVector(out, posterior.weights());
  if (exact) {
    out << YAML::Key << "noise" << YAML::Value;
    emitVector(out, posterior.noiseVariance());
  } else {
    out << YAML::Key << "variance_matrix" << YAML::Value;
    emitColumns(out, posterior.varianceMatrix());
  }
  out << YAML::EndMap;
}

/// The joints of the file's `joints` list. Throws std::runtime_error for a kind other than
/// incremental or absolute.
JointLayout readGpJoints(const YAML::Node& root)
{
  JointLayout joints;
  for (const YAML::Node& joint : require(root, "joints", "the file")) {
    joints.names.push_back(joint[0].as<std::string>());
    const std::string kind = joint[1].as<std::string>();
    if (kind != "incremental" && kind != "absolute") {
      throw std::runtime_error("gp yaml: joint kind must be incremental or absolute");
    }
    joints.kinds.push_back(kind == "absolute" ? EncoderKind::kAbsolute : EncoderKind::kIncremental);
  }
  return joints;
}

/// The options of the file's `options` map (every key required).
GpOptions readGpOptions(const YAML::Node& root)
{
  const YAML::Node o = require(root, "options", "the file");
  GpOptions options;
  options.mean = parseGpMeanFunction(require(o, "mean", "options").as<std::string>());
  options.kernel = parseGpKernelType(require(o, "kernel", "options").as<std::string>());
  visitSavedGpOptions(options, [&o](const char* key, auto& value) {
    value = require(o, key, "options").as<std::decay_t<decltype(value)>>();
  });
  return options;
}

/// The posterior's state of one output map: exact (training inputs, weights, noise) or sparse
/// (inducing inputs, weights, variance matrix).
void readGpPosterior(const YAML::Node& node, const GpKernel& kernel, Eigen::Index joint_count,
                     const std::string& where, GpOutputModel* output)
{
  const Eigen::VectorXd kernel_parameters = output->hyperparameters.head(kernel.parameterCount());
  const std::string kind = require(node, "posterior", where).as<std::string>();
  if (kind == "exact") {
    output->posterior = GpPosterior::exactFromState(
        kernel, kernel_parameters, readColumns(node, "training_inputs", joint_count, where),
        readVector(node, "weights", where), readVector(node, "noise", where));
  } else if (kind == "sparse") {
    output->sparse = true;
    const Eigen::MatrixXd inducing = readColumns(node, "inducing_inputs", joint_count, where);
    output->posterior = GpPosterior::sparseFromState(
        kernel, kernel_parameters, inducing, readVector(node, "weights", where),
        readColumns(node, "variance_matrix", inducing.cols(), where));
  } else {
    throw std::runtime_error("gp yaml: posterior of " + where + " must be exact or sparse");
  }
}

/// One output of the file's `outputs` list (its hyperparameters checked against `kernel`, its
/// mean coefficients against the `joint_count` joints).
void readGpOutput(const YAML::Node& node, int axis, const GpKernel& kernel,
                  Eigen::Index joint_count, GpOutputModel* output)
{
  const std::string where = std::string("output ") + kAxisNames[axis];
  output->hyperparameters = readVector(node, "hyperparameters", where);
  if (output->hyperparameters.size() < kernel.parameterCount()) {
    throw std::runtime_error("gp yaml: too few hyperparameters in " + where);
  }
  output->noise_variance = require(node, "noise_variance", where).as<double>();
  output->mean_coefficients = readVector(node, "mean_coefficients", where);
  if (output->mean_coefficients.size() != 0 && output->mean_coefficients.size() != joint_count) {
    throw std::runtime_error("gp yaml: mean_coefficients in " + where +
                             " needs one value per joint");
  }
  output->log_likelihood = require(node, "log_likelihood", where).as<double>();
  output->converged = true;
  output->termination = "loaded";
  readGpPosterior(node, kernel, joint_count, where, output);
}

}  // namespace

std::string GaussianProcessModel::toYaml() const
{
  if (!fitted_) {
    throw std::logic_error("gp: toYaml() before fit()");
  }
  return writeModelYaml(name(), [this](YAML::Emitter& out) {
    emitJointLayoutYaml(out, joints_);
    emitGpOptions(out, options_);
    out << YAML::Key << "input_scale" << YAML::Value;
    emitVector(out, input_scale_);
    out << YAML::Key << "outputs" << YAML::Value << YAML::BeginSeq;
    for (int axis = 0; axis < 3; ++axis)
      emitGpOutput(out, axis, outputs_[static_cast<std::size_t>(axis)]);
    out << YAML::EndSeq;
  });
}

std::unique_ptr<GaussianProcessModel> GaussianProcessModel::fromYaml(const std::string& text)
{
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(std::string("gp yaml: ") + error.what());
  }
  refuseYamlBeyond(root, "gp yaml");
  try {
    if (require(root, "model", "the file").as<std::string>() != "gp") {
      throw std::runtime_error("gp yaml: not a gp model");
    }
    const JointLayout joints = readGpJoints(root);
    const GpOptions options = readGpOptions(root);
    auto model = std::make_unique<GaussianProcessModel>(options, joints);
    const auto m = static_cast<Eigen::Index>(joints.names.size());
    model->input_scale_ = readVector(root, "input_scale", "the file");
    if (model->input_scale_.size() != m) {
      throw std::runtime_error("gp yaml: input_scale needs one value per joint");
    }
    const YAML::Node outputs = require(root, "outputs", "the file");
    if (outputs.size() != 3) {
      throw std::runtime_error("gp yaml: outputs needs x, y and theta");
    }
    const GpKernel kernel(options.kernel, static_cast<int>(m));
    for (int axis = 0; axis < 3; ++axis) {
      readGpOutput(outputs[static_cast<std::size_t>(axis)], axis, kernel, m,
                   &model->outputs_[static_cast<std::size_t>(axis)]);
    }
    model->fitted_ = true;
    return model;
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(std::string("gp yaml: ") + error.what());
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(std::string("gp yaml: ") + error.what());
  }
}

}  // namespace odometry_calibration
