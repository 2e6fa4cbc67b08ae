// fuzzycsg diagram TREE -o OUT.dot|.svg|.png [--direction auto|TB|LR]
//
// The tree itself as a diagram: Graphviz DOT text, or a picture laid out and drawn by Graphviz
// (SVG, PNG). Prints the node count and how long the layout took. A program built without the
// diagram module (FUZZYCSG_WITH_DIAGRAM=OFF: no Graphviz) has the verb, which says so.

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#if FUZZYCSG_HAVE_DIAGRAM
#include "fuzzycsg/diagram/diagram.hpp"
#endif
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::app {

namespace {

struct DiagramArgs {
  std::string tree, out;
  std::string direction = "auto";
  bool quiet = false;
};

int run_diagram(const DiagramArgs& a) {
#if !FUZZYCSG_HAVE_DIAGRAM
  throw InputError(fmt::format(
      "diagram: this fuzzycsg was built without Graphviz (FUZZYCSG_WITH_DIAGRAM=OFF), so it "
      "cannot write {}",
      a.out));
#else
  const Tree tree = io::read_tree_file(a.tree);
  DiagramOptions options;
  options.title = std::filesystem::path(a.tree).filename().string();
  options.direction = a.direction == "TB"   ? DiagramDirection::kTopDown
                      : a.direction == "LR" ? DiagramDirection::kLeftRight
                                            : DiagramDirection::kAuto;
  const auto start = std::chrono::steady_clock::now();
  write_diagram(tree, a.out, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!a.quiet) {
    fmt::print("diagram: {} nodes to {} in {:.2f} s\n", tree.nodes.size(), a.out, seconds);
  }
  return 0;
#endif
}

}  // namespace

Verb register_diagram(CLI::App& app) {
  auto a = std::make_shared<DiagramArgs>();
  CLI::App* cmd = app.add_subcommand(
      "diagram", "The tree as a diagram: Graphviz DOT, or SVG / PNG drawn by Graphviz");
  cmd->add_option("tree", a->tree, "Tree file")->required();
  cmd->add_option("-o,--output", a->out, "Output: .dot (or .gv), .svg or .png")->required();
  cmd->add_option("--direction", a->direction,
                  "Root at the top (TB) or the left (LR); auto: LR beyond 64 leaves")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "TB", "LR"}));
  cmd->add_flag("-q,--quiet", a->quiet, "No summary line");
  return {cmd, [a] { return run_diagram(*a); }};
}

}  // namespace fuzzycsg::app
