#include "batch_summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <vector>

#include "batch_run.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/core/tree.hpp"
#include "fuzzycsg/io/canvas.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/tree_json.hpp"

namespace fuzzycsg::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct JobRow {
  std::string id, verb, input, status = "pending", error, host;
  int line = 0;
  std::optional<double> seconds, iou, chamfer;
  std::optional<int> primitives;
  fs::path dir;  // where its files are (done or failed); empty when pending
};

std::optional<json> read_json(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return std::nullopt;
  json j = json::parse(io::read_file(file), nullptr, false);
  if (!j.is_object()) return std::nullopt;  // unreadable, or not a record
  return j;
}

std::optional<double> number_at(const json& j, const char* pointer) {
  const json::json_pointer p(pointer);
  if (!j.contains(p) || !j.at(p).is_number()) return std::nullopt;
  return j.at(p).get<double>();
}

// The measures of a done job from its verb's report and tree (docs/batch.md lists them).
void read_measures(JobRow& r) {
  if (const auto report = read_json(r.dir / "report.json")) {
    const json& j = *report;
    if (r.verb == "convert") {
      r.iou = number_at(j, "/metrics/iou");
      r.chamfer = number_at(j, "/metrics/chamfer");
    } else if (r.verb == "fit") {
      const char* which =
          j.contains(json::json_pointer("/metrics/pruned/iou")) ? "pruned" : "trained";
      r.iou = number_at(j, fmt::format("/metrics/{}/iou", which).c_str());
      r.chamfer = number_at(j, fmt::format("/metrics/{}/chamfer", which).c_str());
    } else if (r.verb == "trace") {
      // Pixels: the target's, those the result adds and those it misses.
      const auto set = number_at(j, "/bitmap/pixels_set"), excess = number_at(j, "/excess"),
                 missed = number_at(j, "/uncovered");
      if (set && excess && missed && *set + *excess > 0) {
        r.iou = (*set - *missed) / (*set + *excess);
      }
    }
  }
  for (const char* tree : {"tree_pruned.json", "tree.json"}) {
    std::error_code ec;
    if (!fs::is_regular_file(r.dir / tree, ec)) continue;
    try {
      r.primitives = count(io::read_tree_file(r.dir / tree)).primitives;
    } catch (const std::exception&) {
      r.error = fmt::format("{} unreadable", tree);
    }
    break;
  }
}

JobRow row_of(const json& job, const fs::path& out) {
  JobRow r;
  r.id = job.value("id", "");
  r.verb = job.value("verb", "");
  r.input = job.value("input", "");
  r.line = job.value("manifest_line", 0);
  for (const auto& [dir, status] :
       {std::pair{out / r.id, "done"}, std::pair{out / ".failed" / r.id, "failed"}}) {
    const auto record = read_json(dir / "job.json");
    if (!record) continue;
    r.status = status;
    r.dir = dir;
    r.seconds = number_at(*record, "/seconds");
    const json host = record->value("host", json());
    r.host = host.is_string() ? host.get<std::string>() : "";
    if (r.status == "done") {
      read_measures(r);
    } else {
      const int code = static_cast<int>(number_at(*record, "/exit_status").value_or(0));
      r.error = fmt::format("{}: {}", exit_status_text(code), tail_of(dir / "stderr.txt", 1));
    }
    break;
  }
  return r;
}

