// libFuzzer target: any input is read as a tree file. InputError is the expected answer to bad
// input; any other exception, a crash or a sanitizer report is a bug. A tree that reads must
// also round-trip: write -> read gives an identical tree and the same text again.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/tree_json.hpp"
#include "io/tree_compare.hpp"

namespace {

[[noreturn]] void bug(const std::string& what, std::string_view detail) {
  std::fprintf(stderr, "tree_reader_fuzz: %s\n%.*s\n", what.c_str(),
               static_cast<int>(detail.size()), detail.data());
  std::abort();
}

void check_message(const fuzzycsg::InputError& e) {
  const std::string_view message = e.what();
  if (message.empty() || message.find('\n') != std::string_view::npos) {
    bug("an InputError message is not one non-empty line", message);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fuzzycsg;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Tree tree;
  try {
    tree = io::read_tree_string(text, "fuzz.json");
  } catch (const InputError& e) {
    check_message(e);
    return 0;
  }

  std::string written;
  Tree back;
  try {
    written = io::write_tree_string(tree);
    back = io::read_tree_string(written, "written.json");
  } catch (const InputError& e) {
    bug(std::string("a tree that was read does not write and read back: ") + e.what(), written);
  }
  const std::string difference = testing::tree_difference(tree, back);
  if (!difference.empty()) bug("the round trip changed the tree: " + difference, written);
  if (io::write_tree_string(back) != written) bug("the written text is not stable", written);
  return 0;
}
