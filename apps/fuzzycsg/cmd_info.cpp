// fuzzycsg info TREE [--json]: dimension, counts of primitives, operators and parameters.

#include <fmt/format.h>

#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.hpp"
#include "fuzzycsg/core/program.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::app {

namespace {

struct InfoArgs {
  std::string tree;
  bool json = false;
};

int run_info(const InfoArgs& a) {
  const Tree tree = io::read_tree_file(a.tree);
  const TreeCounts counts = count(tree);
  const auto& families = counts.families;
  const auto& operators = counts.operator_kinds;
  const int shared = counts.shared_parameters;
  const Program program = Program::compile(tree);

  if (a.json) {
    nlohmann::ordered_json j;
    j["file"] = a.tree;
    j["dim"] = tree.dim;
    j["primitives"] = counts.primitives;
    j["operators"] = counts.operators;
    j["depth"] = counts.depth;
    j["parameters"] = counts.parameters;
    j["free_parameters"] = counts.free_parameters;
    j["fixed_parameters"] = counts.parameters - counts.free_parameters;
    j["shared_parameters"] = shared;
    j["instructions"] = program.tape().size();
    j["families"] = families;
    j["operator_kinds"] = operators;
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  fmt::print("{}\n", a.tree);
  fmt::print("  dimension     {}\n", tree.dim);
  fmt::print("  primitives    {}\n", counts.primitives);
  for (const auto& [name, k] : families) fmt::print("    {:<22}{}\n", name, k);
  fmt::print("  operators     {}\n", counts.operators);
  for (const auto& [name, k] : operators) fmt::print("    {:<22}{}\n", name, k);
  fmt::print("  depth         {}\n", counts.depth);
  fmt::print("  parameters    {} ({} free, {} fixed, {} shared)\n", counts.parameters,
             counts.free_parameters, counts.parameters - counts.free_parameters, shared);
  fmt::print("  instructions  {}\n", program.tape().size());
  return 0;
}

}  // namespace

Verb register_info(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = app.add_subcommand("info", "Dimension and counts of a tree");
  cmd->add_option("tree", args->tree, "Tree file (JSON, fuzzycsg-tree v1)")->required();
  cmd->add_flag("--json", args->json, "Print JSON");
  return {cmd, [args] { return run_info(*args); }};
}

}  // namespace fuzzycsg::app
