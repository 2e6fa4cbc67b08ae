// Point files.
#include "fuzzycsg/io/points.hpp"

#include <charconv>
#include <cmath>
#include <limits>

#include "fuzzycsg/core/error.hpp"
#include "io_detail.hpp"

namespace fuzzycsg::io {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

class PointParser {
 public:
  PointParser(std::string_view text, int dim, std::string_view source)
      : text_(text), dim_(dim), source_(source) {}

  std::vector<float> run() {
    std::size_t line_start = 0;
    int line = 0;
    while (line_start <= text_.size()) {
      ++line;
      std::size_t line_end = text_.find('\n', line_start);
      if (line_end == std::string_view::npos) line_end = text_.size();
      parse_line(text_.substr(line_start, line_end - line_start), line);
      line_start = line_end + 1;
    }
    if (points_.empty()) fail("no points");
    return std::move(points_);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(std::string(source_) + ": " + problem);
  }
  [[noreturn]] void fail_at(int line, std::size_t column, const std::string& problem) const {
    fail("line " + std::to_string(line) + ", column " + std::to_string(column) + ": " + problem);
  }

  void parse_line(std::string_view s, int line) {
    std::size_t i = 0;
    while (i < s.size() && is_space(s[i])) ++i;
    if (i == s.size() || s[i] == '#') return;  // blank line or comment

    int count = 0;
    bool need_number = true;  // after a comma a number must follow
    while (i < s.size()) {
      // One number.
      const std::size_t start = i;
      while (i < s.size() && !is_space(s[i]) && s[i] != ',') ++i;
      if (i == start) fail_at(line, start + 1, "expected a number (got \",\")");
      add_number(s.substr(start, i - start), line, start + 1, count);
      need_number = false;
      // A separator: whitespace with at most one comma.
      while (i < s.size() && is_space(s[i])) ++i;
      if (i < s.size() && s[i] == ',') {
        need_number = true;
        ++i;
        while (i < s.size() && is_space(s[i])) ++i;
      }
    }
    if (need_number) fail_at(line, s.size() + 1, "expected a number (got the end of the line)");
    if (count != dim_) {
      fail("line " + std::to_string(line) + ": expected " + std::to_string(dim_) +
           " coordinates (got " + std::to_string(count) + ")");
    }
  }

  void add_number(std::string_view token, int line, std::size_t column, int& count) {
    std::string_view digits = token;
    // from_chars takes no leading '+'; accept one before a digit or a point.
    if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-' && digits[1] != '+') {
      digits.remove_prefix(1);
    }
    double v = 0.0;
    const auto result = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (result.ec == std::errc::result_out_of_range) {
      fail_at(line, column, "number out of range (got " + detail::quote(token) + ")");
    }
    if (result.ec != std::errc() || result.ptr != digits.data() + digits.size()) {
      fail_at(line, column, "expected a number (got " + detail::quote(token) + ")");
    }
    if (!std::isfinite(v)) {
      fail_at(line, column, "must be finite (got " + detail::quote(token) + ")");
    }
    if (std::abs(v) > static_cast<double>(std::numeric_limits<float>::max())) {
      fail_at(line, column, "number out of range (got " + detail::quote(token) + ")");
    }
    ++count;
    if (count <= dim_) points_.push_back(static_cast<float>(v));
  }

  std::string_view text_;
  int dim_;
  std::string_view source_;
  std::vector<float> points_;
};

}  // namespace

std::vector<float> read_points_string(std::string_view text, int dim, std::string_view source) {
  if (dim < 1) {
    throw InputError(std::string(source) + ": points must have at least 1 coordinate (got " +
                     std::to_string(dim) + ")");
  }
  return PointParser(text, dim, source).run();
}

std::vector<float> read_points_file(const std::filesystem::path& path, int dim) {
  const std::string text = detail::read_text_file(path);
  return read_points_string(text, dim, detail::display_name(path));
}

}  // namespace fuzzycsg::io
