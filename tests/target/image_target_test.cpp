// Image targets: a disc drawn here against the analytic disc (area, labels, boundary, normals,
// distances), aspect ratio, the Netpbm reader against PNG, the glyphs of tests/data, bad files.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/target/picture.hpp"
#include "fuzzycsg/target/signed_distance_grid.hpp"
#include "fuzzycsg/target/target.hpp"
#include "test_support.hpp"

namespace fuzzycsg::test {
namespace {

using namespace std::string_literals;

// A picture: grey values, row 0 at the top.
struct Picture {
  int width = 0, height = 0;
  std::vector<std::uint8_t> grey;
};

// Pixel (r, c) of a width x height picture spanning the domain along its longer side (as the
// target maps it) is dark where `dark` holds at its centre.
Picture draw(int width, int height, const std::function<bool(double, double)>& dark) {
  Picture p{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height)};
  const double h = 2.0 / std::max(width, height);
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const double x = (c + 0.5 - width / 2.0) * h, y = (height / 2.0 - r - 0.5) * h;
      p.grey[static_cast<std::size_t>(r) * width + c] = dark(x, y) ? 30 : 220;
    }
  }
  return p;
}

std::string write_png(const TempDir& dir, const std::string& name, const Picture& p) {
  const std::string path = dir.file(name);
  if (!stbi_write_png(path.c_str(), p.width, p.height, 1, p.grey.data(), p.width)) {
    throw std::runtime_error("cannot write " + path);
  }
  return path;
}

constexpr double kCx = 0.3, kCy = 0.2, kR = 0.45;  // the disc, off centre in x and y
bool in_disc(double x, double y) { return std::hypot(x - kCx, y - kCy) < kR; }

TEST(ImageTarget, Disc) {
  TempDir dir;
  const std::string path = write_png(dir, "disc.png", draw(400, 400, in_disc));
  for (int resolution : {0, 256}) {
    SCOPED_TRACE(resolution);
    const auto target = load_target(path, TargetOptions{0.2, resolution, 0});
    const int n = resolution == 0 ? 400 : resolution;
    const double h = 2.0 / n;
    EXPECT_EQ(target->kind(), "image");
    EXPECT_EQ(target->dim(), 2);
    EXPECT_EQ(target->describe(), "image disc.png: 400x400 pixels, grid " + std::to_string(n) +
                                      "x" + std::to_string(n));

    // The centre is inside; (-0.3, 0.2) and (0.3, -0.4), 0.6 from it, are outside, and would be
    // 0.2 from it, inside, were x or y flipped. Nothing beyond [-1, 1] is inside.
    std::vector<float> occ(4);
    target->occupancy(std::vector<float>{0.3f, 0.2f, -0.3f, 0.2f, 0.3f, -0.4f, 1.2f, 0.2f}, occ);
    EXPECT_EQ(occ, (std::vector<float>{1, 0, 0, 0}));

    // Area, and every label away from the circle.
    const std::size_t count = 200000;
    const double area = std::numbers::pi * kR * kR / 4;  // share of [-1, 1]^2
    EXPECT_NEAR(inside_fraction(*target, count, 3), area,
                tolerance(area, count, 2 * std::numbers::pi * kR * h / 4));
    Rng rng(5);
    const std::vector<float> points = uniform_points(2, count, rng);
    std::vector<float> labels(count);
    target->occupancy(points, labels);
    for (std::size_t i = 0; i < count; ++i) {
      const double d = std::hypot(points[2 * i] - kCx, points[2 * i + 1] - kCy) - kR;
      if (std::abs(d) > 1.5 * h) {
        ASSERT_EQ(labels[i], d < 0 ? 1.0f : 0.0f) << d;
      }
    }

    // Boundary samples on the circle, normals radial, spread evenly over the angle.
    std::vector<float> b, nrm;
    target->sample_boundary(20000, rng, b, nrm);
    ASSERT_EQ(b.size(), 40000u);
    ASSERT_EQ(nrm.size(), 40000u);
    std::array<int, 8> sector{};
    for (std::size_t s = 0; s < 20000; ++s) {
      const double x = b[2 * s] - kCx, y = b[2 * s + 1] - kCy, r = std::hypot(x, y);
      EXPECT_NEAR(r, kR, 0.75 * h);
      EXPECT_NEAR(std::hypot(nrm[2 * s], nrm[2 * s + 1]), 1.0, 1e-6);
      // Resampling 400 to 256 pixels by nearest neighbour makes a rougher staircase than
      // SignedDistanceGrid.DiscDistances draws.
      EXPECT_GT((nrm[2 * s] * x + nrm[2 * s + 1] * y) / r, std::cos(0.35));
      const double angle = std::atan2(y, x) + std::numbers::pi;
      ++sector[std::min(7, static_cast<int>(angle / (2 * std::numbers::pi) * 8))];
    }
    for (int k = 0; k < 8; ++k) EXPECT_NEAR(sector[k] / 20000.0, 0.125, tolerance(0.125, 20000));
  }
}

