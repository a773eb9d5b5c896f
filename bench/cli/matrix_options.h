#pragma once
// `run`'s matrix axes on the command line: what is drawn and at what size (backends, scenes, cube and frame
// sizes), the point lights' count and grouping, and how it is drawn (technique, filter, storage, layout and
// what tunes them). Each is a comma list bound to its MatrixSpec field, whose initial value is the default
// shown.

#include <CLI/CLI.hpp>

#include "bench/run/matrix.h"

namespace omnishadow::bench {

void add_matrix_options(CLI::App& run, MatrixSpec& m);

}  // namespace omnishadow::bench
