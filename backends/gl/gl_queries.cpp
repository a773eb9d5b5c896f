#include "backends/gl/gl_queries.h"

namespace omnishadow::gl {
namespace {

// GL_ARB_pipeline_statistics_query targets, in the order PassCounters lists them.
constexpr std::array<GLenum, 8> kStatisticTargets = {
    GL_VERTICES_SUBMITTED_ARB,         GL_PRIMITIVES_SUBMITTED_ARB,
    GL_VERTEX_SHADER_INVOCATIONS_ARB,  GL_GEOMETRY_SHADER_INVOCATIONS,
    GL_GEOMETRY_SHADER_PRIMITIVES_EMITTED_ARB, GL_CLIPPING_INPUT_PRIMITIVES_ARB,
    GL_CLIPPING_OUTPUT_PRIMITIVES_ARB, GL_FRAGMENT_SHADER_INVOCATIONS_ARB};

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

double FrameQueries::timer_ms(Pass pass) const { return static_cast<double>(result_of(timers_[pass])) * 1e-6; }

void FrameQueries::begin_statistics(Pass pass) {
  for (int k = 0; k < kStatisticCount; ++k) glBeginQuery(kStatisticTargets[k], statistics_[pass][k]);
}

void FrameQueries::end_statistics() {
  for (GLenum target : kStatisticTargets) glEndQuery(target);
}

PassCounters FrameQueries::statistics(Pass pass) const {
  PassCounters c;
  if (!has_statistics_) return c;
  const auto& q = statistics_[pass];
  c.valid = true;
  c.vertices_submitted = result_of(q[0]);
  c.primitives_submitted = result_of(q[1]);
  c.vs_invocations = result_of(q[2]);
  c.gs_invocations = result_of(q[3]);
  c.gs_primitives = result_of(q[4]);
  c.clipping_input = result_of(q[5]);
  c.clipping_output = result_of(q[6]);
  c.fs_invocations = result_of(q[7]);
  return c;
}

}  // namespace omnishadow::gl
