#include "backends/gl/gl_queries.h"

namespace omnishadow::gl {
namespace {

// The shared table's GL targets, checked against GL's own names (in the table's order).
constexpr GLenum kTargets[] = {GL_VERTICES_SUBMITTED_ARB,
                               GL_PRIMITIVES_SUBMITTED_ARB,
                               GL_VERTEX_SHADER_INVOCATIONS_ARB,
                               GL_GEOMETRY_SHADER_INVOCATIONS,
                               GL_GEOMETRY_SHADER_PRIMITIVES_EMITTED_ARB,
                               GL_CLIPPING_INPUT_PRIMITIVES_ARB,
                               GL_CLIPPING_OUTPUT_PRIMITIVES_ARB,
                               GL_FRAGMENT_SHADER_INVOCATIONS_ARB};
constexpr bool table_matches_gl() {
  for (size_t k = 0; k < kPipelineStatistics.size(); ++k)
    if (kPipelineStatistics[k].gl_target != kTargets[k]) return false;
  return std::size(kTargets) == kPipelineStatistics.size();
}
static_assert(table_matches_gl());

uint64_t result_of(GLuint query) {
  GLuint64 value = 0;
  glGetQueryObjectui64v(query, GL_QUERY_RESULT, &value);
  return value;
}

}  // namespace

FrameQueries::FrameQueries(bool has_pipeline_statistics) : has_statistics_(has_pipeline_statistics) {
  glCreateQueries(GL_TIME_ELAPSED, kPassCount, timers_.data());
  // glGenQueries, not glCreateQueries: Mesa 22.3 rejects the ARB statistics targets in glCreateQueries
  // (GL_INVALID_ENUM) while accepting them in glBeginQuery. The first glBeginQuery gives each its target.
  if (has_statistics_)
    for (auto& pass : statistics_) glGenQueries(kStatisticCount, pass.data());
}

FrameQueries::~FrameQueries() {
  glDeleteQueries(kPassCount, timers_.data());
  if (has_statistics_)
    for (auto& pass : statistics_) glDeleteQueries(kStatisticCount, pass.data());
}

double FrameQueries::timer_ms(Pass pass) const {
  return static_cast<double>(result_of(timers_[pass])) * 1e-6;
}

void FrameQueries::begin_statistics(Pass pass) {
  for (int k = 0; k < kStatisticCount; ++k)
    glBeginQuery(kPipelineStatistics[k].gl_target, statistics_[pass][k]);
}

void FrameQueries::end_statistics() {
  for (const PipelineStatistic& s : kPipelineStatistics) glEndQuery(s.gl_target);
}

PassCounters FrameQueries::statistics(Pass pass) const {
  PassCounters c;
  if (!has_statistics_) return c;
  const auto& q = statistics_[pass];
  c.valid = true;
  for (size_t k = 0; k < kPipelineStatistics.size(); ++k) c.*kPipelineStatistics[k].member = result_of(q[k]);
  return c;
}

}  // namespace omnishadow::gl