// The distance field of a disc mask against the distance to the circle.
TEST(SignedDistanceGrid, DiscDistances) {
  const int n = 256;
  const double h = 2.0 / n;
  std::vector<std::uint8_t> mask(n * n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) mask[r * n + c] = in_disc(-1 + (c + 0.5) * h, 1 - (r + 0.5) * h);
  }
  const SignedDistanceGrid grid(mask, n);
  EXPECT_EQ(grid.size(), n);
  EXPECT_DOUBLE_EQ(grid.cell(), h);
  Rng rng(2);
  const std::vector<float> points = uniform_points(2, 50000, rng);
  double worst = 0;
  for (std::size_t i = 0; i < 50000; ++i) {
    const double x = points[2 * i], y = points[2 * i + 1];
    if (std::abs(x) > 1 - h || std::abs(y) > 1 - h) continue;  // clamped beyond the centres
    const double exact = std::hypot(x - kCx, y - kCy) - kR;
    worst = std::max(worst, std::abs(grid.value(x, y) - exact));
  }
  EXPECT_LT(worst, 0.75 * h);  // half a pixel of pixelation, and the half-pixel shift
  // Normals on the zero level set (found by bisection along radii) against the radius.
  double worst_angle = 0, mean_angle = 0;
  for (int i = 0; i < 2000; ++i) {
    const double a = 2 * std::numbers::pi * (i + 0.5) / 2000;
    double lo = 0, hi = 1;
    for (int k = 0; k < 50; ++k) {
      const double mid = (lo + hi) / 2;
      (grid.value(kCx + mid * std::cos(a), kCy + mid * std::sin(a)) <= 0 ? lo : hi) = mid;
    }
    const auto nrm = grid.normal(kCx + lo * std::cos(a), kCy + lo * std::sin(a));
    EXPECT_NEAR(std::hypot(nrm[0], nrm[1]), 1.0, 1e-12);
    const double angle = std::acos(std::min(1.0, nrm[0] * std::cos(a) + nrm[1] * std::sin(a)));
    worst_angle = std::max(worst_angle, angle);
    mean_angle += angle / 2000;
  }
  EXPECT_LT(worst_angle, 0.25);
  EXPECT_LT(mean_angle, 0.08);
  EXPECT_THROW(SignedDistanceGrid(std::vector<std::uint8_t>(16, 1), 4), InputError);
  EXPECT_THROW(SignedDistanceGrid(std::vector<std::uint8_t>(15, 1), 4), InputError);
}

// The exact transform against brute force on random masks, square and not.
TEST(SignedDistanceGrid, DistanceTransformIsExact) {
  Rng rng(8);
  for (const auto& [w, h, density] : {std::tuple{37, 23, 0.02}, std::tuple{16, 16, 0.3},
                                      std::tuple{1, 9, 0.2}, std::tuple{50, 1, 0.1}}) {
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(w) * h);
    for (auto& m : mask) m = (rng() % 1000) < density * 1000 ? 1 : 0;
    mask[rng() % mask.size()] = 1;
    const std::vector<double> d = squared_distance_transform(mask, w, h, 1);
    for (int r = 0; r < h; ++r) {
      for (int c = 0; c < w; ++c) {
        double best = std::numeric_limits<double>::infinity();
        for (int r2 = 0; r2 < h; ++r2) {
          for (int c2 = 0; c2 < w; ++c2) {
            if (mask[r2 * w + c2])
              best = std::min(best, double((r - r2) * (r - r2) + (c - c2) * (c - c2)));
          }
        }
        ASSERT_EQ(d[r * w + c], best) << w << "x" << h << " at " << r << ", " << c;
      }
    }
  }
  const std::vector<double> none =
      squared_distance_transform(std::vector<std::uint8_t>(6, 0), 3, 2, 1);
  for (double v : none) EXPECT_EQ(v, std::numeric_limits<double>::infinity());
}

