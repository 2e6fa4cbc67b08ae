#include "fuzzycsg/diagram/diagram.hpp"

#include <cgraph.h>
#include <gtest/gtest.h>
#include <stb_image.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "fuzzycsg/core/builders.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg {
namespace {

Tree example(const char* name) {
  return io::read_tree_file(std::filesystem::path(FUZZYCSG_SOURCE_DIR) / "examples" / name);
}

// The DOT text read back by Graphviz's own parser.
struct ParsedDot {
  struct Deleter {
    void operator()(Agraph_t* graph) const { agclose(graph); }
  };
  std::unique_ptr<Agraph_t, Deleter> g;
  explicit ParsedDot(const std::string& dot) : g(agmemread(dot.c_str())) {}
  std::string attr(const char* node, const char* name) const {
    Agnode_t* n = agnode(g.get(), const_cast<char*>(node), 0);
    if (n == nullptr) return "(no node)";
    const char* v = agget(n, const_cast<char*>(name));
    return v ? v : "";
  }
};

// Every tree node is one DOT node named by its path, every parent-child link one edge, from the
// parent, in child order.
void expect_same_structure(const Tree& tree, const std::string& dot) {
  const ParsedDot parsed(dot);
  ASSERT_NE(parsed.g, nullptr) << dot;
  EXPECT_EQ(agnnodes(parsed.g.get()), static_cast<int>(tree.nodes.size()));
  EXPECT_EQ(agnedges(parsed.g.get()), static_cast<int>(tree.nodes.size()) - 1);
  const std::vector<std::string> paths = node_paths(tree);
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    Agnode_t* n = agnode(parsed.g.get(), const_cast<char*>(paths[i].c_str()), 0);
    ASSERT_NE(n, nullptr) << paths[i];
    std::vector<std::string> heads;
    for (Agedge_t* e = agfstout(parsed.g.get(), n); e != nullptr; e = agnxtout(parsed.g.get(), e)) {
      heads.emplace_back(agnameof(aghead(e)));
    }
    std::vector<std::string> children;
    for (const int c : tree.nodes[i].children)
      children.push_back(paths[static_cast<std::size_t>(c)]);
    EXPECT_EQ(heads, children) << paths[i];
  }
}

int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(DiagramDot, ExamplesParseWithOneNodePerTreeNodeAndEdgesInChildOrder) {
  for (const char* name : {"box_with_hole.json", "cart_2d.json", "unified_logits.json",
                           "li_tian_blend.json", "logic_families.json", "extrude_bracket.json"}) {
    SCOPED_TRACE(name);
    const Tree tree = example(name);
    const std::string dot = diagram_dot(tree);
    expect_same_structure(tree, dot);
    EXPECT_NE(dot.find("ordering=out"), std::string::npos);
  }
}

TEST(DiagramDot, LabelsShowOperatorsLeavesAndTheSubtractedOperand) {
  const Tree tree = example("box_with_hole.json");
  const ParsedDot d(diagram_dot(tree));
  ASSERT_NE(d.g, nullptr);
  EXPECT_EQ(d.attr("root", "label"), "difference A \\\\ B\\nproduct");
  EXPECT_EQ(d.attr("root.children[0]", "label"), "box\\nsize [1.2, 0.8, 0.4]\\nsharpness 80");
  EXPECT_EQ(d.attr("root.children[1]", "shape"), "box");
  EXPECT_NE(d.attr("root.children[1]", "label").find("rotate [90, 0, 0]"), std::string::npos);
  Agnode_t* root = agnode(d.g.get(), const_cast<char*>("root"), 0);
  Agedge_t* a = agfstout(d.g.get(), root);
  Agedge_t* b = agnxtout(d.g.get(), a);
  EXPECT_EQ(std::string(agget(a, const_cast<char*>("headlabel"))), "A");
  EXPECT_EQ(std::string(agget(b, const_cast<char*>("headlabel"))), "B");
  EXPECT_EQ(std::string(agget(b, const_cast<char*>("style"))), "dashed");
  EXPECT_NE(std::string(agget(a, const_cast<char*>("style"))), "dashed");
  EXPECT_NE(std::string(agget(d.g.get(), const_cast<char*>("label"))).find("3D tree: 2 leaves"),
            std::string::npos);
}

