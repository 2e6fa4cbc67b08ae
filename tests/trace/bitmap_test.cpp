// Reading bitmaps: glyph PNG and PBM agree, colour and alpha, corrupt and oversized files, 1x1.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/png.hpp"
#include "fuzzycsg/trace/bitmap.hpp"

namespace fuzzycsg::trace {
namespace {

namespace fs = std::filesystem;

const fs::path kGlyphs = fs::path(FUZZYCSG_TEST_DATA_DIR) / "glyphs";

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("fuzzycsg_trace_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(path_);
  }
  ~TempDir() {
    if (!::testing::Test::HasFailure()) fs::remove_all(path_);
  }
  fs::path file(const std::string& name, const std::string& bytes) const {
    const fs::path p = path_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }

 private:
  fs::path path_;
};

TEST(TraceBitmap, SetSpanAndCount) {
  Bitmap b(130, 3);
  EXPECT_EQ(b.words_per_row(), 3);
  b.set_span(1, 5, 129);
  EXPECT_EQ(b.count(), 124);
  EXPECT_FALSE(b.get(4, 1));
  EXPECT_TRUE(b.get(5, 1));
  EXPECT_TRUE(b.get(63, 1));
  EXPECT_TRUE(b.get(64, 1));
  EXPECT_TRUE(b.get(128, 1));
  EXPECT_FALSE(b.get(129, 1));
  b.set_span(0, 64, 65);
  EXPECT_EQ(b.count(), 125);
  b.clear_rows(0, 2);
  EXPECT_EQ(b.count(), 0);
  EXPECT_THROW(Bitmap(0, 5), InputError);
  EXPECT_THROW(Bitmap(8193, 8192), InputError);
}

TEST(TraceBitmap, GlyphPngAndPbmGiveTheSameMask) {
  for (const char* glyph : {"DejaVuSans-Bold_U0050_P", "DejaVuSans-Bold_U0045_E",
                            "DejaVuSerif-Bold_U0062_b", "FreeSansBold_U0069_i"}) {
    SCOPED_TRACE(glyph);
    const Bitmap png = read_bitmap(kGlyphs / (std::string(glyph) + ".png"));
    const Bitmap pbm = read_bitmap(kGlyphs / (std::string(glyph) + ".pbm"));
    EXPECT_EQ(png.width(), 128);
    EXPECT_EQ(png.height(), 128);
    EXPECT_EQ(png, pbm);
    EXPECT_GT(png.count(), 500);
    EXPECT_LT(png.count(), 128 * 128 / 2);
    EXPECT_FALSE(png.get(0, 0));  // a dark glyph on a white background
  }
}

TEST(TraceBitmap, ColourAndAlpha) {
  TempDir dir;
  // 5 x 1 RGBA: dark red (inside), yellow (outside), black transparent (white: outside), blue
  // half transparent over white (luminance ~ 0.55: outside), opaque dark grey (inside).
  const std::vector<unsigned char> rgba = {150, 0, 0, 255, 255, 255, 0,  255, 0,  0,
                                           0,   0, 0, 0,   255, 128, 60, 60,  60, 255};
  const fs::path p = dir.file("colour.png", encode_png(5, 1, 4, rgba));
  const Bitmap b = read_bitmap(p);
  ASSERT_EQ(b.width(), 5);
  ASSERT_EQ(b.height(), 1);
  EXPECT_TRUE(b.get(0, 0));
  EXPECT_FALSE(b.get(1, 0));
  EXPECT_FALSE(b.get(2, 0));
  EXPECT_FALSE(b.get(3, 0));
  EXPECT_TRUE(b.get(4, 0));
}

TEST(TraceBitmap, OneByOne) {
  TempDir dir;
  const Bitmap black = read_bitmap(dir.file("black.pbm", "P1\n1 1\n1\n"));
  ASSERT_EQ(black.width(), 1);
  ASSERT_EQ(black.height(), 1);
  EXPECT_TRUE(black.get(0, 0));
  const std::vector<unsigned char> white = {255};
  const Bitmap w = read_bitmap(dir.file("white.png", encode_png(1, 1, 1, white)));
  EXPECT_EQ(w.width(), 1);
  EXPECT_EQ(w.count(), 0);
}

TEST(TraceBitmap, CorruptMissingAndOversizedFilesAreOneLineErrorsNamingTheFile) {
  TempDir dir;
  const auto message = [](const fs::path& p) {
    try {
      read_bitmap(p);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // A PNG cut short.
  const std::vector<unsigned char> grey(64 * 64, 0);
  const std::string png = encode_png(64, 64, 1, grey);
  for (const auto& [name, bytes] :
       std::vector<std::pair<std::string, std::string>>{{"cut.png", png.substr(0, 40)},
                                                        {"text.png", "not a picture"},
                                                        {"cut.pbm", "P4\n16 16\n\x01\x02"},
                                                        {"huge.pbm", "P4\n10000 10000\n"},
                                                        {"empty.png", ""}}) {
    SCOPED_TRACE(name);
    const std::string m = message(dir.file(name, bytes));
    EXPECT_NE(m, "no error");
    EXPECT_NE(m.find(name), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  EXPECT_NE(message(dir.file("huge.pbm", "P4\n10000 10000\n")).find("too large"),
            std::string::npos);
  // A PNG header claiming 10000 x 10000 pixels is refused before anything is decoded.
  static constexpr char kHugePng[] =
      "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x27\x10"
      "\x00\x00\x27\x10\x08\x00\x00\x00\x00\x9f\x25\x3d\xfb";
  const std::string huge_png =
      message(dir.file("huge.png", std::string(kHugePng, sizeof(kHugePng) - 1)));
  EXPECT_NE(huge_png.find("huge.png"), std::string::npos) << huge_png;
  EXPECT_NE(huge_png.find("too large"), std::string::npos) << huge_png;
  const std::string missing = message(fs::path("/nonexistent/dir/glyph.png"));
  EXPECT_NE(missing.find("glyph.png"), std::string::npos) << missing;
}

TEST(TraceBitmap, BytesRoundTrip) {
  const std::vector<std::uint8_t> bytes = {1, 0, 0, 1, 1, 0};
  const Bitmap b = bitmap_from_bytes(bytes, 3, 2);
  EXPECT_EQ(bitmap_to_bytes(b), bytes);
  EXPECT_EQ(b.count(), 3);
  EXPECT_THROW(bitmap_from_bytes(bytes, 2, 2), InputError);
}

}  // namespace
}  // namespace fuzzycsg::trace
