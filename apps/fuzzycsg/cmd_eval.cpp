// fuzzycsg eval TREE --points PTS [-o OUT] [--grad GRAD.json] [--threads N]
//
// Occupancy of the tree at every point (one per line), and optionally the gradient of the sum
// of the occupancies with respect to every named parameter, as JSON.

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fuzzycsg/eval/evaluator.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/points.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::app {

namespace {

struct EvalArgs {
  std::string tree;
  std::string points;
  std::string out;
  std::string grad;
  int threads = 0;
};

void write_or_print(const std::string& path, const std::string& text) {
  if (path.empty() || path == "-") {
    fmt::print("{}", text);
  } else {
    io::write_text_file_atomic(path, text);
  }
}

int run_eval(const EvalArgs& a) {
  const Tree tree = io::read_tree_file(a.tree);
  const std::vector<float> points = io::read_points_file(a.points, tree.dim);
  const Evaluator evaluator(tree, EvalOptions{a.threads});
  const std::vector<double> params = tree.params.values();
  const std::size_t n = points.size() / static_cast<std::size_t>(tree.dim);
  std::vector<float> occupancy(n);

  std::string grad_text;
  if (!a.grad.empty()) {
    std::vector<double> grad(params.size());
    const double sum = evaluator.backward(params, points, Loss{}, grad, occupancy);
    nlohmann::ordered_json j;
    j["points"] = n;
    j["sum"] = sum;
    nlohmann::ordered_json g = nlohmann::ordered_json::object();
    for (std::size_t i = 0; i < params.size(); ++i) {
      const Parameter& p = tree.params.at(i);
      g[p.name] = p.fixed ? 0.0 : grad[i];
    }
    j["gradient"] = std::move(g);
    nlohmann::ordered_json fixed = nlohmann::ordered_json::array();
    for (const Parameter& p : tree.params.entries()) {
      if (p.fixed) fixed.push_back(p.name);
    }
    j["fixed"] = std::move(fixed);
    grad_text = j.dump(2) + "\n";
  } else {
    evaluator.forward(params, points, occupancy);
  }

  std::string text;
  text.reserve(n * 12);
  for (float o : occupancy) fmt::format_to(std::back_inserter(text), "{}\n", o);
  // Both outputs are complete before either is written.
  if (!a.grad.empty() && a.grad != "-") write_or_print(a.grad, grad_text);
  write_or_print(a.out, text);
  if (a.grad == "-") write_or_print(a.grad, grad_text);
  return 0;
}

}  // namespace

Verb register_eval(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd = app.add_subcommand("eval", "Occupancy (and gradient) of a tree at points");
  cmd->add_option("tree", args->tree, "Tree file (JSON, fuzzycsg-tree v1)")->required();
  cmd->add_option("--points", args->points,
                  "Point file: one point per line, whitespace or comma separated")
      ->required();
  cmd->add_option("-o,--output", args->out, "Occupancies, one per line (default: stdout)");
  cmd->add_option("--grad", args->grad,
                  "Write the gradient of the sum of occupancies wrt every parameter as JSON "
                  "('-' for stdout)");
  add_threads_option(cmd, args->threads);
  return {cmd, [args] { return run_eval(*args); }};
}

}  // namespace fuzzycsg::app
