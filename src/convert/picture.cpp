// convert on a picture: the 2D form of the job, by the bitmap tracer of Gibson et al. (trace:
// a search over crisp trees of circles and rotated rectangles) and its refinement by gradient
// descent on the tree's fuzzy relaxation; measured against the picture as fit measures it.

#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>

#include "convert/picture.hpp"
#include "convert/tidy.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/transform.hpp"
#include "fuzzycsg/target/target.hpp"
#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/convert.hpp"
#include "fuzzycsg/trace/evaluate.hpp"
#include "fuzzycsg/trace/refine.hpp"
#include "fuzzycsg/trace/search.hpp"

namespace fuzzycsg::convert {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

int leaves_of(const Tree& tree) {
  int n = 0;
  for (const Node& node : tree.nodes) n += node.kind == NodeKind::kPrimitive ? 1 : 0;
  return n;
}

// Pixels of the tree's bitmap that differ from the picture's.
long long mismatch(const trace::CsgTree& tree, const trace::Bitmap& picture) {
  const trace::TreeEvaluator e(tree, picture.width(), picture.height());
  return trace::score(e.result(), picture, tree.primitive_count()).mismatch();
}

// The numbers of a traced primitive that are rounded, with whether each must stay > 0.
std::vector<std::pair<double*, bool>> numbers_of(trace::Primitive& p) {
  if (p.shape == trace::Shape::kCircle) return {{&p.x, false}, {&p.y, false}, {&p.r, true}};
  return {{&p.x, false}, {&p.y, false}, {&p.w, true}, {&p.h, true}, {&p.theta, false}};
}

// As tidy_solids does in 3D: a rectangle's angle within `snap_deg` of a quarter turn snapped to
// it (brought into [0, 90) with its sides swapped where that is the same rectangle), then each
// number rounded to the coarsest of 1, 0.5 and 0.1 (pixels or degrees) that keeps each change
// within `step` wrong pixels and all of them within `total`, or else to 0.01.
trace::CsgTree tidy_picture_tree(trace::CsgTree tree, const trace::Bitmap& picture,
                                 const TidyOptions& options, int& snapped, int& rounded) {
  const long long inside = static_cast<long long>(picture.count());
  const long long step = static_cast<long long>(options.step_tolerance * inside);
  const long long total = static_cast<long long>(options.total_tolerance * inside);
  const long long before = mismatch(tree, picture);
  long long current = before;
  const auto keep = [&](int leaf, const trace::Primitive& candidate) {
    const trace::Primitive old = tree.primitive(leaf);
    tree.primitive(leaf) = candidate;
    const long long e = mismatch(tree, picture);
    if (e <= current + step && e <= before + total) {
      current = e;
      return true;
    }
    tree.primitive(leaf) = old;
    return false;
  };
  for (const int leaf : tree.leaves()) {
    trace::Primitive p = tree.primitive(leaf);
    if (p.shape != trace::Shape::kRectangle) continue;
    const double quarters = std::round(p.theta / 90.0);
    if (std::abs(p.theta - 90.0 * quarters) > options.snap_angle_deg) continue;
    // An odd number of quarter turns is the rectangle with its sides swapped.
    if (std::abs(std::fmod(quarters, 2.0)) == 1.0) std::swap(p.w, p.h);
    p.theta = 0.0;
    if (!(p == tree.primitive(leaf))) snapped += keep(leaf, p) ? 1 : 0;
  }
  for (const int leaf : tree.leaves()) {
    const std::size_t count = numbers_of(tree.primitive(leaf)).size();
    for (std::size_t k = 0; k < count; ++k) {
      bool done = false;
      for (const double quantum : {1.0, 0.5, 0.1}) {
        trace::Primitive candidate = tree.primitive(leaf);
        const auto [value, positive] = numbers_of(candidate)[k];
        const double r = std::round(*value / quantum) * quantum;
        if (positive && r <= 0) continue;
        if (r == *value) {
          done = true;
          break;
        }
        *value = r;
        if (keep(leaf, candidate)) {
          ++rounded;
          done = true;
          break;
        }
      }
      if (done) continue;
      const auto [value, positive] = numbers_of(tree.primitive(leaf))[k];
      const double r = std::round(*value / 0.01) * 0.01;
      if (!positive || r > 0) *value = r;
    }
  }
  return tree;
}

}  // namespace

