// A tree built through the core API and evaluated by the installed fuzzycsg::eval: the union of
// a sphere at the origin and a smaller one moved along x. Prints the occupancy at a point
// inside the moved sphere and at one outside both; exits 1 when they are not what they must be.

#include <cmath>
#include <cstdio>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/eval/evaluator.hpp"

namespace {

fuzzycsg::ParamRef param(fuzzycsg::Tree& tree, std::string name, double value,
                         fuzzycsg::Range range = fuzzycsg::Range::any()) {
  return tree.params.add(fuzzycsg::Parameter{std::move(name), value, false, false, range});
}

int sphere(fuzzycsg::Tree& tree, const std::string& name, double radius, double x) {
  fuzzycsg::Node n;
  n.kind = fuzzycsg::NodeKind::kPrimitive;
  n.shape.type = fuzzycsg::PrimitiveType::kSphere;
  n.intrinsic.push_back(param(tree, name + ".radius", radius, fuzzycsg::Range::positive()));
  n.placement.translate = {param(tree, name + ".x", x), param(tree, name + ".y", 0.0),
                           param(tree, name + ".z", 0.0)};
  n.step.param = param(tree, name + ".sharpness", 50.0, fuzzycsg::Range::positive());
  tree.nodes.push_back(std::move(n));
  return static_cast<int>(tree.nodes.size()) - 1;
}

}  // namespace

int main() {
  fuzzycsg::Tree tree;
  tree.dim = 3;
  const int a = sphere(tree, "a", 0.5, 0.0);
  const int b = sphere(tree, "b", 0.3, 1.0);
  fuzzycsg::Node u;
  u.kind = fuzzycsg::NodeKind::kOperator;
  u.op = fuzzycsg::OpKind::kUnion;
  u.children = {a, b};
  tree.nodes.push_back(std::move(u));
  tree.root = static_cast<int>(tree.nodes.size()) - 1;
  fuzzycsg::validate(tree, "downstream");

  const fuzzycsg::Evaluator evaluator(tree, fuzzycsg::EvalOptions{1});
  const std::vector<double> params = tree.params.values();
  // Inside b (0.1 from its centre), and outside both (0.3 beyond a's surface, farther from b's).
  const std::vector<float> points{0.9f, 0.0f, 0.0f, 0.0f, 0.8f, 0.0f};
  std::vector<float> occupancy(2);
  evaluator.forward(params, points, occupancy);
  const double p[3] = {0.9, 0.0, 0.0};
  const double reference = fuzzycsg::reference_occupancy(tree, params, p);

  std::printf("fuzzycsg %s: %zu parameters, inside %.3f, outside %.3f\n", FUZZYCSG_FOUND_VERSION,
              evaluator.num_params(), occupancy[0], occupancy[1]);
  const bool right =
      occupancy[0] > 0.99f && occupancy[1] < 0.01f && std::abs(occupancy[0] - reference) < 1e-4;
  if (!right) std::printf("wrong occupancy (the reference inside: %.6f)\n", reference);
  return right ? 0 : 1;
}
