// DOT text laid out and drawn through Graphviz's library (libgvc): the dot layout, the core
// plugin's SVG, the cairo plugin's PNG. Graphviz keeps global state (its parser, its error
// handler), so every call holds one lock.

#include <fmt/format.h>
#include <gvc.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diagram/diagram.hpp"
#include "fuzzycsg/io/files.hpp"

namespace fuzzycsg {

namespace {

std::mutex& graphviz_mutex() {
  static std::mutex m;
  return m;
}

// What Graphviz reports while the lock is held (it hands over a message in pieces).
std::string& graphviz_messages() {
  static std::string s;
  return s;
}

int collect_message(char* piece) {
  graphviz_messages() += piece;
  return 0;
}

// The first reported line, without Graphviz's "Error: " prefix.
std::string first_message() {
  std::string s = graphviz_messages();
  if (const auto eol = s.find('\n'); eol != std::string::npos) s.resize(eol);
  if (s.rfind("Error: ", 0) == 0) s.erase(0, 7);
  return s.empty() ? std::string("no message") : s;
}

// One Graphviz context for the process, never freed: its text layout plugin (pango) keeps a
// pointer into the context's font table across contexts, so freeing one and creating another
// reads freed memory (found under AddressSanitizer, Graphviz 2.42).
GVC_t* graphviz_context() {
  static GVC_t* const gvc = gvContext();
  if (gvc == nullptr) throw Error("Graphviz: cannot create a context");
  return gvc;
}

// Holds the lock and routes Graphviz's errors (not its warnings) to graphviz_messages() for
// its lifetime.
class GraphvizLock {
 public:
  GraphvizLock() : lock_(graphviz_mutex()) {
    graphviz_messages().clear();
    previous_handler_ = agseterrf(&collect_message);
    previous_level_ = agseterr(AGERR);
  }
  ~GraphvizLock() {
    agseterr(previous_level_);
    agseterrf(previous_handler_);
  }
  GraphvizLock(const GraphvizLock&) = delete;
  GraphvizLock& operator=(const GraphvizLock&) = delete;
  GVC_t* gvc() const { return graphviz_context(); }

 private:
  std::lock_guard<std::mutex> lock_;
  agusererrf previous_handler_ = nullptr;
  agerrlevel_t previous_level_ = AGWARN;
};

// A graph read from DOT text, freed (its layout too) when it goes.
class Graph {
 public:
  Graph(GVC_t* gvc, std::string_view dot) : gvc_(gvc) {
    const std::string text(dot);  // agmemread reads a NUL-terminated string
    g_ = agmemread(text.c_str());
    if (g_ == nullptr) throw Error("Graphviz cannot read the diagram: " + first_message());
  }
  ~Graph() {
    if (laid_out_) gvFreeLayout(gvc_, g_);
    agclose(g_);
  }
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;
  Agraph_t* get() const { return g_; }

  void layout() {
    if (gvLayout(gvc_, g_, "dot") != 0) throw Error("Graphviz layout failed: " + first_message());
    laid_out_ = true;
  }

 private:
  GVC_t* gvc_;
  Agraph_t* g_ = nullptr;
  bool laid_out_ = false;
};

const char* graphviz_format(DiagramFormat format) {
  return format == DiagramFormat::kPng ? "png" : "svg";
}

// Keeps a PNG within the pixel limits: the layout's bounding box (points, plus the default
// 4-point pad) at the cairo renderer's 96 dots per inch, scaled down by the drawing size that
// Graphviz reads when it renders (GD_drawing(g)->size, the "size" attribute in points; the
// attribute itself is read only by the layout, which is done).
void limit_png_size(Agraph_t* g, const DiagramOptions& options) {
  const char* attr = agget(g, const_cast<char*>("bb"));  // "llx lly urx ury" or with commas
  if (attr == nullptr) return;
  std::string bb(attr);
  std::replace(bb.begin(), bb.end(), ',', ' ');
  double llx = 0, lly = 0, urx = 0, ury = 0;
  if (std::sscanf(bb.c_str(), "%lf %lf %lf %lf", &llx, &lly, &urx, &ury) != 4) return;
  const double pad = 8.0;
  const double w_pt = urx - llx + pad, h_pt = ury - lly + pad;
  const double w_px = w_pt * 96.0 / 72.0, h_px = h_pt * 96.0 / 72.0;
  double scale = std::min(1.0, options.max_png_side / std::max(w_px, h_px));
  scale = std::min(scale, std::sqrt(static_cast<double>(options.max_png_pixels) / (w_px * h_px)));
  if (scale >= 1.0) return;
  GD_drawing(g)->size.x = w_pt * scale;
  GD_drawing(g)->size.y = h_pt * scale;
}

std::string render_locked(const GraphvizLock& lock, std::string_view dot, DiagramFormat format,
                          const DiagramOptions& options) {
  Graph graph(lock.gvc(), dot);
  graph.layout();
  if (format == DiagramFormat::kPng) limit_png_size(graph.get(), options);
  char* data = nullptr;
  unsigned int length = 0;
  if (gvRenderData(lock.gvc(), graph.get(), graphviz_format(format), &data, &length) != 0) {
    if (data != nullptr) gvFreeRenderData(data);
    throw InputError(
        fmt::format("the installed Graphviz cannot draw {} ({}); write .svg or .dot instead",
                    format == DiagramFormat::kPng ? "PNG" : "SVG", first_message()));
  }
  std::string out(data, length);
  gvFreeRenderData(data);
  return out;
}

}  // namespace

}  // namespace fuzzycsg

// Under AddressSanitizer: what Graphviz's text layout allocates in fontconfig and pango (their
// font caches, kept for the life of the process) is not reported as leaked, in every program
// that draws diagrams; anything else still is.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FUZZYCSG_LEAK_CHECKED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(FUZZYCSG_LEAK_CHECKED)
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libfontconfig.so\nleak:libpango-1.0.so\nleak:libpangoft2-1.0.so\n"
         "leak:libpangocairo-1.0.so\n";
}
// Without the table of suppressions used at exit: a program's stderr stays its own.
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }
#endif

namespace fuzzycsg {

std::optional<DiagramFormat> diagram_format_from_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".dot" || ext == ".gv") return DiagramFormat::kDot;
  if (ext == ".svg") return DiagramFormat::kSvg;
  if (ext == ".png") return DiagramFormat::kPng;
  return std::nullopt;
}

std::string render_dot(std::string_view dot, DiagramFormat format, const DiagramOptions& options) {
  if (format == DiagramFormat::kDot) return std::string(dot);
  if (options.max_png_side < 16 || options.max_png_pixels < 256) {
    throw InputError("render_dot: the PNG limits must be at least 16 pixels a side, 256 in all");
  }
  const GraphvizLock lock;
  return render_locked(lock, dot, format, options);
}

bool diagram_format_available(DiagramFormat format) {
  if (format == DiagramFormat::kDot) return true;
  try {
    render_dot("digraph { a }", format);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

void write_diagram(const Tree& tree, const std::filesystem::path& path,
                   const DiagramOptions& options) {
  const std::optional<DiagramFormat> format = diagram_format_from_path(path);
  if (!format) {
    throw InputError(fmt::format("{}: unknown diagram format '{}' (use .dot, .svg or .png)",
                                 path.string(), path.extension().string()));
  }
  std::string bytes;
  try {
    bytes = render_dot(diagram_dot(tree, options), *format, options);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", path.string(), e.what()));
  }
  io::write_text_file_atomic(path, bytes);
}

}  // namespace fuzzycsg
