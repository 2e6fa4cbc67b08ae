#pragma once
// The frames of a morph (Gibson et al. 1997, "Application to geometric morphing"): two trees of
// the same structure (search_morph's result, node i of one corresponding to node i of the
// other) interpolated leaf by leaf, each frame rasterised by point tests at the pixel centres,
// and the frames as an animated GIF (giflib).
//
// Every leaf is interpolated as a rounded rectangle <(x, y), (w, h), corner c, theta>: a circle
// of radius r is the 2r x 2r square with c = r, a rectangle has c = 0. Centre, extents, corner
// radius and angle are interpolated linearly, so that a leaf that is a circle in one tree and a
// rectangle in the other (MOD acts on each tree independently) turns from one into the other
// through rounded rectangles. A rectangle is symmetric under a half turn, so its angle is
// interpolated along the shortest turn modulo 180 degrees, or in the direction asked for:
// clockwise on screen (theta increasing, y pointing down) or counter-clockwise. A circle
// paired with a rectangle takes the rectangle's angle throughout; two circles none.
//
// At t = 0 and t = 1 the leaves are the trees' own primitives, so those frames equal the trees'
// bitmaps (TreeEvaluator) exactly.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fuzzycsg/trace/bitmap.hpp"
#include "fuzzycsg/trace/csg.hpp"

namespace fuzzycsg::trace {

enum class Rotation : std::uint8_t { kShortest, kClockwise, kCounterClockwise };
std::string_view rotation_name(Rotation r);  // "shortest", "cw", "ccw"
std::optional<Rotation> rotation_from_name(std::string_view name);

struct RoundedRect {
  double x = 0, y = 0;  // centre (pixel units, y down)
  double w = 1, h = 1;  // full extents along the rotated u and v axes
  double corner = 0;    // corner radius, in [0, min(w, h) / 2]
  double theta = 0;     // degrees, as Primitive::theta
};

// A primitive as a rounded rectangle (a circle: the 2r x 2r square with corner radius r).
RoundedRect as_rounded_rect(const Primitive& p);
// Whether (px, py) lies strictly inside.
bool contains(const RoundedRect& r, double px, double py);

// The angle of a rectangle turning from theta0 to theta1 (degrees) at t in [0, 1]: the turn is
// the shortest one modulo 180 degrees (at most 90 either way; exactly 90 goes clockwise), or
// in [0, 180) clockwise, or in (-180, 0] counter-clockwise.
double interpolate_angle(double theta0, double theta1, double t, Rotation rotation);

// One leaf at t in [0, 1].
RoundedRect interpolate(const Primitive& a, const Primitive& b, double t,
                        Rotation rotation = Rotation::kShortest);

// Whether the two trees have the same structure: the same live nodes (ids), the same
// operators and children, leaves where the other has leaves.
bool same_structure(const CsgTree& a, const CsgTree& b);

// The morph between two trees of the same structure (throws std::invalid_argument otherwise).
class MorphInterpolator {
 public:
  MorphInterpolator(const CsgTree& first, const CsgTree& second,
                    Rotation rotation = Rotation::kShortest);
  // The frame at t in [0, 1] (clamped) as a width x height bitmap: the pixels whose centres
  // lie inside the interpolated tree. t = 0 and t = 1 evaluate the trees' own primitives.
  Bitmap frame(double t, int width, int height) const;
  // Frame i of n (n >= 1) is at t = i / (n - 1) (t = 0 for n = 1).
  std::vector<Bitmap> frames(int n, int width, int height) const;

 private:
  const CsgTree& first_;
  const CsgTree& second_;
  Rotation rotation_;
};

// The scale (an integer >= 1) at which a width x height picture is drawn so that its longer
// side is at least `at_least` pixels (nearest neighbour), as long as the picture stays within
// 4096 pixels a side.
int display_scale(int width, int height, int at_least = 256);

// A bitmap as an 8-bit indexed image scaled up `scale` times (nearest): `clear` and `set` are
// the indices of clear and set pixels.
std::vector<std::uint8_t> indexed_image(const Bitmap& b, int scale, std::uint8_t clear = 0,
                                        std::uint8_t set = 1);

// An animated GIF of frames of width x height palette indices (row-major, row 0 on top), each
// shown `delay_ms` milliseconds (GIF counts hundredths), looping forever. The palette has at
// most 256 colours. Throws std::runtime_error if giflib fails, and always (after checking the
// arguments) in a fuzzycsg built without giflib (FUZZYCSG_WITH_GIF=OFF; the fuzzycsg::trace
// target then defines FUZZYCSG_HAVE_GIFLIB=0, otherwise 1).
std::string encode_gif(std::span<const std::vector<std::uint8_t>> frames, int width, int height,
                       std::span<const std::array<std::uint8_t, 3>> palette, int delay_ms);
// The same with the frames made one at a time by frame(i), i = 0 .. count - 1 (so that only one
// is held at a time).
std::string encode_gif(int count, int width, int height,
                       std::span<const std::array<std::uint8_t, 3>> palette, int delay_ms,
                       const std::function<std::vector<std::uint8_t>(int)>& frame);

}  // namespace fuzzycsg::trace