// A picture wider than high keeps its proportions: it spans x in [-1, 1] and y in [-1/2, 1/2],
// the rest of the square is outside.
TEST(ImageTarget, KeepsAspectRatio) {
  TempDir dir;
  Picture wide{200, 100, std::vector<std::uint8_t>(200 * 100, 0)};  // all dark
  wide.grey[0] = 255;                                               // one light pixel
  Picture tall{25, 100, std::vector<std::uint8_t>(25 * 100, 0)};
  tall.grey[0] = 255;
  const std::string wide_path = write_png(dir, "wide.png", wide);
  const std::string tall_path = write_png(dir, "tall.png", tall);
  for (int resolution : {0, 64}) {
    const auto w = load_target(wide_path, TargetOptions{0.2, resolution, 0});
    const auto t = load_target(tall_path, TargetOptions{0.2, resolution, 0});
    EXPECT_EQ(w->describe(), std::string("image wide.png: 200x100 pixels, grid ") +
                                 (resolution ? "64x64" : "200x200"));
    EXPECT_NEAR(inside_fraction(*w, 100000, 1), 0.5, tolerance(0.5, 100000, 0.02));
    EXPECT_NEAR(inside_fraction(*t, 100000, 1), 0.25, tolerance(0.25, 100000, 0.02));
    std::vector<float> occ(4);
    w->occupancy(std::vector<float>{0.0f, 0.7f, 0.9f, 0.4f, 0.0f, -0.7f, -0.9f, -0.4f}, occ);
    EXPECT_EQ(occ, (std::vector<float>{0, 1, 0, 1}));
    t->occupancy(std::vector<float>{0.3f, 0.0f, 0.2f, 0.9f, -0.3f, 0.0f, -0.2f, -0.9f}, occ);
    EXPECT_EQ(occ, (std::vector<float>{0, 1, 0, 1}));
  }
}

// One small picture written as P1, P2, P4, P5 (8 and 16 bit) and PNG gives one target.
TEST(ImageTarget, NetpbmFormatsAgreeWithPng) {
  TempDir dir;
  const int w = 13, h = 7;  // rows of P4 padded to whole bytes
  Picture p{w, h, std::vector<std::uint8_t>(w * h)};
  for (int i = 0; i < w * h; ++i) p.grey[i] = (i * 7 % 11) < 5 ? 0 : 255;
  const std::string png = write_png(dir, "p.png", p);
  std::string p1 = "P1\n# comment\n13 7\n", p2 = "P2 13 7\n# max\n255\n", p4 = "P4\n13 7\n",
              p5 = "P5 13 7 255\n", p5_16 = "P5\n13\n7\n65535\n";
  for (int r = 0; r < h; ++r) {
    unsigned char byte = 0;
    for (int c = 0; c < w; ++c) {
      const bool dark = p.grey[r * w + c] == 0;
      p1 += dark ? '1' : '0';  // plain PBM needs no spaces between bits
      p2 += dark ? " 0" : " 255";
      p5 += static_cast<char>(p.grey[r * w + c]);
      p5_16 += dark ? std::string(2, '\0') : std::string("\x80\x00", 2);  // 32768 >= 65535 / 2
      byte = static_cast<unsigned char>(byte | (dark ? 0x80 >> (c % 8) : 0));
      if (c % 8 == 7 || c == w - 1) {
        p4 += static_cast<char>(byte);
        byte = 0;
      }
    }
    p1 += '\n';
    p2 += '\n';
  }
  const auto reference = load_target(png, TargetOptions{0.2, 0, 0});
  Rng rng(4);
  const std::vector<float> points = uniform_points(2, 20000, rng);
  std::vector<float> expected(20000), got(20000);
  reference->occupancy(points, expected);
  for (const auto& [name, bytes] :
       {std::pair{"p1.pbm", p1}, std::pair{"p2.pgm", p2}, std::pair{"p4.pbm", p4},
        std::pair{"p5.pgm", p5}, std::pair{"p5_16.PGM", p5_16}}) {
    SCOPED_TRACE(name);
    const auto target = load_target(dir.write(name, bytes), TargetOptions{0.2, 0, 0});
    EXPECT_EQ(target->describe(), std::string("image ") + name + ": 13x7 pixels, grid 13x13");
    target->occupancy(points, got);
    EXPECT_EQ(got, expected);
  }
}