bool is_picture(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".pbm" || ext == ".pgm";
}

ConvertResult convert_picture(const std::string& path, const ConvertOptions& options,
                              const ConvertHooks& hooks) {
  const Clock::time_point start = Clock::now();
  ConvertResult result;
  Clock::time_point stage = start;
  const auto begin = [&](const char* name) {
    stage = Clock::now();
    if (hooks.progress) {
      ConvertProgress p;
      p.stage = name;
      hooks.progress(p);
    }
  };
  const auto end = [&](const char* name) { result.stages.push_back({name, seconds_since(stage)}); };

  begin("load");
  const trace::Bitmap bitmap = trace::read_bitmap(path);
  trace::check_traceable(bitmap, path);
  TargetOptions target_options;
  target_options.image_resolution = 0;  // the picture's own pixels, as the tracer sees them
  target_options.threads = options.threads;
  const std::unique_ptr<Target> target = load_target(path, target_options);
  result.target = target->describe();
  // Pixel units (y up, the tree files of trace) to the picture's normalised square: its
  // longer side spans [-1, 1].
  const int w = bitmap.width(), h = bitmap.height();
  const double s = 2.0 / std::max(w, h);
  result.normalisation = Similarity{{-0.5 * w * s, -0.5 * h * s, 0.0}, s};
  end("load");

  begin("search");
  trace::SearchOptions search;
  search.seed = options.seed;
  search.threads = options.threads;
  // Seconds left of a share of the time limit; 0 (none, for the tracer) when there is no limit.
  const bool limited = std::isfinite(options.time_limit);
  const auto left = [&](double share) {
    return limited ? share * options.time_limit - seconds_since(start) : 0.0;
  };
  search.time_limit = limited ? 0.6 * options.time_limit : 0.0;
  trace::SearchResult found = trace::search(bitmap, search);
  // --max-primitives: primitives made dearer until the tree has no more than asked.
  for (int attempt = 0; options.max_primitives > 0 && attempt < 6 &&
                        found.best.primitive_count() > options.max_primitives;
       ++attempt) {
    search.local.k *= 2;
    search.time_limit = left(0.6);
    if (limited && search.time_limit <= 0) break;
    found = trace::search(bitmap, search);
  }
  result.time_limit_reached = found.statistics.stopped_by == std::string("time-limit");
  end("search");

  trace::CsgTree best = found.best;
  if (options.refine_steps > 0) {
    begin("refine");
    trace::RefineOptions refine;
    refine.iterations = options.refine_steps;
    refine.k = search.local.k;
    refine.seed = options.seed;
    refine.threads = options.threads;
    refine.time_limit = limited ? std::max(1.0, left(0.8)) : 0.0;
    const trace::RefineResult refined = trace::refine(best, bitmap, refine);
    if (refined.improved) {
      best = refined.tree;
      result.refined = true;
    }
    end("refine");
  }

  begin("tidy");
  if (options.tidy) {
    best = tidy_picture_tree(std::move(best), bitmap, TidyOptions{}, result.axes_snapped,
                             result.values_rounded);
  }
  end("tidy");

  begin("measure");
  result.tree = trace::to_tree(best, w, h);
  const Tree normalised = transformed(result.tree, result.normalisation);
  result.metrics = measure(normalised, normalised.params.values(), *target, options.metrics);
  if (result.metrics.chamfer) result.chamfer = *result.metrics.chamfer / s;
  if (result.metrics.hausdorff) result.hausdorff = *result.metrics.hausdorff / s;
  end("measure");

  result.reached = result.metrics.iou >= options.warn_iou;
  result.primitives = leaves_of(result.tree);
  result.seconds = seconds_since(start);
  result.time_limit_reached = result.time_limit_reached || result.seconds > options.time_limit;
  return result;
}

}  // namespace fuzzycsg::convert
