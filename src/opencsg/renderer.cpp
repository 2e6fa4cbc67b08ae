#include "fuzzycsg/opencsg/renderer.hpp"

// GLEW's header must come before any other OpenGL header.
#include <GL/glew.h>
//
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <fmt/core.h>
#include <opencsg.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>

#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/diffcsg/products.hpp"

namespace fuzzycsg::opencsg {

using diffcsg::Vec3;

namespace {

// One primitive's triangles in a vertex buffer, drawn by OpenCSG and by the colour pass alike
// (the same vertices in the same order, so that GL_EQUAL matches OpenCSG's depth exactly).
class MeshPrimitive final : public OpenCSG::Primitive {
 public:
  MeshPrimitive(GLuint buffer, GLsizei vertices, OpenCSG::Operation op, unsigned convexity)
      : OpenCSG::Primitive(op, convexity), buffer_(buffer), vertices_(vertices) {}
  void render() override {
    glBindBuffer(GL_ARRAY_BUFFER, buffer_);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, nullptr);
    glDrawArrays(GL_TRIANGLES, 0, vertices_);
    glDisableClientState(GL_VERTEX_ARRAY);
    // OpenCSG draws its own quads from client memory.
    glBindBuffer(GL_ARRAY_BUFFER, 0);
  }

 private:
  GLuint buffer_;
  GLsizei vertices_;
};

// 1 for a convex mesh (every vertex behind or on every face's plane); otherwise a bound on the
// front faces a ray can cross (its triangle count, at most OpenCSG's 255 stencil layers).
int mesh_convexity(const TriangleMesh& m) {
  double size = 0;
  for (const Vec3& v : m.vertices)
    size = std::max({size, std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  for (const auto& t : m.triangles) {
    const Vec3& a = m.vertices[static_cast<std::size_t>(t[0])];
    const Vec3 n = diffcsg::cross(diffcsg::sub(m.vertices[static_cast<std::size_t>(t[1])], a),
                                  diffcsg::sub(m.vertices[static_cast<std::size_t>(t[2])], a));
    const double tolerance = 1e-9 * std::sqrt(diffcsg::dot(n, n)) * std::max(size, 1e-300);
    for (const Vec3& v : m.vertices) {
      if (diffcsg::dot(n, diffcsg::sub(v, a)) > tolerance) {
        return static_cast<int>(std::min<std::size_t>(m.triangles.size(), 255));
      }
    }
  }
  return 1;
}

std::atomic<int> next_context{1};

}  // namespace

struct Renderer::State {
  int width = 0, height = 0;
  int opencsg_context = 0;
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  GLuint framebuffer = 0, colour = 0, depth = 0;
  struct Mesh {
    GLuint buffer = 0;
    GLsizei vertices = 0;
    int convexity = 1;
  };
  std::vector<Mesh> meshes;
  std::vector<diffcsg::Product> products;
  std::vector<Vec3> points;  // every vertex, for the depth range

  void make_current() const {
    if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE) {
      throw Error(
          fmt::format("OpenCSG renderer: eglMakeCurrent failed (EGL error 0x{:x})", eglGetError()));
    }
    OpenCSG::setContext(opencsg_context);
  }
  void release_meshes() {
    for (const Mesh& m : meshes) glDeleteBuffers(1, &m.buffer);
    meshes.clear();
  }
};

Renderer::Renderer(int width, int height) : state_(std::make_unique<State>()) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384) {
    throw InputError(fmt::format("OpenCSG renderer: {}x{} pixels: out of range", width, height));
  }
  State& s = *state_;
  s.width = width;
  s.height = height;
  s.opencsg_context = next_context++;
  const auto fail = [](const std::string& what) {
    throw Error(fmt::format(
        "OpenCSG renderer: no OpenGL context from Mesa's surfaceless EGL platform: {} (EGL "
        "error 0x{:x}; needs libegl-mesa0 and libgl1-mesa-dri)",
        what, eglGetError()));
  };
  const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) fail("no eglGetPlatformDisplayEXT");
  s.display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (s.display == EGL_NO_DISPLAY) fail("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
  EGLint major = 0, minor = 0;
  if (eglInitialize(s.display, &major, &minor) != EGL_TRUE) fail("eglInitialize");
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) fail("eglBindAPI(EGL_OPENGL_API)");
  // The surfaceless platform's configs are for pbuffers (the default asks for windows); the
  // drawing goes to a framebuffer object, with no surface at all.
  const EGLint attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                               EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  if (eglChooseConfig(s.display, attributes, &config, 1, &configs) != EGL_TRUE || configs < 1) {
    fail("no EGL config renders desktop OpenGL");
  }
  // A compatibility profile (the default): OpenCSG draws with the fixed-function pipeline.
  s.context = eglCreateContext(s.display, config, EGL_NO_CONTEXT, nullptr);
  if (s.context == EGL_NO_CONTEXT) fail("eglCreateContext");
  s.make_current();
  // GLEW (built for GLX) loads every entry point, then reports that there is no GLX display.
  const GLenum glew = glewInit();
  if (glew != GLEW_OK && glew != GLEW_ERROR_NO_GLX_DISPLAY) {
    throw Error(fmt::format("OpenCSG renderer: glewInit failed: {}",
                            reinterpret_cast<const char*>(glewGetErrorString(glew))));
  }
  if (!GLEW_ARB_framebuffer_object) {
    throw Error("OpenCSG renderer: the OpenGL context lacks GL_ARB_framebuffer_object");
  }
  glGenFramebuffers(1, &s.framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, s.framebuffer);
  glGenRenderbuffers(1, &s.colour);
  glBindRenderbuffer(GL_RENDERBUFFER, s.colour);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, s.colour);
  glGenRenderbuffers(1, &s.depth);
  glBindRenderbuffer(GL_RENDERBUFFER, s.depth);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, s.depth);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw Error("OpenCSG renderer: the framebuffer object is incomplete");
  }
}

