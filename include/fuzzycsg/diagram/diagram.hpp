#pragma once
// The diagram module: the tree drawn as a graph by Graphviz. This header is all of its
// interface.
//
// The tree itself as a diagram: Graphviz DOT text written here, laid out and drawn (SVG, PNG)
// by Graphviz's library (libgvc, the dot layout).
//
// One DOT node per tree node, its ID the node path ("root.children[1]", a tooltip in SVG).
// Operators are ellipses labelled with the operator and its logic family (with the family's
// parameters), the complement of a difference or complement node when it is not the standard
// one, and for unified operators the type they stand for (the argmax of c: intersection,
// union, A \ B, B \ A) and c rounded to two decimals; leaves are boxes with the family, the
// scalar fields and short vectors (longer ones by their length), the placement and the step.
// A field that refers to a shared parameter shows the parameter's name. Node names ("name" in
// the file) come first, in quotes. Children are drawn left to right in file order
// (ordering=out); the two edges of a difference (and of a unified operator that stands for
// one) are labelled A and B, the subtracted operand's edge dashed. The graph label gives the
// dimension and the counts.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg {

enum class DiagramFormat { kDot, kSvg, kPng };

// By the path's extension (.dot or .gv, .svg, .png; any case); none for another one.
std::optional<DiagramFormat> diagram_format_from_path(const std::filesystem::path& path);

enum class DiagramDirection {
  kAuto,       // top to bottom up to kDiagramAutoLeftRightLeaves leaves, left to right beyond
  kTopDown,    // the root at the top, leaves in a row at the bottom
  kLeftRight,  // the root at the left, leaves in a column at the right
};
inline constexpr int kDiagramAutoLeftRightLeaves = 64;

struct DiagramOptions {
  DiagramDirection direction = DiagramDirection::kAuto;
  std::string title;  // a first line of the graph label (the file name, say); empty: none
  // PNG only: the picture is scaled down (never up) so that its longer side has at most this
  // many pixels and it has at most max_png_pixels pixels (at 96 dots per inch otherwise).
  int max_png_side = 16384;
  long long max_png_pixels = 50'000'000;
};

// The DOT text of the tree (nothing laid out).
std::string diagram_dot(const Tree& tree, const DiagramOptions& options = {});

// DOT text laid out with dot and drawn as SVG or PNG (bytes). Throws Error when Graphviz fails
// on the text and InputError when the format is not available in the installed Graphviz (PNG
// needs its cairo plugin, Debian's libgvc6 ships it); kDot returns the text unchanged.
std::string render_dot(std::string_view dot, DiagramFormat format,
                       const DiagramOptions& options = {});

// Can the installed Graphviz draw this format? (kDot: always.)
bool diagram_format_available(DiagramFormat format);

// The diagram in the format the path's extension names, written to a temporary file beside
// `path` and renamed. Throws InputError naming the path for an unknown extension or an
// unwritable path.
void write_diagram(const Tree& tree, const std::filesystem::path& path,
                   const DiagramOptions& options = {});

}  // namespace fuzzycsg
