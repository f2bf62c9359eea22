// Estimators of the paper's relation d_hat_c = beta_c u_c + eps_c per channel (section III-B): recursive least
// squares and the Ceres batch fits. beta is dimensionless, eps in the channel's unit [N, N, N m].
#include <memory>
#include <string>

#include "conversions.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/estimators/batch_least_squares_fit.hpp"
#include "pushpred/estimators/recursive_least_squares.hpp"

namespace pushpred::python {
namespace {

constexpr const char* kParametersDoc = R"doc(
The relation after the intervals fed so far, as a dict: beta [-] and eps [N, N, N m] per channel (x, y, rotation),
covariance (three 2 x 2 arrays of (beta, eps)), beta_std, eps_std, residual_std [N, N, N m], samples,
effective_samples, intervals, loss_scale. Raises InputError "NAME: not ready: REASON" before it can be told.)doc";

/// An n x 3 array from Python, or InputError naming what is wrong with its shape.
Eigen::MatrixX3d channels(const Eigen::MatrixXd& m, const char* what) {
  if (m.cols() != 3)
    throw InputError(std::string(what) + " must have 3 columns (x, y, rotation), not " + std::to_string(m.cols()));
  return m;
}

RobustLoss parse_loss(const std::string& name) {
  if (name == "none") return RobustLoss::None;
  if (name == "huber") return RobustLoss::Huber;
  if (name == "cauchy") return RobustLoss::Cauchy;
  throw InputError("loss must be 'none', 'huber' or 'cauchy', not '" + name + "'");
}

}  // namespace

void bind_estimators(py::module_& m) {
  m.def("relation_estimator_names", &relation_estimator_names,
        "names for relation_estimator(): rls, rls_forget, batch, batch_huber, ...");

  py::class_<RelationEstimator, std::unique_ptr<RelationEstimator>>(m, "RelationEstimator", R"doc(
An estimator of the relation d_hat = beta u + eps, fed one identification interval at a time. Make one with
relation_estimator(name), RecursiveLeastSquares(...) or BatchLeastSquaresFit(...).)doc")
      .def_property_readonly("name", &RelationEstimator::name, "the estimator's name (relation_estimator_names())")
      .def("__repr__",
           [](const py::object& self) {
             const auto& e = self.cast<const RelationEstimator&>();
             return "<pushpred." + py::type::of(self).attr("__name__").cast<std::string>() + " '" + e.name() +
                    "': " + (e.ready() ? std::string("ready") : "not ready (" + e.not_ready_reason() + ")") + ">";
           })
      .def(
          "add_interval",
          [](RelationEstimator& e, const Eigen::MatrixXd& u, const Eigen::MatrixXd& d_hat) {
            const Eigen::MatrixX3d u3 = channels(u, "u"), d3 = channels(d_hat, "d_hat");
            without_gil([&] { e.add_interval(u3, d3); });
          },
          py::arg("u"), py::arg("d_hat"), R"doc(
Feeds one identification interval: u, the applied input, and d_hat, the estimated disturbance, both n x 3
(x [N], y [N], rotation [N m]), one row per sample.)doc")
      .def(
          "add_estimate",
          [](RelationEstimator& e, const py::dict& estimate) {
            const auto input = input_and_disturbance(estimate);  // (u, d_hat)
            without_gil([&] { e.add_interval(input.first, input.second); });
          },
          py::arg("estimate"), "Feeds an observer's output over one interval (a dict from estimate_disturbance()).")
      .def_property_readonly("ready", &RelationEstimator::ready, "True once parameters() can be asked")
      .def_property_readonly("not_ready_reason", &RelationEstimator::not_ready_reason,
                             "why parameters() cannot be asked yet; empty when it can")
      .def(
          "parameters", [](const RelationEstimator& e) { return relation_dict(e.parameters()); }, kParametersDoc)
      .def("reset", &RelationEstimator::reset, "forgets every interval fed so far; the options stay")
      .def("clone", &RelationEstimator::clone, "an independent copy, with the intervals fed so far");

  py::class_<RecursiveLeastSquares, RelationEstimator, std::unique_ptr<RecursiveLeastSquares>>(
      m, "RecursiveLeastSquares",
      "The paper's recursive least squares; forgetting in (0, 1] weighs an interval i intervals old by forgetting^i.")
      .def(py::init([](double forgetting) {
             RlsOptions o;
             o.forgetting = forgetting;
             return std::make_unique<RecursiveLeastSquares>(o);
           }),
           py::arg("forgetting") = 1.0);

  py::class_<BatchLeastSquaresFit, RelationEstimator, std::unique_ptr<BatchLeastSquaresFit>>(
      m, "BatchLeastSquaresFit", R"doc(
The relation fitted by Ceres over all data fed so far, refitted at every interval. loss: "none", "huber" or
"cauchy"; loss_scale per channel [N, N, N m] (0: automatic); joint: one problem over the three channels, so that a
robust loss down-weights a sample as a whole.)doc")
      .def(py::init([](const std::string& loss, const Eigen::Vector3d& loss_scale, bool joint) {
             BatchFitOptions o;
             o.loss = parse_loss(loss);
             o.loss_scale = loss_scale;
             o.joint = joint;
             return std::make_unique<BatchLeastSquaresFit>(o);
           }),
           py::arg("loss") = "none", py::arg("loss_scale") = Eigen::Vector3d::Zero().eval(), py::arg("joint") = false);

  m.def(
      "relation_estimator",
      [](const std::string& name) { return make_relation_estimator(name); }, py::arg("name"),
      "The relation estimator called `name` (relation_estimator_names()) with its default options.");

  m.def(
      "least_squares_relation",
      [](const Eigen::MatrixXd& u, const Eigen::MatrixXd& d_hat) {
        return relation_dict(least_squares_relation(channels(u, "u"), channels(d_hat, "d_hat")));
      },
      py::arg("u"), py::arg("d_hat"),
      "The reference batch least-squares fit of all rows at once, per channel (Householder QR), as a dict like "
      "RelationEstimator.parameters().");
}

}  // namespace pushpred::python
