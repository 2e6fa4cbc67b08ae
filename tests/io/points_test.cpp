// Point files: separators, comments, and errors with line and column.
#include "fuzzycsg/io/points.hpp"
#include "fuzzycsg/io/files.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"

namespace fuzzycsg::io {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::string& text, int dim) {
  try {
    read_points_string(text, dim, "pts.txt");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Points, SeparatorsAndComments) {
  const std::string text =
      "# x y z\n"
      "1 2 3\n"
      "\n"
      "  4,5,6\n"
      "7 ,\t8 , 9   \r\n"
      "   # indented comment\n"
      "-1.5e-3, +2, .5\n"
      "\t\n"
      "1e10 -0 0x";
  EXPECT_EQ(error_of(text, 3), "pts.txt: line 9, column 9: expected a number (got \"0x\")");
  const std::vector<float> points =
      read_points_string(text.substr(0, text.size() - 10), 3, "pts.txt");
  EXPECT_EQ(points, (std::vector<float>{1, 2, 3, 4, 5, 6, 7, 8, 9, -1.5e-3f, 2, 0.5f}));
  EXPECT_EQ(read_points_string("1 2\n3 4", 2, "p"), (std::vector<float>{1, 2, 3, 4}));
  EXPECT_EQ(read_points_string("0.1,0.2\r\n", 2, "p"), (std::vector<float>{0.1f, 0.2f}));
}

TEST(Points, Errors) {
  EXPECT_EQ(error_of("1 2 3\n1 2 3\n1 2\n", 3), "pts.txt: line 3: expected 3 coordinates (got 2)");
  EXPECT_EQ(error_of("1 2 3 4\n", 3), "pts.txt: line 1: expected 3 coordinates (got 4)");
  EXPECT_EQ(error_of("1 2 3\n\n\n# c\n\n\n1 2 3\n4, 5, abc\n", 3).substr(0, 36),
            "pts.txt: line 8, column 7: expected ");
  EXPECT_EQ(error_of("1 2 3\n4 5 6\n7 8 9\n1 2 3\n1 2 3\n1 2 3\n1, 2,      abc\n", 3),
            "pts.txt: line 7, column 12: expected a number (got \"abc\")");
  EXPECT_EQ(error_of("1,,2\n", 2), "pts.txt: line 1, column 3: expected a number (got \",\")");
  EXPECT_EQ(error_of(", 1 2\n", 2), "pts.txt: line 1, column 1: expected a number (got \",\")");
  EXPECT_EQ(error_of("1, 2,\n", 2),
            "pts.txt: line 1, column 6: expected a number (got the end of the line)");
  EXPECT_EQ(error_of("1 inf\n", 2), "pts.txt: line 1, column 3: must be finite (got \"inf\")");
  EXPECT_EQ(error_of("nan 1\n", 2), "pts.txt: line 1, column 1: must be finite (got \"nan\")");
  EXPECT_EQ(error_of("1 1e999\n", 2),
            "pts.txt: line 1, column 3: number out of range (got \"1e999\")");
  EXPECT_EQ(error_of("1 1e39\n", 2),
            "pts.txt: line 1, column 3: number out of range (got \"1e39\")");
  EXPECT_EQ(error_of("1 2 # trailing\n", 2),
            "pts.txt: line 1, column 5: expected a number (got \"#\")");
  EXPECT_EQ(error_of("1 --2\n", 2), "pts.txt: line 1, column 3: expected a number (got \"--2\")");
  EXPECT_EQ(error_of("1 ++2\n", 2), "pts.txt: line 1, column 3: expected a number (got \"++2\")");
  EXPECT_EQ(error_of("", 3), "pts.txt: no points");
  EXPECT_EQ(error_of("# only a comment\n\n", 3), "pts.txt: no points");
  EXPECT_EQ(error_of("1 2 3", 0), "pts.txt: points must have at least 1 coordinate (got 0)");
}

TEST(Points, Files) {
  const fs::path dir =
      fs::temp_directory_path() / ("fuzzycsg-points-test-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path file = dir / "pts.txt";
  write_text_file_atomic(file, "0 0\n1 1\n");
  EXPECT_EQ(read_points_file(file, 2), (std::vector<float>{0, 0, 1, 1}));
  write_text_file_atomic(file, "2 2\n");
  EXPECT_EQ(read_points_file(file, 2), (std::vector<float>{2, 2}));
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1u);  // no temporary files left behind
  try {
    read_points_file(dir / "missing.txt", 2);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir / "missing.txt").string() + ": cannot read (No such file or directory)");
  }
  try {
    read_points_file(dir, 2);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir.string() + ": cannot read (Is a directory)");
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fuzzycsg::io
