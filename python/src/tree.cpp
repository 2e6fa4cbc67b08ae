// fuzzycsg.Tree, the builders, eval and grad.

#include <pybind11/stl.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common.hpp"
#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/program.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/fit/option_names.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::python {

void check_shape(const py::array& a, const char* what, std::vector<py::ssize_t> shape) {
  bool ok = a.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t k = 0; ok && k < shape.size(); ++k) {
    ok = shape[k] < 0 || a.shape(static_cast<py::ssize_t>(k)) == shape[k];
  }
  if (ok) return;
  const auto text = [](const std::vector<py::ssize_t>& s) {
    std::string t = "(";
    for (std::size_t k = 0; k < s.size(); ++k) {
      t += (k ? ", " : "") + (s[k] < 0 ? std::string("*") : std::to_string(s[k]));
    }
    return t + (s.size() == 1 ? ",)" : ")");
  };
  std::vector<py::ssize_t> got(a.shape(), a.shape() + a.ndim());
  throw py::value_error(std::string(what) + ": shape " + text(got) + ", expected " + text(shape));
}

CArray<float> points_array(const py::handle& points, int dim) {
  CArray<float> p = as_array<float>(points, "points");
  if (p.ndim() == 1 && p.size() == dim) p = p.reshape({py::ssize_t{1}, py::ssize_t{dim}});
  check_shape(p, "points", {-1, dim});
  check_finite(p, "points");
  return p;
}

namespace {

// The parameter vector: the tree's own values, or `params` (one per table entry).
std::vector<double> parameter_vector(const Tree& tree, const py::object& params) {
  if (params.is_none()) return tree.params.values();
  const CArray<double> a = as_array<double>(params, "params");
  check_shape(a, "params", {static_cast<py::ssize_t>(tree.params.size())});
  check_finite(a, "params");
  return {a.data(), a.data() + a.size()};
}

// "root.children[0].coefficients[3]" -> "root.children[0].coefficients"; names without a final
// index are their own group.
std::string group_of(const std::string& name) {
  if (name.empty() || name.back() != ']') return name;
  const auto open = name.rfind('[');
  if (open == std::string::npos || open + 2 > name.size() - 1) return name;
  for (std::size_t i = open + 1; i + 1 < name.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return name;
  }
  return name.substr(0, open);
}

// Entries of the parameter table named `name` (one) or grouped under it (an array's entries).
std::vector<std::size_t> entries_named(const Tree& tree, const std::string& name) {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < tree.params.size(); ++k) {
    const std::string& n = tree.params.at(k).name;
    if (n == name || group_of(n) == name) out.push_back(k);
  }
  if (out.empty()) throw py::key_error("no parameter named " + name);
  return out;
}

py::dict info(const Tree& tree) {
  const TreeCounts c = count(tree);
  py::dict d;
  d["dim"] = tree.dim;
  d["primitives"] = c.primitives;
  d["operators"] = c.operators;
  d["depth"] = c.depth;
  d["parameters"] = c.parameters;
  d["free_parameters"] = c.free_parameters;
  d["fixed_parameters"] = c.parameters - c.free_parameters;
  d["shared_parameters"] = c.shared_parameters;
  d["instructions"] = Program::compile(tree).tape().size();
  d["families"] = c.families;
  d["operator_kinds"] = c.operator_kinds;
  return d;
}

template <class E, std::size_t N>
E named(const OptionNames<E, N>& names, const std::string& value, const char* field) {
  if (const auto v = option_value(names, value)) return *v;
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + std::string(n.name);
  throw OptionError(field, "unknown value '" + value + "' (" + list + ")");
}

Tree full_binary_tree(int leaves, int dim, const std::string& family, const std::string& ops,
                      const std::string& op_init, const std::string& op_types, double init_range,
                      std::uint64_t seed, double temperature, double omega,
                      std::optional<double> sharpness) {
  FullTreeOptions o;
  o.dim = dim;
  if (dim != 2 && dim != 3) throw OptionError("dim", "must be 2 or 3");
  if (leaves < 1 || (leaves & (leaves - 1)) != 0 || leaves > (1 << 16)) {
    throw OptionError("leaves", "must be a power of two in [1, 65536]");
  }
  o.leaves = leaves;
  const auto f = primitive_from_name(family, dim);
  if (!f) throw OptionError("family", "unknown " + std::to_string(dim) + "D primitive " + family);
  o.family = *f;
  o.ops = named(kOperatorModeNames, ops, "ops");
  o.op_init = named(kOperatorInitNames, op_init, "op_init");
  o.op_types = named(kOperatorTypesNames, op_types, "op_types");
  o.init_range = init_range;
  o.seed = seed;
  o.temperature = temperature;
  o.omega = omega;
  o.sharpness = sharpness;
  Tree t = make_full_binary_tree(o);
  validate(t, "full_binary_tree");
  return t;
}

