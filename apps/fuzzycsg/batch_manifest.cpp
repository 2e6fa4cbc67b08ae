#include "batch_manifest.hpp"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "batch_summary.hpp"
#include "commands.hpp"
#include "fuzzycsg/core/error.hpp"
#include "support.hpp"

namespace fuzzycsg::app {

namespace {

using nlohmann::json;

bool valid_id(const std::string& id) {
  if (id.empty() || id.size() > 200 || id.front() == '.') return false;
  for (const char* taken : kSummaryFiles) {
    if (id == taken) return false;
  }
  return std::all_of(id.begin(), id.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '.' || c == '_' || c == '-';
  });
}

// The job's options parsed by its verb's own command line (nothing runs): an unknown flag, a
// value of the wrong kind or out of a flag's range is CLI11's message.
void check_options(const BatchJob& job, const std::string& where) {
  CLI::App app{"fuzzycsg", "fuzzycsg"};
  app.require_subcommand(1);
  // The verb's settings live as long as the Verb its registration returns: kept while parsing.
  const Verb verb = job.verb == "convert" ? register_convert(app)
                    : job.verb == "fit"   ? register_fit(app)
                    : job.verb == "trace" ? register_trace(app)
                                          : register_refine(app);
  std::vector<std::string> args = batch_job_arguments(job, "batch-check-output");
  std::reverse(args.begin(), args.end());  // CLI11 takes them last first
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    throw InputError(fmt::format("{}: options: {}", where, e.what()));
  }
}

BatchJob read_job(const json& j, int line, const std::filesystem::path& base,
                  const std::string& where) {
  if (!j.is_object()) throw InputError(where + ": a JSON object expected");
  for (const auto& [key, value] : j.items()) {
    if (key != "id" && key != "verb" && key != "input" && key != "options") {
      throw InputError(fmt::format("{}: {}: unknown field (id, verb, input, options)", where, key));
    }
  }
  BatchJob job;
  job.line = line;
  for (const char* field : {"id", "verb", "input"}) {
    if (!j.contains(field) || !j[field].is_string()) {
      throw InputError(fmt::format("{}: {}: a string expected", where, field));
    }
  }
  job.id = j["id"].get<std::string>();
  if (!valid_id(job.id)) {
    throw InputError(
        fmt::format("{}: id: '{}' must be letters, digits, '.', '_' or '-' (not first a '.', not a "
                    "summary file's name)",
                    where, job.id));
  }
  job.verb = j["verb"].get<std::string>();
  if (std::none_of(std::begin(kBatchVerbs), std::end(kBatchVerbs),
                   [&](const char* v) { return job.verb == v; })) {
    throw InputError(
        fmt::format("{}: verb: unknown verb '{}' (convert, fit, trace, refine)", where, job.verb));
  }
  job.input = std::filesystem::absolute(base / j["input"].get<std::string>()).lexically_normal();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(job.input, ec)) {
    throw InputError(fmt::format("{}: input: {}: no such file", where, job.input.string()));
  }
  if (j.contains("options")) {
    const json& o = j["options"];
    if (!o.is_array()) throw InputError(where + ": options: an array of strings expected");
    for (const json& v : o) {
      if (!v.is_string()) throw InputError(where + ": options: an array of strings expected");
      job.options.push_back(v.get<std::string>());
      if (job.options.back() == "-o" || job.options.back() == "--output") {
        throw InputError(where + ": options: the output is the batch's (leave out -o)");
      }
    }
  }
  // Files named in the options are found beside the manifest, as the input is.
  for (std::size_t k = 0; k < job.options.size(); ++k) {
    std::string& o = job.options[k];
    const auto resolve = [&](const std::string& value) {
      return value.empty() ? value
                           : std::filesystem::absolute(base / value).lexically_normal().string();
    };
    if (o == "--target" && k + 1 < job.options.size()) {
      job.options[k + 1] = resolve(job.options[k + 1]);
      ++k;
    } else if (o.starts_with("--target=")) {
      o = "--target=" + resolve(o.substr(9));
    }
  }
  check_options(job, where);
  return job;
}

// One CSV record on one line (RFC 4180 quoting: "a ""b"", c" is one field). Written here rather
// than taken from a CSV library: a manifest's record is one line of four short fields.
std::vector<std::string> csv_fields(const std::string& text, const std::string& where) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c != '"') {
        fields.back() += c;
      } else if (i + 1 < text.size() && text[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else {
        quoted = false;
      }
    } else if (c == '"' && fields.back().empty()) {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  if (quoted) throw InputError(where + ": a quoted field is not closed");
  return fields;
}

// A CSV record as the JSON object of a JSON-lines manifest: options split at blanks.
json csv_job(const std::vector<std::string>& header, const std::vector<std::string>& fields,
             const std::string& where) {
  if (fields.size() != header.size()) {
    throw InputError(
        fmt::format("{}: {} fields, the header has {}", where, fields.size(), header.size()));
  }
  json j = json::object();
  for (std::size_t k = 0; k < header.size(); ++k) {
    if (header[k] != "options") {
      j[header[k]] = fields[k];
      continue;
    }
    json options = json::array();
    std::istringstream words(fields[k]);
    for (std::string w; words >> w;) options.push_back(w);
    j["options"] = options;
  }
  return j;
}

}  // namespace

std::vector<std::string> batch_job_arguments(const BatchJob& job,
                                             const std::filesystem::path& out) {
  std::vector<std::string> args{job.verb, job.input.string(), "-o", out.string()};
  args.insert(args.end(), job.options.begin(), job.options.end());
  return args;
}

std::vector<BatchJob> read_batch_manifest(const std::filesystem::path& manifest) {
  std::ifstream in(manifest);
  if (!in) throw InputError(fmt::format("{}: cannot read", manifest.string()));
  const std::filesystem::path base = manifest.parent_path();
  std::vector<BatchJob> jobs;
  std::set<std::string> ids;
  const bool csv = has_extension(manifest.string(), {".csv"});
  std::vector<std::string> header;  // CSV: the columns
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;  // blank lines, comments
    const std::string where = fmt::format("{}:{}", manifest.string(), line);
    json j;
    if (csv && header.empty()) {
      header = csv_fields(text, where);
      for (const std::string& column : header) {
        if (column != "id" && column != "verb" && column != "input" && column != "options") {
          throw InputError(
              fmt::format("{}: {}: unknown column (id, verb, input, options)", where, column));
        }
        if (std::count(header.begin(), header.end(), column) > 1) {
          throw InputError(fmt::format("{}: {}: a column named twice", where, column));
        }
      }
      continue;
    }
    if (csv) {
      j = csv_job(header, csv_fields(text, where), where);
    } else {
      try {
        j = json::parse(text);
      } catch (const json::parse_error& e) {
        throw InputError(fmt::format("{}: not JSON ({})", where, e.what()));
      }
    }
    BatchJob job = read_job(j, line, base, where);
    if (!ids.insert(job.id).second) {
      throw InputError(fmt::format("{}: id: '{}' is used by an earlier line", where, job.id));
    }
    jobs.push_back(std::move(job));
  }
  if (jobs.empty()) throw InputError(fmt::format("{}: no jobs", manifest.string()));
  return jobs;
}

}  // namespace fuzzycsg::app
