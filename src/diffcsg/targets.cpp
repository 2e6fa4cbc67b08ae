#include "fuzzycsg/diffcsg/targets.hpp"

#include <fmt/core.h>
#include <stb_image.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/png.hpp"
#include "fuzzycsg/target/mesh_file.hpp"

namespace fuzzycsg::diffcsg {

namespace {

struct StbFree {
  void operator()(unsigned char* p) const { stbi_image_free(p); }
};

}  // namespace

Scene read_mesh_scene(const std::filesystem::path& path, double crease_degrees) {
  TriangleMesh m = read_mesh_file(path);
  const double volume = signed_volume(m);
  double extent = 0;
  for (const Vec3& v : m.vertices)
    extent = std::max({extent, std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  // Six times the volume against 1e-12 of the cube of the extent.
  if (!(6 * std::abs(volume) > 1e-12 * extent * extent * extent)) {
    throw InputError(fmt::format("{}: the mesh encloses no volume", path.string()));
  }
  if (volume < 0) {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  }
  return scene_from_mesh(std::move(m), crease_degrees);
}

std::string encode_image_png(const Image& image, Shading shading) {
  if (image.channels != 3) throw Error("encode_image_png: 3 channels expected");
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  std::vector<unsigned char> rgba(pixels * 4, 0);
  for (std::size_t p = 0; p < pixels; ++p) {
    const float* c = image.at(p);
    if (c[0] == 0 && c[1] == 0 && c[2] == 0) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      const double v = shading == Shading::kNormals ? (c[k] + 1) / 2 : c[k];
      rgba[p * 4 + k] = static_cast<unsigned char>(std::lround(std::clamp(v, 0.0, 1.0) * 255));
    }
    rgba[p * 4 + 3] = 255;
  }
  return encode_png(image.width, image.height, 4, rgba);
}

Image read_image_png(const std::filesystem::path& path, Shading shading) {
  const std::string bytes = io::read_file(path);
  int w = 0, h = 0, channels = 0;
  const auto* data_in = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int size = static_cast<int>(std::min<std::size_t>(bytes.size(), 1u << 30));
  if (stbi_info_from_memory(data_in, size, &w, &h, &channels) &&
      static_cast<long long>(w) * h > (1ll << 26)) {
    throw InputError(fmt::format("{}: {}x{} pixels is too large", path.string(), w, h));
  }
  std::unique_ptr<unsigned char, StbFree> data(
      stbi_load_from_memory(data_in, size, &w, &h, &channels, 4));
  if (!data) {
    const char* reason = stbi_failure_reason();
    throw InputError(fmt::format("{}: cannot read image ({})", path.string(),
                                 reason ? reason : "unknown error"));
  }
  Image img{w, h, 3, std::vector<float>(static_cast<std::size_t>(w) * h * 3, 0.0f)};
  for (std::size_t p = 0; p < static_cast<std::size_t>(w) * h; ++p) {
    const unsigned char* c = data.get() + p * 4;
    if (c[3] < 128) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      const float v = c[k] / 255.0f;
      img.at(p)[k] = shading == Shading::kNormals ? 2 * v - 1 : v;
    }
  }
  return img;
}

bool is_views_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return false;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    return j.is_object() && j.value("format", std::string()) == "fuzzycsg-views";
  } catch (const nlohmann::json::exception&) {
    return false;
  }
}

