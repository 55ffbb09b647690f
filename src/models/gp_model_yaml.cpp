// Save / load of GaussianProcessModel: options, joints, input scale, and per output the
// hyperparameters, the mean coefficients and the posterior's state (exact: training inputs,
// alpha and noise variances, the Cholesky factor is recomputed on load; sparse: inducing
// inputs, w and V). Doubles are written with 17 significant digits, so they load bit-exact.
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/models/gp_model.h"

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

}  // namespace

std::string GaussianProcessModel::toYaml() const
{
  if (!fitted_) {
    throw std::logic_error("gp: toYaml() before fit()");
  }
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << name();
  out << YAML::Key << "joints" << YAML::Value << YAML::BeginSeq;
  for (std::size_t j = 0; j < joints_.names.size(); ++j) {
    out << YAML::Flow << YAML::BeginSeq << joints_.names[j]
        << (joints_.kinds[j] == EncoderKind::kIncremental ? "incremental" : "absolute")
        << YAML::EndSeq;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "options" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "mean" << YAML::Value << toString(options_.mean);
  out << YAML::Key << "kernel" << YAML::Value << toString(options_.kernel);
  out << YAML::Key << "learn_noise" << YAML::Value << options_.learn_noise;
  out << YAML::Key << "starts" << YAML::Value << options_.starts;
  out << YAML::Key << "max_iterations" << YAML::Value << options_.max_iterations;
  out << YAML::Key << "seed" << YAML::Value << options_.seed;
  out << YAML::Key << "max_exact_pairs" << YAML::Value << options_.max_exact_pairs;
  out << YAML::Key << "likelihood_subset" << YAML::Value << options_.likelihood_subset;
  out << YAML::Key << "refine_iterations" << YAML::Value << options_.refine_iterations;
  out << YAML::Key << "refine_subset" << YAML::Value << options_.refine_subset;
  out << YAML::Key << "inducing_points" << YAML::Value << options_.inducing_points;
  out << YAML::Key << "outlier_threshold" << YAML::Value << options_.outlier_threshold;
  out << YAML::Key << "prefit_huber_threshold" << YAML::Value << options_.prefit_huber_threshold;
  out << YAML::Key << "outlier_passes" << YAML::Value << options_.outlier_passes;
  out << YAML::Key << "predict_learned_noise" << YAML::Value << options_.predict_learned_noise;
  out << YAML::Key << "num_threads" << YAML::Value << options_.num_threads;
  out << YAML::EndMap;
  out << YAML::Key << "input_scale" << YAML::Value;
  emitVector(out, input_scale_);
  out << YAML::Key << "outputs" << YAML::Value << YAML::BeginSeq;
  for (int axis = 0; axis < 3; ++axis) {
    const GpOutputModel& output = outputs_[static_cast<std::size_t>(axis)];
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
  out << YAML::EndSeq;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

std::unique_ptr<GaussianProcessModel> GaussianProcessModel::fromYaml(const std::string& text)
{
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(std::string("gp yaml: ") + error.what());
  }
  try {
    if (require(root, "model", "the file").as<std::string>() != "gp") {
      throw std::runtime_error("gp yaml: not a gp model");
    }
    JointLayout joints;
    for (const YAML::Node& joint : require(root, "joints", "the file")) {
      joints.names.push_back(joint[0].as<std::string>());
      const std::string kind = joint[1].as<std::string>();
      if (kind != "incremental" && kind != "absolute") {
        throw std::runtime_error("gp yaml: joint kind must be incremental or absolute");
      }
      joints.kinds.push_back(kind == "absolute" ? EncoderKind::kAbsolute
                                                : EncoderKind::kIncremental);
    }
    const YAML::Node o = require(root, "options", "the file");
    GpOptions options;
    options.mean = parseGpMeanFunction(require(o, "mean", "options").as<std::string>());
    options.kernel = parseGpKernelType(require(o, "kernel", "options").as<std::string>());
    options.learn_noise = require(o, "learn_noise", "options").as<bool>();
    options.starts = require(o, "starts", "options").as<int>();
    options.max_iterations = require(o, "max_iterations", "options").as<int>();
    options.seed = require(o, "seed", "options").as<unsigned>();
    options.max_exact_pairs = require(o, "max_exact_pairs", "options").as<std::size_t>();
    options.likelihood_subset = require(o, "likelihood_subset", "options").as<std::size_t>();
    options.refine_iterations = require(o, "refine_iterations", "options").as<int>();
    options.refine_subset = require(o, "refine_subset", "options").as<std::size_t>();
    options.inducing_points = require(o, "inducing_points", "options").as<std::size_t>();
    options.outlier_threshold = require(o, "outlier_threshold", "options").as<double>();
    options.prefit_huber_threshold = require(o, "prefit_huber_threshold", "options").as<double>();
    options.outlier_passes = require(o, "outlier_passes", "options").as<int>();
    options.predict_learned_noise = require(o, "predict_learned_noise", "options").as<bool>();
    options.num_threads = require(o, "num_threads", "options").as<int>();
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
      const YAML::Node node = outputs[static_cast<std::size_t>(axis)];
      const std::string where = std::string("output ") + kAxisNames[axis];
      GpOutputModel& output = model->outputs_[static_cast<std::size_t>(axis)];
      output.hyperparameters = readVector(node, "hyperparameters", where);
      if (output.hyperparameters.size() < kernel.parameterCount()) {
        throw std::runtime_error("gp yaml: too few hyperparameters in " + where);
      }
      output.noise_variance = require(node, "noise_variance", where).as<double>();
      output.mean_coefficients = readVector(node, "mean_coefficients", where);
      if (output.mean_coefficients.size() != 0 && output.mean_coefficients.size() != m) {
        throw std::runtime_error("gp yaml: mean_coefficients in " + where +
                                 " needs one value per joint");
      }
      output.log_likelihood = require(node, "log_likelihood", where).as<double>();
      output.converged = true;
      output.termination = "loaded";
      const Eigen::VectorXd kernel_parameters =
          output.hyperparameters.head(kernel.parameterCount());
      const std::string kind = require(node, "posterior", where).as<std::string>();
      if (kind == "exact") {
        output.posterior = GpPosterior::exactFromState(
            kernel, kernel_parameters, readColumns(node, "training_inputs", m, where),
            readVector(node, "weights", where), readVector(node, "noise", where));
      } else if (kind == "sparse") {
        output.sparse = true;
        const Eigen::MatrixXd inducing = readColumns(node, "inducing_inputs", m, where);
        output.posterior = GpPosterior::sparseFromState(
            kernel, kernel_parameters, inducing, readVector(node, "weights", where),
            readColumns(node, "variance_matrix", inducing.cols(), where));
      } else {
        throw std::runtime_error("gp yaml: posterior of " + where + " must be exact or sparse");
      }
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
