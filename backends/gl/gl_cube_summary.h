#pragma once
// The cube's summary and check grid computed on the GPU (shaders/cube_summary.comp) and read back: 96 bytes
// and the grid instead of the whole cube.

#include <epoxy/gl.h>

#include "backends/backend.h"

namespace omnishadow::gl {

// `layers`: a 2D-array texture (or view) of the cube's six faces in face order; `sampler` must not compare.
// Fills img.cube_summary, img.cube_sample (stored values) and img.cube_sample_stride.
void read_cube_summary(GLuint program, GLuint layers, GLuint sampler, int cube_size, Images& img);

}  // namespace omnishadow::gl
