#pragma once
// The io module: files the project reads and writes.
//
//   tree_json.hpp  tree files (docs/tree-format.md): read_tree_file, read_tree_string,
//                  write_tree_file, write_tree_string.
//   points.hpp     point files (one point per line).
//   files.hpp      read_file, and write_text_file_atomic (a reader never sees half a file).
//   output_dir.hpp OutputDir: a verb's output folder replaced as a set.
//   png.hpp        encode_png.
//   canvas.hpp     a small RGB raster with lines and text, for the program's plots.

#include "fuzzycsg/io/canvas.hpp"
#include "fuzzycsg/io/files.hpp"
#include "fuzzycsg/io/output_dir.hpp"
#include "fuzzycsg/io/png.hpp"
#include "fuzzycsg/io/points.hpp"
#include "fuzzycsg/io/tree_json.hpp"