// The jobs as the batch recorded them, or (no record) the folders there are.
std::vector<JobRow> collect(const fs::path& out) {
  std::vector<JobRow> rows;
  const fs::path jobs_file = out / ".batch" / "jobs.json";
  if (const auto recorded = read_json(jobs_file)) {
    try {
      for (const json& job : recorded->at("jobs")) rows.push_back(row_of(job, out));
    } catch (const json::exception& e) {
      throw InputError(
          fmt::format("{}: jobs: not the batch's record ({})", jobs_file.string(), e.what()));
    }
    return rows;
  }
  for (const fs::path& parent : {out, out / ".failed"}) {
    std::error_code ec;
    if (!fs::is_directory(parent, ec)) continue;
    for (const auto& e : fs::directory_iterator(parent)) {
      const auto record = read_json(e.path() / "job.json");
      if (!record || e.path().filename().string().front() == '.') continue;
      if (parent != out && fs::exists(out / e.path().filename())) continue;
      try {
        rows.push_back(row_of(*record, out));
      } catch (const json::exception& x) {
        throw InputError(
            fmt::format("{}: not a job's record ({})", (e.path() / "job.json").string(), x.what()));
      }
    }
  }
  std::sort(rows.begin(), rows.end(), [](const JobRow& a, const JobRow& b) { return a.id < b.id; });
  return rows;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string number_text(const std::optional<double>& v) {
  return v ? fmt::format("{:.6g}", *v) : std::string();
}

std::string summary_csv(const std::vector<JobRow>& rows) {
  std::string text =
      "id,verb,input,manifest_line,status,seconds,iou,chamfer,primitives,host,error\n";
  for (const JobRow& r : rows) {
    text += fmt::format(
        "{},{},{},{},{},{},{},{},{},{},{}\n", csv_field(r.id), r.verb, csv_field(r.input), r.line,
        r.status, number_text(r.seconds), number_text(r.iou), number_text(r.chamfer),
        r.primitives ? std::to_string(*r.primitives) : "", csv_field(r.host), csv_field(r.error));
  }
  return text;
}

json optional_json(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Totals {
  int done = 0, failed = 0, pending = 0;
  std::vector<double> seconds, iou, chamfer, primitives;
  std::vector<const JobRow*> slowest, worst;  // five each
};

Totals totals_of(const std::vector<JobRow>& rows) {
  Totals t;
  for (const JobRow& r : rows) {
    (r.status == "done" ? t.done : r.status == "failed" ? t.failed : t.pending)++;
    if (r.status != "done") continue;
    if (r.seconds) t.seconds.push_back(*r.seconds);
    if (r.iou) t.iou.push_back(*r.iou);
    if (r.chamfer) t.chamfer.push_back(*r.chamfer);
    if (r.primitives) t.primitives.push_back(*r.primitives);
    if (r.seconds) t.slowest.push_back(&r);
    if (r.iou) t.worst.push_back(&r);
  }
  const auto keep = [](std::vector<const JobRow*>& v, auto less) {
    std::stable_sort(v.begin(), v.end(), less);
    if (v.size() > 5) v.resize(5);
  };
  keep(t.slowest, [](const JobRow* a, const JobRow* b) { return *a->seconds > *b->seconds; });
  keep(t.worst, [](const JobRow* a, const JobRow* b) { return *a->iou < *b->iou; });
  return t;
}

json stats_json(const std::vector<double>& v) {
  if (v.empty()) return nullptr;
  double sum = 0;
  for (const double x : v) sum += x;
  return {{"mean", sum / v.size()},
          {"median", median(v)},
          {"min", *std::min_element(v.begin(), v.end())},
          {"max", *std::max_element(v.begin(), v.end())},
          {"sum", sum}};
}

std::string summary_json(const fs::path& out, const std::vector<JobRow>& rows, const Totals& t) {
  nlohmann::ordered_json j;
  j["format"] = "fuzzycsg-batch-summary";
  j["version"] = 1;
  j["output"] = fs::absolute(out).lexically_normal().string();
  j["totals"] = {{"jobs", rows.size()},
                 {"done", t.done},
                 {"failed", t.failed},
                 {"pending", t.pending},
                 {"seconds", stats_json(t.seconds)},
                 {"iou", stats_json(t.iou)},
                 {"chamfer", stats_json(t.chamfer)},
                 {"primitives", stats_json(t.primitives)}};
  const auto ids = [](const std::vector<const JobRow*>& v) {
    json a = json::array();
    for (const JobRow* r : v) a.push_back(r->id);
    return a;
  };
  j["slowest"] = ids(t.slowest);
  j["worst"] = ids(t.worst);
  nlohmann::ordered_json jobs = nlohmann::ordered_json::array();
  for (const JobRow& r : rows) {
    nlohmann::ordered_json o;
    o["id"] = r.id;
    o["verb"] = r.verb;
    o["input"] = r.input;
    o["manifest_line"] = r.line;
    o["status"] = r.status;
    o["seconds"] = optional_json(r.seconds);
    o["iou"] = optional_json(r.iou);
    o["chamfer"] = optional_json(r.chamfer);
    o["primitives"] = r.primitives ? json(*r.primitives) : json(nullptr);
    o["host"] = r.host;
    o["error"] = r.error;
    jobs.push_back(o);
  }
  j["jobs"] = jobs;
  return j.dump(2) + "\n";
}

// The contact sheet: a cell per job, its target and result (the pictures its verb wrote) over
// a caption; at most kSheetCells cells, the failed and the lowest IoU first when there are more.
constexpr int kSheetCells = 48, kColumns = 4, kCellW = 320, kPictureH = 150, kCaptionH = 38,
              kGap = 8, kTitleH = 34;

// The pictures of a done job: target and result side by side where its verb wrote both.
std::vector<fs::path> pictures_of(const JobRow& r) {
  const std::vector<std::vector<const char*>> choices{{"target.png", "fit.png"},
                                                      {"target.png", "after.png"},
                                                      {"render.png"},
                                                      {"result.png"},
                                                      {"plot.png"}};
  for (const auto& names : choices) {
    std::vector<fs::path> files;
    for (const char* n : names) {
      std::error_code ec;
      if (fs::is_regular_file(r.dir / n, ec)) files.push_back(r.dir / n);
    }
    if (files.size() == names.size()) return files;
  }
  return {};
}

std::string fitted_text(std::string s, double size, double width) {
  if (Canvas::text_width(s, size) <= width) return s;
  while (!s.empty() && Canvas::text_width(s + "...", size) > width) s.pop_back();
  return s + "...";
}

void draw_cell(Canvas& c, const JobRow& r, double x, double y) {
  const Rgb frame{200, 200, 200}, ink{30, 30, 30}, grey{110, 110, 110};
  const Rgb back = r.status == "done"     ? Rgb{255, 255, 255}
                   : r.status == "failed" ? Rgb{253, 228, 228}
                                          : Rgb{238, 238, 238};
  c.fill(x, y, x + kCellW, y + kPictureH, back);
  const std::vector<fs::path> files = r.status == "done" ? pictures_of(r) : std::vector<fs::path>{};
  const double slot = files.empty() ? kCellW : static_cast<double>(kCellW) / files.size();
  for (std::size_t k = 0; k < files.size(); ++k) {
    try {
      const Pixels p = decode_picture(io::read_file(files[k]), files[k].string());
      const double scale = std::min((slot - 4) / p.width(), (kPictureH - 4.0) / p.height());
      const int w = std::max(1, static_cast<int>(p.width() * scale));
      const int h = std::max(1, static_cast<int>(p.height() * scale));
      c.image(std::round(x + k * slot + (slot - w) / 2), std::round(y + (kPictureH - h) / 2.0),
              resized(p, w, h));
    } catch (const std::exception&) {
      c.text(x + k * slot + slot / 2, y + kPictureH / 2.0, "unreadable picture", grey, 11,
             Align::kCentre, Anchor::kMiddle);
    }
  }
  if (files.empty()) {
    const std::string what = r.status == "done" ? "no picture" : r.status;
    c.text(x + kCellW / 2.0, y + kPictureH / 2.0 - (r.error.empty() ? 0 : 9), what, grey, 13,
           Align::kCentre, Anchor::kMiddle);
    if (!r.error.empty()) {
      c.text(x + kCellW / 2.0, y + kPictureH / 2.0 + 11, fitted_text(r.error, 10, kCellW - 12),
             grey, 10, Align::kCentre, Anchor::kMiddle);
    }
  }
  c.polyline(std::vector<Point>{{x + 0.5, y + 0.5},
                                {x + kCellW - 0.5, y + 0.5},
                                {x + kCellW - 0.5, y + kPictureH - 0.5},
                                {x + 0.5, y + kPictureH - 0.5}},
             frame, 1, true);
  c.text(x + 2, y + kPictureH + 4, fitted_text(r.id, 12, kCellW - 4), ink, 12);
  std::string line;
  if (r.iou) line += fmt::format("IoU {:.4f}   ", *r.iou);
  if (r.primitives)
    line += fmt::format("{} primitive{}   ", *r.primitives, *r.primitives == 1 ? "" : "s");
  if (r.seconds) line += fmt::format("{:.1f} s", *r.seconds);
  c.text(x + 2, y + kPictureH + 21, line, grey, 11);
}

std::string contact_sheet_png(const std::vector<JobRow>& rows, std::string title) {
  std::vector<const JobRow*> shown;
  for (const JobRow& r : rows) shown.push_back(&r);
  if (shown.size() > static_cast<std::size_t>(kSheetCells)) {
    const auto rank = [](const JobRow* r) {
      return r->status == "failed" ? -2.0 : r->status == "pending" ? -1.0 : r->iou.value_or(2.0);
    };
    std::stable_sort(shown.begin(), shown.end(),
                     [&](const JobRow* a, const JobRow* b) { return rank(a) < rank(b); });
    shown.resize(kSheetCells);
    title += fmt::format("; {} shown: failed and lowest IoU first", kSheetCells);
  }
  const int n = static_cast<int>(shown.size());
  const int columns = std::min(kColumns, n), lines = (n + columns - 1) / columns;
  Canvas c(kGap + columns * (kCellW + kGap), kTitleH + lines * (kPictureH + kCaptionH + kGap));
  c.text(kGap, 10, title, Rgb{30, 30, 30}, 14);
  for (int k = 0; k < n; ++k) {
    draw_cell(c, *shown[static_cast<std::size_t>(k)], kGap + (k % columns) * (kCellW + kGap),
              kTitleH + (k / columns) * (kPictureH + kCaptionH + kGap));
  }
  return c.png();
}

}  // namespace

int summarise_batch(const fs::path& out, bool quiet) {
  std::error_code ec;
  if (!fs::is_directory(out, ec)) {
    throw InputError(fmt::format("{}: not a batch's output directory", out.string()));
  }
  const std::vector<JobRow> rows = collect(out);
  if (rows.empty()) {
    throw InputError(fmt::format("{}: no jobs recorded (run `fuzzycsg batch MANIFEST -o {}` first)",
                                 out.string(), out.string()));
  }
  const Totals t = totals_of(rows);
  const std::string title =
      fmt::format("{}: {} jobs, {} done, {} failed, {} pending", out.filename().string(),
                  rows.size(), t.done, t.failed, t.pending);
  io::write_text_file_atomic(out / "summary.csv", summary_csv(rows));
  io::write_text_file_atomic(out / "summary.json", summary_json(out, rows, t));
  io::write_text_file_atomic(out / "summary.png", contact_sheet_png(rows, title));
  if (quiet) return 0;
  fmt::print("batch: {} jobs: {} done, {} failed, {} pending\n", rows.size(), t.done, t.failed,
             t.pending);
  if (!t.seconds.empty()) {
    fmt::print("  time: {:.1f} s in all, median {:.2f} s a job\n",
               stats_json(t.seconds)["sum"].get<double>(), median(t.seconds));
  }
  if (!t.iou.empty()) {
    fmt::print("  IoU: median {:.4f}, min {:.4f}\n", median(t.iou),
               *std::min_element(t.iou.begin(), t.iou.end()));
  }
  if (!t.chamfer.empty()) fmt::print("  Chamfer: median {:.5f}\n", median(t.chamfer));
  if (!t.primitives.empty()) fmt::print("  primitives: median {:.0f}\n", median(t.primitives));
  std::string slow, worst;
  for (const JobRow* r : t.slowest) slow += fmt::format(" {} ({:.1f} s)", r->id, *r->seconds);
  for (const JobRow* r : t.worst) worst += fmt::format(" {} ({:.4f})", r->id, *r->iou);
  if (!slow.empty()) fmt::print("  slowest:{}\n", slow);
  if (!worst.empty()) fmt::print("  worst IoU:{}\n", worst);
  for (const JobRow& r : rows) {
    if (r.status == "failed")
      fmt::print("  failed: {} (manifest line {}): {}\n", r.id, r.line, r.error);
  }
  fmt::print("batch: wrote {}/{{summary.csv, summary.json, summary.png}}\n", out.string());
  return 0;
}

}  // namespace fuzzycsg::app