ViewSet read_views(const std::filesystem::path& path) {
  const std::string file = path.string();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(io::read_file(path));
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(fmt::format("{}: not JSON (byte {})", file, e.byte));
  }
  const auto fail = [&](const std::string& where, const std::string& what) {
    throw InputError(fmt::format("{}: {}: {}", file, where, what));
  };
  if (!j.is_object() || j.value("format", std::string()) != "fuzzycsg-views") {
    fail("format", "\"fuzzycsg-views\" expected");
  }
  if (!j.contains("version") || j["version"] != 1) fail("version", "1 expected");
  ViewSet out;
  if (j.contains("shading")) {
    const auto s = j["shading"].is_string() ? shading_from_name(j["shading"].get<std::string>())
                                            : std::nullopt;
    if (!s) fail("shading", "\"normals\" or \"colours\" expected");
    out.shading = *s;
  }
  if (!j.contains("views") || !j["views"].is_array() || j["views"].empty()) {
    fail("views", "a non-empty list expected");
  }
  const auto vec3 = [&](const nlohmann::json& v, const std::string& where) {
    if (!v.is_array() || v.size() != 3) fail(where, "three numbers expected");
    Vec3 out3{};
    for (std::size_t k = 0; k < 3; ++k) {
      if (!v[k].is_number() || !std::isfinite(v[k].get<double>()))
        fail(where, "three numbers expected");
      out3[k] = v[k].get<double>();
    }
    return out3;
  };
  const std::filesystem::path dir = path.parent_path();
  for (std::size_t k = 0; k < j["views"].size(); ++k) {
    const nlohmann::json& v = j["views"][k];
    const std::string at = fmt::format("views[{}]", k);
    if (!v.is_object()) fail(at, "an object expected");
    if (!v.contains("image") || !v["image"].is_string())
      fail(at + ".image", "a file name expected");
    for (const auto& [key, value] : v.items()) {
      if (key != "image" && key != "eye" && key != "target" && key != "up" && key != "fov" &&
          key != "size") {
        fail(at, fmt::format("unknown field \"{}\"", key));
      }
    }
    Camera c;
    if (!v.contains("eye")) fail(at, "missing field \"eye\"");
    if (!v.contains("target")) fail(at, "missing field \"target\"");
    c.eye = vec3(v["eye"], at + ".eye");
    c.target = vec3(v["target"], at + ".target");
    c.up = v.contains("up") ? vec3(v["up"], at + ".up") : Vec3{0, 0, 1};
    if (v.contains("fov")) {
      if (!v["fov"].is_number()) fail(at + ".fov", "a number expected");
      c.fov_deg = v["fov"].get<double>();
    } else {
      c.fov_deg = 30;
    }
    if (!(c.fov_deg > 0 && c.fov_deg < 180)) fail(at + ".fov", "must be in (0, 180) degrees");
    if (dot(sub(c.target, c.eye), sub(c.target, c.eye)) == 0) fail(at, "the eye is at the target");
    if (dot(c.up, c.up) == 0) fail(at + ".up", "must not be 0");
    const std::filesystem::path image = dir / v["image"].get<std::string>();
    Image img = read_image_png(image, out.shading);
    if (v.contains("size")) {
      const nlohmann::json& s = v["size"];
      if (!s.is_array() || s.size() != 2 || !s[0].is_number_integer() ||
          !s[1].is_number_integer()) {
        fail(at + ".size", "[width, height] expected");
      }
      if (s[0].get<int>() != img.width || s[1].get<int>() != img.height) {
        fail(at + ".size", fmt::format("{}x{}, but {} is {}x{}", s[0].get<int>(), s[1].get<int>(),
                                       image.string(), img.width, img.height));
      }
    }
    c.width = img.width;
    c.height = img.height;
    out.cameras.push_back(c);
    out.images.push_back(std::move(img));
  }
  return out;
}

std::string views_json(Shading shading, const std::vector<Camera>& cameras,
                       const std::vector<std::string>& image_files) {
  nlohmann::ordered_json j;
  j["format"] = "fuzzycsg-views";
  j["version"] = 1;
  j["shading"] = std::string(shading_name(shading));
  j["views"] = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < cameras.size() && k < image_files.size(); ++k) {
    const Camera& c = cameras[k];
    nlohmann::ordered_json v;
    v["image"] = image_files[k];
    v["eye"] = c.eye;
    v["target"] = c.target;
    v["up"] = c.up;
    v["fov"] = c.fov_deg;
    v["size"] = {c.width, c.height};
    j["views"].push_back(std::move(v));
  }
  return j.dump(2) + "\n";
}

}  // namespace fuzzycsg::diffcsg