// An extrude's label counts its profile's segments and shows the height after it.
TEST(DiagramDot, ExtrudeShowsItsSegmentsAndHeight) {
  const ParsedDot d(diagram_dot(example("extrude_bracket.json")));
  ASSERT_NE(d.g, nullptr);
  EXPECT_EQ(d.attr("root.children[0]", "label"),
            "\"slotted plate\"\\nextrude\\nprofile 4 segments\\nheight 0.2\\nsharpness 80");
}

TEST(DiagramDot, UnifiedOperatorsShowTheirTypeAndRoundedC) {
  // c = (0.1, 0.2, 0.1, 0.6): B \ A, so the first child (A) is the subtracted one.
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
      "root": {"op": "unified", "c": [0.1, 0.2, 0.1, 0.6], "children": [
        {"type": "circle", "radius": 0.5},
        {"op": "unified", "logits": [0.0, 0.15, 0.0, 0.0], "children": [
          {"type": "circle", "radius": 0.2}, {"type": "rectangle", "size": [0.3, 0.4]}]}]}})",
                                         "unified");
  const std::string dot = diagram_dot(tree);
  expect_same_structure(tree, dot);
  const ParsedDot d(dot);
  EXPECT_EQ(d.attr("root", "label"), "unified: B \\\\ A\\nc [0.10, 0.20, 0.10, 0.60]");
  // sin(10 * 0.15) * 1000 dominates: union, c rounded to [0, 1, 0, 0].
  EXPECT_EQ(d.attr("root.children[1]", "label"), "unified: union\\nc [0.00, 1.00, 0.00, 0.00]");
  Agnode_t* root = agnode(d.g.get(), const_cast<char*>("root"), 0);
  Agedge_t* a = agfstout(d.g.get(), root);
  EXPECT_EQ(std::string(agget(a, const_cast<char*>("style"))), "dashed");
  // A union's children are not ordered: no A/B labels.
  Agnode_t* u = agnode(d.g.get(), const_cast<char*>("root.children[1]"), 0);
  EXPECT_EQ(std::string(agget(agfstout(d.g.get(), u), const_cast<char*>("headlabel"))), "");
}

TEST(DiagramDot, SharedParametersByNameAndNamesQuotedAndEscaped) {
  const Tree tree = io::read_tree_string(R"({"format": "fuzzycsg-tree", "version": 1, "dim": 2,
      "parameters": {"wheel_r": 0.3},
      "root": {"op": "union", "logic": "yager", "p": 3, "name": "a \"quoted\\\" name", "children": [
        {"type": "circle", "radius": {"param": "wheel_r"}, "translate": [0.5, {"param": "wheel_r"}]},
        {"type": "circle", "radius": 0.2, "step": {"hn": 3, "range": 0.1}}]}})",
                                         "shared");
  const std::string dot = diagram_dot(tree);
  expect_same_structure(tree, dot);
  const ParsedDot d(dot);
  // agget gives the label as written, with DOT's escapes.
  EXPECT_EQ(d.attr("root", "label"), "\"a \"quoted\\\\\" name\"\\nunion\\nyager p 3");
  EXPECT_EQ(d.attr("root.children[0]", "label"),
            "circle\\nradius wheel_r = 0.3\\ntranslate [0.5, wheel_r]\\nsharpness 50");
  EXPECT_EQ(d.attr("root.children[1]", "label"), "circle\\nradius 0.2\\nstep H3, range 0.1");
}

TEST(DiagramDot, LargeTreesRunLeftToRightAndParse) {
  FullTreeOptions o;
  o.leaves = 1024;
  const Tree tree = make_full_binary_tree(o);
  const std::string dot = diagram_dot(tree);
  expect_same_structure(tree, dot);
  EXPECT_NE(dot.find("rankdir=LR"), std::string::npos);
  EXPECT_NE(diagram_dot(example("cart_2d.json")).find("rankdir=TB"), std::string::npos);
  DiagramOptions td;
  td.direction = DiagramDirection::kTopDown;
  EXPECT_NE(diagram_dot(tree, td).find("rankdir=TB"), std::string::npos);
}

