// The JSON document of a tree file (tree_detail.hpp): a SAX handler that builds it, rejects
// duplicate keys and bounds the nesting depth, with one-line messages.
#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "io_detail.hpp"
#include "tree_detail.hpp"

namespace fuzzycsg::io::detail {

std::string prefix(std::string_view source, const std::string& path) {
  std::string s(source);
  if (!s.empty()) s += ": ";
  if (!path.empty()) s += path + ": ";
  return s;
}

namespace {

using Json = nlohmann::json;

// A key as a path segment: plain when it looks like a name, quoted otherwise.
std::string key_segment(const std::string& key) {
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
  return plain ? key : "[" + quote(key) + "]";
}

// ---------------------------------------------------------------------------------------------
// JSON parsing: a SAX handler that builds the document, rejects duplicate keys and bounds the
// nesting depth.

class DocumentBuilder {
 public:
  DocumentBuilder(std::string_view text, std::string_view source) : text_(text), source_(source) {}

  Json document;

  // Each event returns true: parsing goes on, or an InputError ends it.
  bool null() { return value(Json(nullptr)); }
  bool boolean(bool v) { return value(Json(v)); }
  bool number_integer(Json::number_integer_t v) { return value(Json(v)); }
  bool number_unsigned(Json::number_unsigned_t v) { return value(Json(v)); }
  bool number_float(Json::number_float_t v, const Json::string_t&) { return value(Json(v)); }
  bool string(Json::string_t& v) { return value(Json(std::move(v))); }
  bool binary(Json::binary_t&) {
    throw InputError(std::string(source_) + ": binary values are not JSON");
  }
  bool start_object(std::size_t) {
    enter(add(Json::object()));
    return true;
  }
  bool key(Json::string_t& k) {
    Level& top = stack_.back();
    if (top.value->contains(k)) {
      throw InputError(prefix(source_, path()) + "duplicate key " + quote(k));
    }
    top.key = std::move(k);
    return true;
  }
  bool end_object() {
    stack_.pop_back();
    return true;
  }
  bool start_array(std::size_t) {
    enter(add(Json::array()));
    return true;
  }
  bool end_array() {
    stack_.pop_back();
    return true;
  }
  bool parse_error(std::size_t position, const std::string& last_token,
                   const nlohmann::detail::exception& e) {
    if (e.id == 406) {  // a number too large for a double
      throw InputError(prefix(source_, value_path()) + "must be finite (got " +
                       printable(last_token) + ")");
    }
    throw InputError(prefix(source_, {}) + location(position) +
                     ": syntax error: " + syntax_problem(e.what()));
  }

 private:
  struct Level {
    Json* value;
    std::string key;  // objects: the key of the member being read
  };

  bool value(Json&& v) {
    add(std::move(v));
    return true;
  }

  Json* add(Json&& v) {
    if (stack_.empty()) {
      document = std::move(v);
      return &document;
    }
    Level& top = stack_.back();
    if (top.value->is_array()) {
      top.value->push_back(std::move(v));
      return &top.value->back();
    }
    Json& slot = (*top.value)[top.key];
    slot = std::move(v);
    return &slot;
  }

  void enter(Json* v) {
    if (stack_.size() >= kMaxNesting) {
      throw InputError(prefix(source_, {}) + "nested deeper than " + std::to_string(kMaxNesting) +
                       " levels");
    }
    stack_.push_back(Level{v, {}});
  }

  // Path of the innermost open container.
  std::string path() const {
    std::string s;
    for (std::size_t i = 0; i + 1 < stack_.size(); ++i) append_segment(s, stack_[i], false);
    return s;
  }
  // Path of the value being read.
  std::string value_path() const {
    std::string s = path();
    if (!stack_.empty()) append_segment(s, stack_.back(), true);
    return s;
  }
  // Appends the segment of a level's current member ("key" or "[index]"); `next`: the member
  // has not been added yet.
  static void append_segment(std::string& s, const Level& level, bool next) {
    if (level.value->is_array()) {
      s += "[" + std::to_string(level.value->size() - (next ? 0 : 1)) + "]";
    } else {
      if (!s.empty()) s += '.';
      s += key_segment(level.key);
    }
  }

  // "line L, column C" of the byte nlohmann stopped at (`position` bytes read).
  std::string location(std::size_t position) const {
    const std::size_t at = std::min(position > 0 ? position - 1 : 0, text_.size());
    std::size_t line = 1;
    std::size_t line_start = 0;
    for (std::size_t i = 0; i < at; ++i) {
      if (text_[i] == '\n') {
        ++line;
        line_start = i + 1;
      }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(at - line_start + 1);
  }

  // The problem part of nlohmann's message, without its own prefix and position.
  static std::string syntax_problem(std::string message) {
    const std::string_view marker = "syntax error while parsing ";
    std::size_t at = message.find(marker);
    if (at != std::string::npos) {
      message.erase(0, at + marker.size());
      const std::size_t dash = message.find(" - ");
      if (dash != std::string::npos) message.erase(0, dash + 3);
    } else if ((at = message.find(": ")) != std::string::npos) {
      message.erase(0, at + 2);
    }
    // The text nlohmann last read can be long (a whole string literal); keep its end.
    const std::string_view last = "last read: '";
    if ((at = message.find(last)) != std::string::npos) {
      const std::size_t from = at + last.size();
      std::size_t to = message.find("'; expected", from);
      if (to == std::string::npos) to = message.size() - 1;
      constexpr std::size_t kKeep = 40;
      if (to > from + kKeep) {
        std::size_t cut = to - kKeep;
        while (cut < to && (static_cast<unsigned char>(message[cut]) & 0xC0) == 0x80) ++cut;
        message.replace(from, cut - from, "...");
      }
    }
    return printable(message);
  }

  std::string_view text_;
  std::string_view source_;
  std::vector<Level> stack_;
};

}  // namespace

Json parse_document(std::string_view text, std::string_view source) {
  if (std::all_of(text.begin(), text.end(),
                  [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; })) {
    throw InputError(prefix(source, {}) + "the input is empty (expected a tree file)");
  }
  DocumentBuilder builder(text, source);
  Json::sax_parse(text.begin(), text.end(), &builder);
  return std::move(builder.document);
}

}  // namespace fuzzycsg::io::detail
