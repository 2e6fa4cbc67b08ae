// The batched evaluation under fuzzycsg.torch's layer: B trees of one topology (a full binary
// tree of P leaves of one family), each given by its leaves' parameters (B x P x k), its
// operators' logits (B x (P - 1) x 4) and a temperature (B), evaluated at its own points
// (B x N x dim), and the vector-Jacobian product of that map by every input. Each tree is one
// forward (and one reverse) sweep of the kernel over its points, whose results are the same for
// any thread count.

#include <pybind11/stl.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "common.hpp"
#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/fit/option_names.hpp"

namespace fuzzycsg::python {

namespace {

class TreeLayer {
 public:
  TreeLayer(int leaves, int dim, const std::string& family, const std::string& ops,
            std::optional<double> sharpness, double omega, std::uint64_t seed, int threads) {
    FullTreeOptions o;
    if (dim != 2 && dim != 3) throw OptionError("dim", "must be 2 or 3");
    if (leaves < 2 || (leaves & (leaves - 1)) != 0 || leaves > (1 << 16)) {
      throw OptionError("leaves", "must be a power of two in [2, 65536]");
    }
    o.dim = dim;
    o.leaves = leaves;
    const auto f = primitive_from_name(family, dim);
    if (!f) throw OptionError("family", "unknown " + std::to_string(dim) + "D primitive " + family);
    o.family = *f;
    const auto mode = option_value(kOperatorModeNames, ops);
    if (!mode || *mode == OperatorMode::kGodel) {
      throw OptionError("ops", "unified or product, not " + ops);
    }
    o.ops = *mode;
    o.omega = omega;
    o.seed = seed;
    o.sharpness = sharpness;
    tree_ = make_full_binary_tree(o);
    // Leaves' parameters, but their steps' sharpness, fixed to the layer's; the operators'
    // logits and temperatures, omega fixed.
    for (const Node& n : tree_.nodes) {
      if (n.kind == NodeKind::kPrimitive) {
        std::vector<std::uint32_t> idx;
        for (ParamRef r : n.intrinsic) idx.push_back(r.index);
        for (ParamRef r : n.placement.translate) idx.push_back(r.index);
        for (ParamRef r : n.placement.rotate) idx.push_back(r.index);
        if (n.placement.scale) idx.push_back(n.placement.scale->index);
        if (n.step.param) {
          tree_.params[*n.step.param].fixed = true;
          sharpness_ = tree_.params[*n.step.param].value;
        }
        for (std::uint32_t k : idx) tree_.params.at(k).fixed = false;
        leaf_index_.push_back(std::move(idx));
      } else if (n.op == OpKind::kUnified) {
        for (ParamRef r : n.unified) logit_index_.push_back(r.index);
        tree_.params[*n.temperature].fixed = false;
        temperature_index_.push_back(n.temperature->index);
        types_.emplace_back("unified");
      } else {
        types_.emplace_back(op_name(n.op));
      }
    }
    k_ = leaf_index_.front().size();
    for (std::uint32_t k : leaf_index_.front()) {
      const std::string& n = tree_.params.at(k).name;
      leaf_fields_.push_back(n.substr(n.rfind('.') + 1));
    }
    evaluator_.emplace(tree_, EvalOptions{threads});
  }

  int leaves() const { return static_cast<int>(leaf_index_.size()); }
  int dim() const { return tree_.dim; }
  std::size_t leaf_size() const { return k_; }
  bool unified() const { return !logit_index_.empty(); }
  double sharpness() const { return sharpness_; }
  const std::vector<std::string>& leaf_fields() const { return leaf_fields_; }
  const std::vector<std::string>& operator_types() const { return types_; }

  py::array_t<float> forward(const py::handle& leaf, const py::handle& logits,
                             const py::handle& temperature, const py::handle& points) const {
    Inputs in = inputs(leaf, logits, temperature, points);
    std::vector<float> out(static_cast<std::size_t>(in.b * in.n));
    {
      py::gil_scoped_release release;
      std::vector<double> params = tree_.params.values();
      for (py::ssize_t b = 0; b < in.b; ++b) {
        fill(params, in, b);
        evaluator_->forward(
            params, point_span(in, b),
            std::span<float>(out.data() + b * in.n, static_cast<std::size_t>(in.n)));
      }
    }
    return to_numpy(std::move(out), {in.b, in.n});
  }