TEST(DiagramRender, SvgHasOneNodeGroupPerTreeNode) {
  for (const char* name : {"box_with_hole.json", "cart_2d.json", "logic_families.json"}) {
    SCOPED_TRACE(name);
    const Tree tree = example(name);
    const std::string svg = render_dot(diagram_dot(tree), DiagramFormat::kSvg);
    ASSERT_EQ(svg.rfind("<?xml", 0), 0u) << svg.substr(0, 200);
    EXPECT_NE(svg.find("<svg"), std::string::npos);
    EXPECT_EQ(count_of(svg, "class=\"node\""), static_cast<int>(tree.nodes.size()));
    EXPECT_EQ(count_of(svg, "class=\"edge\""), static_cast<int>(tree.nodes.size()) - 1);
    // Each node's title is its path.
    EXPECT_NE(svg.find("<title>root.children[0]</title>"), std::string::npos);
  }
}

TEST(DiagramRender, PngDecodesWithAPlausibleSize) {
  ASSERT_TRUE(diagram_format_available(DiagramFormat::kPng));
  const Tree tree = example("cart_2d.json");
  const std::string png = render_dot(diagram_dot(tree), DiagramFormat::kPng);
  int w = 0, h = 0, channels = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()),
                                            static_cast<int>(png.size()), &w, &h, &channels, 3);
  ASSERT_NE(px, nullptr);
  // Several boxes across, a few ranks down, at 96 dots per inch.
  EXPECT_GT(w, 300);
  EXPECT_LT(w, 4000);
  EXPECT_GT(h, 150);
  EXPECT_LT(h, 2000);
  // Mostly white paper with dark ink somewhere.
  std::size_t white = 0, dark = 0;
  for (int i = 0; i < w * h; ++i) {
    const unsigned char* p = px + 3 * i;
    if (p[0] > 245 && p[1] > 245 && p[2] > 245) ++white;
    if (p[0] < 80 && p[1] < 80 && p[2] < 80) ++dark;
  }
  stbi_image_free(px);
  EXPECT_GT(white, static_cast<std::size_t>(w * h / 3));
  EXPECT_GT(dark, 100u);
}

TEST(DiagramRender, PngOfAHugeTreeIsScaledToTheLimits) {
  FullTreeOptions o;
  o.leaves = 256;
  const Tree tree = make_full_binary_tree(o);
  DiagramOptions d;
  d.max_png_side = 2000;
  d.max_png_pixels = 1'000'000;
  const std::string png = render_dot(diagram_dot(tree, d), DiagramFormat::kPng, d);
  int w = 0, h = 0, channels = 0;
  ASSERT_TRUE(stbi_info_from_memory(reinterpret_cast<const unsigned char*>(png.data()),
                                    static_cast<int>(png.size()), &w, &h, &channels));
  EXPECT_LE(std::max(w, h), 2002);
  EXPECT_LE(static_cast<long long>(w) * h, 1'010'000);
  EXPECT_GT(std::max(w, h), 1500);
}

TEST(DiagramRender, BadDotIsAnErrorNotACrash) {
  EXPECT_THROW(render_dot("digraph { a -> ; }", DiagramFormat::kSvg), Error);
  // The next call is not affected by the failed one.
  EXPECT_NE(render_dot("digraph { a -> b }", DiagramFormat::kSvg).find("class=\"node\""),
            std::string::npos);
}

TEST(DiagramWrite, ByExtensionAtomicallyAndErrorsNameThePath) {
  const Tree tree = example("box_with_hole.json");
  const auto dir =
      std::filesystem::temp_directory_path() /
      ("fuzzycsg_diagram_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::create_directories(dir);
  write_diagram(tree, dir / "t.dot");
  write_diagram(tree, dir / "t.SVG");
  write_diagram(tree, dir / "t.png");
  EXPECT_EQ(io::read_file(dir / "t.dot"), diagram_dot(tree));
  EXPECT_NE(io::read_file(dir / "t.SVG").find("<svg"), std::string::npos);
  EXPECT_EQ(io::read_file(dir / "t.png").substr(1, 3), "PNG");
  try {
    write_diagram(tree, dir / "t.pdf");
    ADD_FAILURE() << "no error for .pdf";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.pdf: unknown diagram format '.pdf'"), std::string::npos)
        << e.what();
  }
  try {
    write_diagram(tree, dir / "no" / "such" / "t.svg");
    ADD_FAILURE() << "no error for a missing directory";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write"), std::string::npos) << e.what();
  }
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    left.push_back(entry.path().filename().string());
  }
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"t.SVG", "t.dot", "t.png"}));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fuzzycsg
