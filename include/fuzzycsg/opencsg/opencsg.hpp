#pragma once
// The opencsg module: the scenes of diffcsg drawn by OpenCSG in an offscreen OpenGL context, an
// independent renderer to check diffcsg's images and speed against (tests and benchmarks).
//
//   renderer.hpp  opencsg::Renderer.

#include "fuzzycsg/opencsg/renderer.hpp"