TEST(ImageTarget, GlyphPictures) {
  // The glyphs come as PBM and PNG of the same bitmap.
  for (const char* glyph : {"DejaVuSans-Bold_U0026_ampersand", "LiberationSerif-Regular_U0069_i"}) {
    SCOPED_TRACE(glyph);
    const auto pbm = load_target(data_file(std::string("glyphs/") + glyph + ".pbm"));
    const auto png = load_target(data_file(std::string("glyphs/") + glyph + ".png"));
    EXPECT_EQ(pbm->describe(),
              std::string("image ") + glyph + ".pbm: 128x128 pixels, grid 256x256");
    Rng rng(1);
    const std::vector<float> points = uniform_points(2, 50000, rng);
    std::vector<float> a(50000), b(50000);
    pbm->occupancy(points, a);
    png->occupancy(points, b);
    EXPECT_EQ(a, b);
    const double fraction = inside_fraction(*pbm, 50000, 2);
    EXPECT_GT(fraction, 0.02);
    EXPECT_LT(fraction, 0.5);
  }
}

// A large JPEG of a logo-like shape (as Liu et al.'s 2D target: a dark disc in a dark ring on
// white), drawn here: the picture is read whole and resampled to the distance grid.
TEST(ImageTarget, LargeJpeg) {
  TempDir dir;
  const std::string path = dir.file("logo.jpg");
  const Picture p = draw(3000, 3000, [](double x, double y) {
    const double r = std::hypot(x, y);
    return r < 0.55 || (r > 0.8 && r < 0.95);
  });
  ASSERT_TRUE(stbi_write_jpg(path.c_str(), p.width, p.height, 1, p.grey.data(), 90));
  const auto logo = load_target(path);
  EXPECT_EQ(logo->describe(), "image logo.jpg: 3000x3000 pixels, grid 256x256");
  const double fraction = inside_fraction(*logo, 100000, 3);
  EXPECT_GT(fraction, 0.3);
  EXPECT_LT(fraction, 0.7);
  std::vector<float> occ(2);
  logo->occupancy(std::vector<float>{0.0f, 0.0f, 0.99f, 0.99f}, occ);  // the disc, a corner
  EXPECT_EQ(occ[0], 1.0f);
  EXPECT_EQ(occ[1], 0.0f);
  Rng rng(5);
  std::vector<float> b, n;
  logo->sample_boundary(1000, rng, b, n);
  std::vector<float> probes;
  for (std::size_t s = 0; s < 1000; ++s) {
    for (float sign : {1.0f, -1.0f}) {
      probes.push_back(b[2 * s] + sign * 0.01f * n[2 * s]);
      probes.push_back(b[2 * s + 1] + sign * 0.01f * n[2 * s + 1]);
    }
  }
  std::vector<float> labels(2000);
  logo->occupancy(probes, labels);
  int good = 0;
  for (std::size_t s = 0; s < 1000; ++s) good += labels[2 * s] == 0 && labels[2 * s + 1] == 1;
  EXPECT_GT(good, 950);
}

// A dark shape on a transparent background: transparent counts as white.
TEST(ImageTarget, TransparentIsWhite) {
  TempDir dir;
  std::vector<std::uint8_t> grey_alpha(64 * 64 * 2, 0);  // black, transparent
  for (int r = 16; r < 48; ++r) {
    for (int c = 16; c < 48; ++c) grey_alpha[(r * 64 + c) * 2 + 1] = 255;  // opaque black
  }
  const std::string path = dir.file("icon.png");
  ASSERT_TRUE(stbi_write_png(path.c_str(), 64, 64, 2, grey_alpha.data(), 64 * 2));
  const auto target = load_target(path);
  EXPECT_NEAR(inside_fraction(*target, 100000, 1), 0.25, tolerance(0.25, 100000, 0.01));
}

TEST(ImageTarget, SamplingIsDeterministic) {
  TempDir dir;
  const std::string path = write_png(dir, "disc.png", draw(100, 100, in_disc));
  const auto a = load_target(path, TargetOptions{0.2, 128, 1});
  const auto b = load_target(path, TargetOptions{0.2, 128, 2});
  Rng ra(3), rb(3);
  std::vector<float> pa, na, pb, nb;
  a->sample_boundary(500, ra, pa, na);
  b->sample_boundary(500, rb, pb, nb);
  EXPECT_EQ(pa, pb);
  EXPECT_EQ(na, nb);
}