py::array_t<float> eval(const Tree& tree, const py::handle& points, const py::object& params,
                        int threads) {
  const CArray<float> p = points_array(points, tree.dim);
  const std::vector<double> values = parameter_vector(tree, params);
  const Evaluator ev(tree, EvalOptions{threads});
  std::vector<float> out(static_cast<std::size_t>(p.shape(0)));
  {
    py::gil_scoped_release release;
    ev.forward(values, std::span<const float>(p.data(), static_cast<std::size_t>(p.size())), out);
  }
  return to_numpy(std::move(out), {p.shape(0)});
}

// d/dparams of sum_i w_i o_i (loss "sum") or of the (weighted) mean squared error to `targets`
// (loss "mse"); with points_grad, also d/dpoints.
py::object grad(const Tree& tree, const py::handle& points, const py::object& weights,
                const py::object& params, const std::string& loss, const py::object& targets,
                bool points_grad, int threads) {
  const CArray<float> p = points_array(points, tree.dim);
  const auto n = p.shape(0);
  const std::vector<double> values = parameter_vector(tree, params);
  Loss l;
  CArray<float> w, t;
  if (loss == "sum") {
    l.kind = Loss::Kind::kSum;
  } else if (loss == "mse") {
    l.kind = Loss::Kind::kMse;
    if (targets.is_none()) throw py::value_error("targets: needed for loss 'mse'");
    t = as_array<float>(targets, "targets");
    check_shape(t, "targets", {n});
    check_finite(t, "targets");
    l.targets = {t.data(), static_cast<std::size_t>(n)};
  } else {
    throw py::value_error("loss: 'sum' or 'mse', not '" + loss + "'");
  }
  if (!weights.is_none()) {
    w = as_array<float>(weights, "weights");
    check_shape(w, "weights", {n});
    check_finite(w, "weights");
    l.weights = {w.data(), static_cast<std::size_t>(n)};
  }
  const Evaluator ev(tree, EvalOptions{threads});
  std::vector<double> g(values.size());
  std::vector<float> pg(points_grad ? static_cast<std::size_t>(p.size()) : 0);
  double value = 0;
  {
    py::gil_scoped_release release;
    value = ev.backward(
        values, std::span<const float>(p.data(), static_cast<std::size_t>(p.size())), l, g, {}, pg);
  }
  py::array_t<double> ga = to_numpy(std::move(g), {static_cast<py::ssize_t>(values.size())});
  if (!points_grad) return py::make_tuple(value, ga);
  return py::make_tuple(value, ga, to_numpy(std::move(pg), {n, py::ssize_t{tree.dim}}));
}

py::dict parameter_groups(const Tree& t) {
  std::map<std::string, std::vector<double>> groups;
  std::vector<std::string> order;
  for (const Parameter& p : t.params.entries()) {
    const std::string g = group_of(p.name);
    if (!groups.count(g)) order.push_back(g);
    groups[g].push_back(p.value);
  }
  py::dict d;
  for (const std::string& g : order) {
    auto& v = groups[g];
    const auto n = static_cast<py::ssize_t>(v.size());
    d[py::str(g)] = to_numpy(std::move(v), {n});
  }
  return d;
}

// Sets the entries named `name` (a parameter, or an array field's entries) and validates the
// tree; on an error the tree is unchanged.
void set_named(Tree& t, const std::string& name, const py::handle& value) {
  const auto idx = entries_named(t, name);
  CArray<double> a = as_array<double>(value, "value");
  if (a.ndim() == 0) a = a.reshape({py::ssize_t{1}});
  check_shape(a, "value", {static_cast<py::ssize_t>(idx.size())});
  check_finite(a, "value");
  Tree next = t;
  for (std::size_t k = 0; k < idx.size(); ++k) next.params.at(idx[k]).value = a.data()[k];
  validate(next, name);
  t = std::move(next);
}