Renderer::~Renderer() {
  State& s = *state_;
  if (s.context == EGL_NO_CONTEXT) return;
  if (eglMakeCurrent(s.display, EGL_NO_SURFACE, EGL_NO_SURFACE, s.context) == EGL_TRUE) {
    OpenCSG::setContext(s.opencsg_context);
    OpenCSG::freeResources();
    s.release_meshes();
    glDeleteRenderbuffers(1, &s.colour);
    glDeleteRenderbuffers(1, &s.depth);
    glDeleteFramebuffers(1, &s.framebuffer);
    eglMakeCurrent(s.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  // The display is shared by every renderer of the process and is not terminated.
  eglDestroyContext(s.display, s.context);
}

void Renderer::set_scene(const diffcsg::Scene& scene) {
  State& s = *state_;
  s.make_current();
  if (scene.primitives.size() >= (1u << 24) - 1) {
    throw InputError("OpenCSG renderer: too many primitives for 24-bit colour ids");
  }
  s.products = diffcsg::sum_of_products(scene);
  s.release_meshes();
  s.points.clear();
  for (const diffcsg::PrimitiveMesh& primitive : scene.primitives) {
    const TriangleMesh& m = primitive.mesh;
    std::vector<float> data;
    data.reserve(m.triangles.size() * 9);
    for (const auto& t : m.triangles) {
      for (const int v : t) {
        for (const double c : m.vertices[static_cast<std::size_t>(v)]) {
          data.push_back(static_cast<float>(c));
        }
      }
    }
    State::Mesh mesh;
    glGenBuffers(1, &mesh.buffer);
    glBindBuffer(GL_ARRAY_BUFFER, mesh.buffer);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(),
                 GL_STATIC_DRAW);
    mesh.vertices = static_cast<GLsizei>(m.triangles.size() * 3);
    mesh.convexity = mesh_convexity(m);
    s.meshes.push_back(mesh);
    s.points.insert(s.points.end(), m.vertices.begin(), m.vertices.end());
  }
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

std::vector<int> Renderer::convexity() const {
  std::vector<int> out;
  for (const State::Mesh& m : state_->meshes) out.push_back(m.convexity);
  return out;
}

void Renderer::draw(const diffcsg::Camera& camera, Algorithm algorithm) {
  State& s = *state_;
  if (camera.width != s.width || camera.height != s.height) {
    throw InputError(fmt::format("OpenCSG renderer: camera of {}x{} pixels, renderer of {}x{}",
                                 camera.width, camera.height, s.width, s.height));
  }
  if (algorithm == Algorithm::kScs) {
    for (std::size_t p = 0; p < s.meshes.size(); ++p) {
      if (s.meshes[p].convexity != 1) {
        throw InputError(fmt::format(
            "OpenCSG renderer: SCS draws convex primitives only (primitive {} is not)", p));
      }
    }
  }
  s.make_current();
  glBindFramebuffer(GL_FRAMEBUFFER, s.framebuffer);
  glViewport(0, 0, s.width, s.height);
  glDisable(GL_DITHER);
  glDisable(GL_LIGHTING);
  glDisable(GL_BLEND);
  glShadeModel(GL_FLAT);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glClearColor(0, 0, 0, 0);
  glClearDepth(1);
  glClearStencil(0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);

  // The camera's frame: x right, y up, looking down -z; the depth range spans the scene.
  Vec3 forward, right, up;
  camera.axes(forward, right, up);
  double nearest = std::numeric_limits<double>::infinity(), farthest = 0;
  for (const Vec3& p : s.points) {
    const double z = diffcsg::dot(diffcsg::sub(p, camera.eye), forward);
    nearest = std::min(nearest, z);
    farthest = std::max(farthest, z);
  }
  if (!(farthest > 0)) {
    glFinish();
    return;
  }
  const double far = farthest * 1.01, near = std::max(nearest * 0.99, far * 1e-5);
  const double f = 1 / std::tan(camera.fov_deg * std::numbers::pi / 360);
  const double aspect = static_cast<double>(s.width) / s.height;
  // Column-major, as glLoadMatrixd takes them.
  // clang-format off
  const double projection[16] = {
      f / aspect, 0, 0, 0,
      0, f, 0, 0,
      0, 0, (far + near) / (near - far), -1,
      0, 0, 2 * far * near / (near - far), 0};
  const double modelview[16] = {
      right[0], up[0], -forward[0], 0,
      right[1], up[1], -forward[1], 0,
      right[2], up[2], -forward[2], 0,
      -diffcsg::dot(right, camera.eye), -diffcsg::dot(up, camera.eye),
      diffcsg::dot(forward, camera.eye), 1};
  // clang-format on
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixd(projection);
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixd(modelview);

  OpenCSG::setOption(OpenCSG::AlgorithmSetting,
                     algorithm == Algorithm::kScs ? OpenCSG::SCS : OpenCSG::Goldfeather);
  OpenCSG::setOption(OpenCSG::DepthComplexitySetting, OpenCSG::NoDepthComplexitySampling);
  OpenCSG::setOption(OpenCSG::OffscreenSetting, OpenCSG::FrameBufferObject);
  for (const diffcsg::Product& product : s.products) {
    std::vector<std::unique_ptr<MeshPrimitive>> owned;
    std::vector<OpenCSG::Primitive*> primitives;
    for (const diffcsg::ProductTerm& t : product) {
      const State::Mesh& m = s.meshes[static_cast<std::size_t>(t.primitive)];
      owned.push_back(std::make_unique<MeshPrimitive>(
          m.buffer, m.vertices, t.subtracted ? OpenCSG::Subtraction : OpenCSG::Intersection,
          static_cast<unsigned>(m.convexity)));
      primitives.push_back(owned.back().get());
    }
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    OpenCSG::render(primitives);
    // OpenCSG leaves the depth test as it needed it: the colour pass wants it on, GL_EQUAL.
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_EQUAL);
    glEnable(GL_CULL_FACE);
    for (std::size_t k = 0; k < product.size(); ++k) {
      const std::uint32_t id = static_cast<std::uint32_t>(product[k].primitive) + 1;
      glColor4ub(static_cast<GLubyte>(id & 0xff), static_cast<GLubyte>((id >> 8) & 0xff),
                 static_cast<GLubyte>((id >> 16) & 0xff), 255);
      glCullFace(product[k].subtracted ? GL_FRONT : GL_BACK);
      owned[k]->render();
    }
    glDisable(GL_CULL_FACE);
    glDepthFunc(GL_LESS);
  }
  glFinish();
  if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
    throw Error(fmt::format("OpenCSG renderer: OpenGL error 0x{:x} while drawing", e));
  }
}

std::vector<int> Renderer::read_primitives() const {
  const State& s = *state_;
  s.make_current();
  glBindFramebuffer(GL_FRAMEBUFFER, s.framebuffer);
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(s.width) * s.height * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, s.width, s.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  std::vector<int> out(static_cast<std::size_t>(s.width) * s.height);
  for (int j = 0; j < s.height; ++j) {
    const std::uint8_t* row = &rgba[static_cast<std::size_t>(s.height - 1 - j) * s.width * 4];
    for (int i = 0; i < s.width; ++i) {
      const std::uint8_t* c = row + static_cast<std::size_t>(i) * 4;
      const int id = c[0] | (c[1] << 8) | (c[2] << 16);
      out[static_cast<std::size_t>(j) * s.width + i] = id - 1;
    }
  }
  return out;
}

std::vector<int> Renderer::render(const diffcsg::Camera& camera, Algorithm algorithm) {
  draw(camera, algorithm);
  return read_primitives();
}

std::string Renderer::description() const {
  state_->make_current();
  const auto text = [](GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  return text(GL_RENDERER) + ", " + text(GL_VERSION);
}

}  // namespace fuzzycsg::opencsg
