#pragma once
// The diffcsg module: differentiable rendering of CSG of meshed primitives (Yuan et al. 2024),
// and refinement of a model's parameters against images or a mesh.
//
//   scene.hpp         Scene, scene_from_tree: leaves tessellated, tessellation bound to the
//                     parameters; PrimitiveMesh, a primitive's TriangleMesh (core) and its
//                     smoothing groups.
//   openscad_csg.hpp  OpenSCAD models (imported by the scad module) as scenes and as trees with
//                     OpenSCAD's tessellation.
//   visibility.hpp    exact CSG visibility by rays (Embree), render_visibility.
//   products.hpp      the tree as a union of products (Goldfeather normalisation).
//   shade.hpp         shading with gradients: normal and per-primitive colour images.
//   edges.hpp         intersection edges between primitives.
//   antialias.hpp     antialiasing of silhouettes with gradients (as nvdiffrast).
//   image.hpp         images and where their gradients go.
//   pipeline.hpp      the renderer whole: forward and backward.
//   targets.hpp       what refinement matches: meshes, images and their cameras (views files).
//   refine.hpp        refine: Adam or CMA-ES on the image loss.
//   refine_target.hpp what refine reads: the model (tree file or .csg) and the target (a model
//                     or mesh drawn from orbiting cameras, or a views file).
//   report.hpp        report.json of a refinement.

#include "fuzzycsg/diffcsg/antialias.hpp"
#include "fuzzycsg/diffcsg/edges.hpp"
#include "fuzzycsg/diffcsg/image.hpp"
#include "fuzzycsg/diffcsg/openscad_csg.hpp"
#include "fuzzycsg/diffcsg/pipeline.hpp"
#include "fuzzycsg/diffcsg/products.hpp"
#include "fuzzycsg/diffcsg/refine.hpp"
#include "fuzzycsg/diffcsg/refine_target.hpp"
#include "fuzzycsg/diffcsg/report.hpp"
#include "fuzzycsg/diffcsg/scene.hpp"
#include "fuzzycsg/diffcsg/shade.hpp"
#include "fuzzycsg/diffcsg/targets.hpp"
#include "fuzzycsg/diffcsg/visibility.hpp"