void set_values(Tree& t, const py::handle& v) {
  const CArray<double> a = as_array<double>(v, "values");
  check_shape(a, "values", {static_cast<py::ssize_t>(t.params.size())});
  check_finite(a, "values");
  Tree next = t;
  next.params.set_values({a.data(), static_cast<std::size_t>(a.size())});
  validate(next, "values");
  t = std::move(next);
}

}  // namespace

void register_tree(py::module_& m) {
  py::class_<Tree>(m, "Tree", "A fuzzy CSG tree: nodes over one table of named parameters")
      .def_static(
          "read", [](const std::string& path) { return io::read_tree_file(path); }, py::arg("path"),
          "Reads a tree file (docs/tree-format.md)")
      .def_static(
          "from_json",
          [](const std::string& text, const std::string& source) {
            return io::read_tree_string(text, source);
          },
          py::arg("text"), py::arg("source") = "<string>", "Reads a tree from its JSON text")
      .def(
          "write", [](const Tree& t, const std::string& path) { io::write_tree_file(t, path); },
          py::arg("path"), "Writes the tree file (atomically)")
      .def("to_json", [](const Tree& t) { return io::write_tree_string(t); })
      .def("copy", [](const Tree& t) { return Tree(t); })
      .def_readonly("dim", &Tree::dim)
      .def_property_readonly("num_params", [](const Tree& t) { return t.params.size(); })
      .def_property_readonly("names",
                             [](const Tree& t) {
                               std::vector<std::string> names;
                               for (const Parameter& p : t.params.entries())
                                 names.push_back(p.name);
                               return names;
                             })
      .def_property(
          "values",
          [](const Tree& t) {
            std::vector<double> v = t.params.values();
            const auto n = static_cast<py::ssize_t>(v.size());
            return to_numpy(std::move(v), {n});
          },
          &set_values,
          "Every parameter's value, in the table's order (names); set to change them all")
      .def_property_readonly("fixed",
                             [](const Tree& t) {
                               std::vector<bool> f;
                               for (const Parameter& p : t.params.entries()) f.push_back(p.fixed);
                               return py::array(py::cast(f));
                             })
      .def(
          "get",
          [](const Tree& t, const std::string& name) {
            std::vector<double> v;
            for (std::size_t k : entries_named(t, name)) v.push_back(t.params.at(k).value);
            const auto n = static_cast<py::ssize_t>(v.size());
            return to_numpy(std::move(v), {n});
          },
          py::arg("name"), "A parameter, or the entries of an array field, as an array")
      .def("set", &set_named, py::arg("name"), py::arg("value"),
           "Sets a parameter, or the entries of an array field; checked against their ranges")
      .def("parameters", &parameter_groups,
           "Every parameter by name, array fields as one array each, in table order")
      .def("info", &info, "Counts: primitives, operators, depth, parameters, families")
      .def("__repr__", [](const Tree& t) {
        const TreeCounts c = count(t);
        return "<fuzzycsg.Tree " + std::to_string(t.dim) + "D, " + std::to_string(c.primitives) +
               " primitives, " + std::to_string(c.operators) + " operators, " +
               std::to_string(c.parameters) + " parameters>";
      });

  m.def("full_binary_tree", &full_binary_tree, py::arg("leaves") = 64, py::arg("dim") = 3,
        py::arg("family") = "quadric", py::arg("ops") = "unified", py::arg("op_init") = "uniform",
        py::arg("op_types") = "all", py::arg("init_range") = 0.5, py::arg("seed") = 0,
        py::arg("temperature") = 1000.0, py::arg("omega") = 10.0, py::arg("sharpness") = py::none(),
        "Liu et al.'s full binary tree of `leaves` primitives (core/builders.hpp)");
  m.def("eval", &eval, py::arg("tree"), py::arg("points"), py::arg("params") = py::none(),
        py::arg("threads") = 0, "Occupancy (float32, N) at N x dim points");
  m.def("grad", &grad, py::arg("tree"), py::arg("points"), py::arg("weights") = py::none(),
        py::arg("params") = py::none(), py::arg("loss") = "sum", py::arg("targets") = py::none(),
        py::arg("points_grad") = false, py::arg("threads") = 0,
        "(loss, d loss / d params[, d loss / d points]) for loss 'sum' (sum_i w_i o_i) or 'mse'");
}

}  // namespace fuzzycsg::python