  // d/d(leaf, logits, temperature, points) of sum_{b,i} grad_out[b, i] occupancy[b, i].
  py::tuple backward(const py::handle& leaf, const py::handle& logits,
                     const py::handle& temperature, const py::handle& points,
                     const py::handle& grad_out, bool points_grad) const {
    Inputs in = inputs(leaf, logits, temperature, points);
    const CArray<float> g = as_array<float>(grad_out, "grad_output");
    check_shape(g, "grad_output", {in.b, in.n});
    check_finite(g, "grad_output");
    const auto p = static_cast<std::size_t>(leaves());
    std::vector<double> d_leaf(static_cast<std::size_t>(in.b) * p * k_);
    std::vector<double> d_logits(static_cast<std::size_t>(in.b) * logit_index_.size());
    std::vector<double> d_temp(static_cast<std::size_t>(in.b));
    std::vector<float> d_points(points_grad ? static_cast<std::size_t>(in.pts.size()) : 0);
    {
      py::gil_scoped_release release;
      std::vector<double> params = tree_.params.values();
      std::vector<double> grad(params.size());
      const auto d = static_cast<std::size_t>(dim());
      for (py::ssize_t b = 0; b < in.b; ++b) {
        fill(params, in, b);
        Loss loss;
        loss.kind = Loss::Kind::kSum;
        loss.weights = {g.data() + b * in.n, static_cast<std::size_t>(in.n)};
        std::span<float> pg;
        if (points_grad) pg = {d_points.data() + b * in.n * d, static_cast<std::size_t>(in.n) * d};
        evaluator_->backward(params, point_span(in, b), loss, grad, {}, pg);
        const auto bb = static_cast<std::size_t>(b);
        for (std::size_t l = 0; l < p; ++l) {
          for (std::size_t j = 0; j < k_; ++j)
            d_leaf[(bb * p + l) * k_ + j] = grad[leaf_index_[l][j]];
        }
        for (std::size_t j = 0; j < logit_index_.size(); ++j) {
          d_logits[bb * logit_index_.size() + j] = grad[logit_index_[j]];
        }
        double t = 0;
        for (std::uint32_t k : temperature_index_) t += grad[k];
        d_temp[bb] = t;
      }
    }
    const auto pp = static_cast<py::ssize_t>(p);
    py::object dp = py::none();
    if (points_grad) dp = to_numpy(std::move(d_points), {in.b, in.n, py::ssize_t{dim()}});
    return py::make_tuple(
        to_numpy(std::move(d_leaf), {in.b, pp, static_cast<py::ssize_t>(k_)}),
        to_numpy(std::move(d_logits), {in.b, unified() ? pp - 1 : 0, py::ssize_t{4}}),
        to_numpy(std::move(d_temp), {in.b}), dp);
  }

  // Tree b of a batch as an ordinary tree.
  Tree tree(const py::handle& leaf, const py::handle& logits, double temperature) const {
    const auto p = static_cast<py::ssize_t>(leaves());
    const CArray<double> l = as_array<double>(leaf, "leaf");
    check_shape(l, "leaf", {p, static_cast<py::ssize_t>(k_)});
    check_finite(l, "leaf");
    Tree t = tree_;
    for (std::size_t i = 0; i < leaf_index_.size(); ++i) {
      for (std::size_t j = 0; j < k_; ++j)
        t.params.at(leaf_index_[i][j]).value = l.data()[i * k_ + j];
    }
    if (unified()) {
      const CArray<double> c = as_array<double>(logits, "logits");
      check_shape(c, "logits", {p - 1, 4});
      check_finite(c, "logits");
      for (std::size_t j = 0; j < logit_index_.size(); ++j)
        t.params.at(logit_index_[j]).value = c.data()[j];
      for (std::uint32_t k : temperature_index_) t.params.at(k).value = temperature;
      for (std::uint32_t k : temperature_index_) t.params.at(k).fixed = true;
    }
    validate(t, "tree");
    return t;
  }

 private:
  struct Inputs {
    CArray<double> leaf, logits, temperature;
    CArray<float> pts;
    py::ssize_t b = 0, n = 0;
  };