TEST(ImageTarget, BadFiles) {
  TempDir dir;
  const auto expect_error = [](const std::string& path, const std::string& message,
                               const TargetOptions& options = {}) {
    const std::string e = load_error(path, options);
    EXPECT_EQ(e.substr(0, path.size() + 2), path + ": ") << e;
    EXPECT_NE(e.find(message), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  };
  const std::string white =
      write_png(dir, "white.png", draw(32, 32, [](double, double) { return false; }));
  expect_error(white, "nothing is inside: no dark pixels at 256x256");
  const std::string square =
      write_png(dir, "square.png", draw(32, 32, [](double, double) { return true; }));
  expect_error(square, "nothing is outside: no light pixels at 256x256");
  expect_error(square, "nothing is outside: no light pixels at 1x1", TargetOptions{0.2, 1, 0});
  // A thin line vanishes when resampled.
  const std::string line =
      write_png(dir, "line.png",
                draw(1000, 1000, [](double x, double) { return std::abs(x - 0.0011) < 0.001; }));
  expect_error(line, "nothing is inside: no dark pixels at 64x64", TargetOptions{0.2, 64, 0});
  for (const char* ext : {".png", ".jpg", ".jpeg", ".pbm", ".pgm"}) {
    SCOPED_TRACE(ext);
    expect_error(dir.write(std::string("empty") + ext, ""), "empty file");
    expect_error(dir.write(std::string("garbage") + ext, "\x89PNG\x01\xff garbage"s),
                 "cannot read image (");
    expect_error(dir.file(std::string("missing") + ext), "cannot read (No such file or directory)");
  }
  expect_error(dir.write("colour.pgm", "P6 1 1 255\n\x01\x02"),
               "cannot read image (truncated raster)");
  expect_error(dir.write("colour.ppm.png", "P3 1 1 255\n1 2 300\n"),
               "cannot read image (a sample exceeds the maximum value)");
  expect_error(dir.write("pam.pgm", "P7\nWIDTH 1\n"),
               "cannot read image (not a Netpbm file: P1 to P6)");
  expect_error(dir.write("short.pbm", "P4 16 2\n\x01\x02\x03"),
               "cannot read image (truncated raster)");
  expect_error(dir.write("short1.pbm", "P1 2 2\n0 1 1"), "cannot read image (truncated raster)");
  expect_error(dir.write("digit.pbm", "P1 2 2\n0 1 1 2"),
               "cannot read image (expected 0 or 1 in the raster)");
  expect_error(dir.write("maxval.pgm", "P2 2 1 10\n3 11\n"),
               "cannot read image (a sample exceeds the maximum value)");
  expect_error(dir.write("zero.pgm", "P5 0 1 255\n"),
               "cannot read image (the width and height must be at least 1, got 0x1)");
  expect_error(dir.write("wide.pgm", "P5 99999999999 1 255\n"),
               "cannot read image (the width is too large)");
  expect_error(dir.write("huge.pbm", "P4 100000 100000\n\x01"),
               "cannot read image (100000x100000 pixels is too large; at most 67108864 pixels)");
  expect_error(dir.write("header.pgm", "P5 4 4"), "cannot read image (truncated)");
  expect_error(dir.write("nospace.pgm", "P5 1 1 255\x01"),
               "cannot read image (no whitespace after the header)");
  const std::string ok = write_png(dir, "ok.png", draw(8, 8, in_disc));
  // A PNG whose header claims 20000 x 20000 pixels (width and height follow "IHDR").
  std::string bomb;
  {
    std::ifstream in(ok, std::ios::binary);
    bomb.assign(std::istreambuf_iterator<char>(in), {});
    bomb.replace(16, 8, std::string("\x00\x00\x4e\x20\x00\x00\x4e\x20", 8));
  }
  expect_error(dir.write("bomb.png", bomb),
               "cannot read image (20000x20000 pixels is too large; at most 67108864 pixels)");
  expect_error(ok, "image_resolution must be in [0, 4096] (got 5000)", TargetOptions{0.2, 5000, 0});
  expect_error(ok, "image_resolution must be in [0, 4096] (got -1)", TargetOptions{0.2, -1, 0});
  const std::string long_strip = write_png(dir, "strip.png", draw(5000, 1, in_disc));
  expect_error(long_strip, "5000x1 pixels is too large for the native resolution (at most 4096)",
               TargetOptions{0.2, 0, 0});
}

// A decoder's reason is part of the one-line message: stb names an unknown PNG chunk by the four
// bytes of its type, as they are in the file, newlines included.
TEST(ImageTarget, DecoderReasonsStayOnOneLine) {
  TempDir dir;
  const std::string ok = write_png(dir, "ok.png", draw(8, 8, in_disc));
  std::string png;
  {
    std::ifstream in(ok, std::ios::binary);
    png.assign(std::istreambuf_iterator<char>(in), {});
  }
  // After the signature (8 bytes) and IHDR (25): an empty critical chunk of type "\nP\nX".
  png.insert(33, std::string("\x00\x00\x00\x00\nP\nX\x00\x00\x00\x00", 12));
  const std::string path = dir.write("chunk.png", png);
  const std::string e = load_error(path);
  EXPECT_EQ(e, path + ": cannot read image (?P?X PNG chunk not known)");
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

// stb_image decodes a PNM header of width or height 0 to an image of no pixels, which
// read_picture passed on.
TEST(ImageTarget, PicturesOfNoPixelsAreRefused) {
  TempDir dir;
  for (const auto& [header, size] :
       {std::pair{"P5 0 3 255\n", "0x3"}, std::pair{"P5 3 0 255\n", "3x0"}}) {
    const std::string path = dir.write(std::string("empty_") + size + ".png", header);
    const std::string message =
        path + ": cannot read image (the width and height must be at least 1, got " + size + ")";
    EXPECT_EQ(load_error(path), message);
    try {
      read_picture(path, path);
      ADD_FAILURE() << "read " << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.what(), message);
    }
  }
}

// Netpbm is read by its first bytes whatever the file's name (stb_image, which read binary PNM in
// a .png, read past its buffer converting 16-bit samples, and left the pixels of a truncated
// raster undefined: two reads of one file disagreed).
TEST(ImageTarget, NetpbmByContent) {
  TempDir dir;
  // The fuzzer's input (P5, 276 x 255, no maximum value, no raster) and a short raster.
  for (const auto& [name, bytes, reason] :
       {std::tuple{"truncated.png", "P5276 255PG", "expected the maximum value"},
        std::tuple{"short.png", "P5 276 255 255\n\x01\x02", "truncated raster"}}) {
    const std::string path = dir.write(name, bytes);
    EXPECT_EQ(load_error(path), path + ": cannot read image (" + reason + ")");
  }
  // Plain and raw pixmaps: red (dark), white / white, blue (dark); the same as a greymap.
  const std::string plain = "P3 2 2 255\n255 0 0  255 255 255\n255 255 255  0 0 255\n";
  const std::string raw = "P6 2 2 255\n\xff\x00\x00\xff\xff\xff\xff\xff\xff\x00\x00\xff"s;
  const std::string png =
      write_png(dir, "same.png", draw(2, 2, [](double x, double y) { return x * y < 0; }));
  for (const auto& [name, bytes] :
       {std::pair{"plain.ppm.png", plain}, std::pair{"raw.pgm", raw}, std::pair{"raw.jpg", raw}}) {
    SCOPED_TRACE(name);
    const fuzzycsg::Picture p = read_picture(dir.write(name, bytes), name);
    EXPECT_EQ(p.width, 2);
    EXPECT_EQ(p.height, 2);
    EXPECT_EQ(p.inside, (std::vector<std::uint8_t>{1, 0, 0, 1}));
    EXPECT_EQ(read_picture(png, "same.png").inside, p.inside);
  }
}

// A 16-bit Netpbm named .png: stb_image read past its buffer and the first pixel came out white.
TEST(ImageTarget, SixteenBitPnmNamedPng) {
  TempDir dir;
  // Dark, light / light, dark: in grey (P5) and in colour (P6: red, white / white, blue).
  const std::string grey = "P5 2 2 65535\n"s + std::string("\x00\x00\xff\xff\xff\xff\x00\x00", 8);
  const std::string colour = "P6 2 2 65535\n"s + std::string(2, '\xff') + std::string(4, '\x00') +
                             std::string(12, '\xff') + std::string(4, '\x00') +
                             std::string(2, '\xff');
  for (const auto& [name, bytes] :
       {std::pair{"grey16.png", grey}, std::pair{"colour16.png", colour}}) {
    SCOPED_TRACE(name);
    const fuzzycsg::Picture p = read_picture(dir.write(name, bytes), name);
    EXPECT_EQ(p.width, 2);
    EXPECT_EQ(p.height, 2);
    EXPECT_EQ(p.inside, (std::vector<std::uint8_t>{1, 0, 0, 1}));
  }
}

}  // namespace
}  // namespace fuzzycsg::test