  Inputs inputs(const py::handle& leaf, const py::handle& logits, const py::handle& temperature,
                const py::handle& points) const {
    Inputs in;
    const auto p = static_cast<py::ssize_t>(leaves());
    in.leaf = as_array<double>(leaf, "leaf");
    check_shape(in.leaf, "leaf", {-1, p, static_cast<py::ssize_t>(k_)});
    in.b = in.leaf.shape(0);
    check_finite(in.leaf, "leaf");
    if (unified()) {
      in.logits = as_array<double>(logits, "logits");
      check_shape(in.logits, "logits", {in.b, p - 1, 4});
      check_finite(in.logits, "logits");
      in.temperature = as_array<double>(temperature, "temperature");
      check_shape(in.temperature, "temperature", {in.b});
      check_finite(in.temperature, "temperature");
      for (py::ssize_t b = 0; b < in.b; ++b) {
        if (!(in.temperature.data()[b] > 0)) throw py::value_error("temperature: must be > 0");
      }
    }
    in.pts = as_array<float>(points, "points");
    check_shape(in.pts, "points", {in.b, -1, py::ssize_t{dim()}});
    check_finite(in.pts, "points");
    in.n = in.pts.shape(1);
    return in;
  }

  void fill(std::vector<double>& params, const Inputs& in, py::ssize_t b) const {
    const auto bb = static_cast<std::size_t>(b);
    const double* l = in.leaf.data() + bb * leaf_index_.size() * k_;
    for (std::size_t i = 0; i < leaf_index_.size(); ++i) {
      for (std::size_t j = 0; j < k_; ++j) params[leaf_index_[i][j]] = l[i * k_ + j];
    }
    if (!unified()) return;
    const double* c = in.logits.data() + bb * logit_index_.size();
    for (std::size_t j = 0; j < logit_index_.size(); ++j) params[logit_index_[j]] = c[j];
    for (std::uint32_t k : temperature_index_) params[k] = in.temperature.data()[b];
  }

  std::span<const float> point_span(const Inputs& in, py::ssize_t b) const {
    const auto per = static_cast<std::size_t>(in.n) * static_cast<std::size_t>(dim());
    return {in.pts.data() + static_cast<std::size_t>(b) * per, per};
  }

  Tree tree_;
  std::optional<Evaluator> evaluator_;
  std::vector<std::vector<std::uint32_t>> leaf_index_;  // per leaf, left to right
  std::vector<std::uint32_t> logit_index_;              // 4 per operator, post-order
  std::vector<std::uint32_t> temperature_index_;
  std::vector<std::string> leaf_fields_, types_;
  std::size_t k_ = 0;
  double sharpness_ = 0;
};

}  // namespace

void register_layer(py::module_& m) {
  py::class_<TreeLayer>(m, "TreeLayer",
                        "Batched evaluation of full binary trees of one topology, with the "
                        "vector-Jacobian product by every input")
      .def(py::init<int, int, const std::string&, const std::string&, std::optional<double>, double,
                    std::uint64_t, int>(),
           py::arg("leaves"), py::arg("dim") = 3, py::arg("family") = "quadric",
           py::arg("ops") = "unified", py::arg("sharpness") = py::none(), py::arg("omega") = 10.0,
           py::arg("seed") = 0, py::arg("threads") = 0)
      .def_property_readonly("leaves", &TreeLayer::leaves)
      .def_property_readonly("dim", &TreeLayer::dim)
      .def_property_readonly("leaf_size", &TreeLayer::leaf_size)
      .def_property_readonly("unified", &TreeLayer::unified)
      .def_property_readonly("sharpness", &TreeLayer::sharpness)
      .def_property_readonly("leaf_fields", &TreeLayer::leaf_fields)
      .def_property_readonly("operator_types", &TreeLayer::operator_types)
      .def("forward", &TreeLayer::forward, py::arg("leaf"), py::arg("logits"),
           py::arg("temperature"), py::arg("points"))
      .def("backward", &TreeLayer::backward, py::arg("leaf"), py::arg("logits"),
           py::arg("temperature"), py::arg("points"), py::arg("grad_output"),
           py::arg("points_grad") = true)
      .def("tree", &TreeLayer::tree, py::arg("leaf"), py::arg("logits"),
           py::arg("temperature") = 1000.0);
}

}  // namespace fuzzycsg::python
