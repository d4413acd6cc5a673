#include "kc/ui/renderer.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <chrono>

#include "kc/ui/canvas.h"
#include "kc/ui/heat_field.h"

namespace kc::ui {
namespace {

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec2 aPos;
layout(location = 1) in vec2 aUv;
layout(location = 2) in vec4 aHeat;
uniform vec2 uScale;
uniform vec2 uOffset;
out vec2 vUv;
out vec4 vHeat;
void main() {
  gl_Position = vec4(aPos * uScale + uOffset, 0.0, 1.0);
  vUv = aUv;
  vHeat = aHeat;
})";

const char* kFragmentShader = R"(#version 330 core
in vec2 vUv;
in vec4 vHeat;
uniform sampler2D uTex;
uniform float uHeat;
uniform int uFlat;
uniform vec4 uColor;
out vec4 outColor;
void main() {
  if (uFlat == 1) { outColor = uColor; return; }
  if (uFlat == 2) {  // transparency checkerboard, 8 screen pixels per square
    float k = mod(floor(gl_FragCoord.x / 8.0) + floor(gl_FragCoord.y / 8.0), 2.0);
    outColor = vec4(vec3(mix(0.62, 0.80, k)), 1.0);
    return;
  }
  vec4 c = texture(uTex, vUv);
  float h = uHeat * vHeat.a;
  outColor = vec4(mix(c.rgb, vHeat.rgb, h), max(c.a, h));
})";

unsigned compile(GLenum type, const char* source, std::string& error) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    error = std::string("shader: ") + log;
  }
  return s;
}

}  // namespace

Renderer::~Renderer() {
  if (!m_program) return;
  glDeleteProgram(m_program);
  const GLuint buffers[] = {m_posBuffer, m_uvBuffer, m_heatBuffer, m_indexBuffer};
  glDeleteBuffers(4, buffers);
  glDeleteVertexArrays(1, &m_vao);
  glDeleteBuffers(2, m_quadBuffers);
  glDeleteVertexArrays(1, &m_quadVao);
  if (m_texture) glDeleteTextures(1, &m_texture);
  if (m_maskedTexture) glDeleteTextures(1, &m_maskedTexture);
}

bool Renderer::init() {
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader, m_error);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader, m_error);
  if (!m_error.empty()) return false;
  m_program = glCreateProgram();
  glAttachShader(m_program, vs);
  glAttachShader(m_program, fs);
  glLinkProgram(m_program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(m_program, GL_LINK_STATUS, &ok);
  if (!ok) {
    m_error = "shader program did not link";
    return false;
  }
  m_uScale = glGetUniformLocation(m_program, "uScale");
  m_uOffset = glGetUniformLocation(m_program, "uOffset");
  m_uHeat = glGetUniformLocation(m_program, "uHeat");
  m_uFlat = glGetUniformLocation(m_program, "uFlat");
  m_uColor = glGetUniformLocation(m_program, "uColor");
  m_uTex = glGetUniformLocation(m_program, "uTex");
  glGenVertexArrays(1, &m_vao);
  GLuint buffers[4];
  glGenBuffers(4, buffers);
  m_posBuffer = buffers[0];
  m_uvBuffer = buffers[1];
  m_heatBuffer = buffers[2];
  m_indexBuffer = buffers[3];
  glBindVertexArray(m_vao);
  glBindBuffer(GL_ARRAY_BUFFER, m_posBuffer);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, m_uvBuffer);
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(1);
  glBindBuffer(GL_ARRAY_BUFFER, m_heatBuffer);
  glVertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0, nullptr);
  glEnableVertexAttribArray(2);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_indexBuffer);
  glBindVertexArray(0);
  glGenVertexArrays(1, &m_quadVao);
  glGenBuffers(2, m_quadBuffers);
  glBindVertexArray(m_quadVao);
  for (GLuint a = 0; a < 2; ++a) {
    glBindBuffer(GL_ARRAY_BUFFER, m_quadBuffers[a]);
    glVertexAttribPointer(a, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(a);
  }
  glBindVertexArray(0);
  return true;
}

void Renderer::drawImageQuad(const AppState& state, int flat) {
  const float w = float(state.source.width), h = float(state.source.height);
  const float pos[] = {-0.5f, -0.5f, w - 0.5f, -0.5f, w - 0.5f, h - 0.5f, -0.5f, -0.5f, w - 0.5f, h - 0.5f, -0.5f, h - 0.5f};
  const float uv[] = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
  glBindVertexArray(m_quadVao);
  glBindBuffer(GL_ARRAY_BUFFER, m_quadBuffers[0]);
  glBufferData(GL_ARRAY_BUFFER, sizeof pos, pos, GL_STREAM_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, m_quadBuffers[1]);
  glBufferData(GL_ARRAY_BUFFER, sizeof uv, uv, GL_STREAM_DRAW);
  glVertexAttrib4f(2, 0.0f, 0.0f, 0.0f, 0.0f);  // no heat colour
  glUniform1i(m_uFlat, flat);
  glBindTexture(GL_TEXTURE_2D, m_texture);
  glDrawArrays(GL_TRIANGLES, 0, 6);
  glBindVertexArray(0);
}

void Renderer::uploadTexture(const Image& image, unsigned& texture) {
  if (!texture) glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

void Renderer::uploadMesh(const AppState& state, bool warped) {
  const double w = state.source.width, h = state.source.height;
  Points rest;
  std::vector<unsigned> indices;
  if (warped) {
    rest = state.mesh.restVertices();
    indices.reserve(state.mesh.triangles().size() * 3);
    for (const auto& t : state.mesh.triangles())
      for (int k : t) indices.push_back(static_cast<unsigned>(k));
  } else {  // the picture at rest: one quad
    rest.resize(4, 2);
    rest << -0.5, -0.5, w - 0.5, -0.5, w - 0.5, h - 0.5, -0.5, h - 0.5;
    indices = {0, 1, 2, 0, 2, 3};
  }
  m_vertexCount = static_cast<int>(rest.rows());
  m_indexCount = static_cast<int>(indices.size());
  m_scratch.resize(static_cast<std::size_t>(rest.rows()) * 2);
  for (Index v = 0; v < rest.rows(); ++v) {
    m_scratch[2 * v] = static_cast<float>((rest(v, 0) + 0.5) / w);
    m_scratch[2 * v + 1] = static_cast<float>((rest(v, 1) + 0.5) / h);
  }
  glBindBuffer(GL_ARRAY_BUFFER, m_uvBuffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_scratch.size() * sizeof(float)), m_scratch.data(), GL_STATIC_DRAW);
  for (Index v = 0; v < rest.rows(); ++v) {
    m_scratch[2 * v] = static_cast<float>(rest(v, 0));
    m_scratch[2 * v + 1] = static_cast<float>(rest(v, 1));
  }
  glBindBuffer(GL_ARRAY_BUFFER, m_posBuffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_scratch.size() * sizeof(float)), m_scratch.data(), GL_DYNAMIC_DRAW);
  glBindVertexArray(m_vao);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_indexBuffer);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(unsigned)), indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  std::vector<Rgba> none(static_cast<std::size_t>(m_vertexCount));
  glBindBuffer(GL_ARRAY_BUFFER, m_heatBuffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(none.size() * 4), none.data(), GL_DYNAMIC_DRAW);
}

bool Renderer::uploadHeat(AppState& state, bool warped) {
  if (!warped) return true;
  // The field's weights at the mesh vertices; a job may be holding them (try again next frame).
  if (!state.meshSource || state.meshSource->W.rows() != state.mesh.restVertices().rows()) return false;
  HeatRange range;
  std::vector<double> w = controlWeights(state.meshSource->W, state.activeControl);
  if (const ExteriorWeights* ext = state.mesh.exteriorWeights(); ext && state.activeControl >= 0)
    for (std::size_t v = 0; v < w.size(); ++v)  // pinned: outside the cage the warp uses the exterior weights
      if (ext->exterior[v]) w[v] = ext->H.coeff(Index(v), state.activeControl);
  const std::vector<Rgba> colors = heatColors(w, state.heat.log, state.heat.logFloor, range);
  state.heatLow = range.low;
  state.heatHigh = range.high;
  glBindBuffer(GL_ARRAY_BUFFER, m_heatBuffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(colors.size() * 4), colors.data(), GL_DYNAMIC_DRAW);
  return true;
}

void Renderer::draw(AppState& state, int fbWidth, int fbHeight, double displayWidth, double displayHeight) {
  if (!m_program || state.source.empty()) return;
  const auto t0 = std::chrono::steady_clock::now();
  if (m_sourceRevision != state.sourceRevision) {
    uploadTexture(state.source, m_texture);
    m_sourceRevision = state.sourceRevision;
    m_meshRevision = ~0ull;
    m_maskKey = ~0ull;
  }
  const bool warped = showsWarp(state);
  if (m_meshRevision != state.meshRevision || m_warped != warped) {
    uploadMesh(state, warped);
    m_meshRevision = state.meshRevision;
    m_warped = warped;
    m_deformKey = m_heatKey = ~0ull;
  }
  if (warped && m_deformKey != state.deformCount) {
    const Points& F = state.mesh.deformedVertices();
    m_scratch.resize(static_cast<std::size_t>(F.rows()) * 2);
    for (Index v = 0; v < F.rows(); ++v) {
      m_scratch[2 * v] = static_cast<float>(F(v, 0));
      m_scratch[2 * v + 1] = static_cast<float>(F(v, 1));
    }
    glBindBuffer(GL_ARRAY_BUFFER, m_posBuffer);
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(m_scratch.size() * sizeof(float)), m_scratch.data());
    m_deformKey = state.deformCount;
  }
  const OutsideMode outside = state.mesh.options().outside;
  const bool masked = warped && (outside == OutsideMode::Fixed || outside == OutsideMode::Transparent);
  if (masked && m_maskKey != state.meshRevision) {  // the export's mask: the bound cage's polygon
    uploadTexture(applyMask(state.source, polygonMask(state.boundCage.C, state.source.width, state.source.height)),
                  m_maskedTexture);
    m_maskKey = state.meshRevision;
  }
  const std::uint64_t heatKey = (static_cast<std::uint64_t>(state.activeControl + 1) << 1) | (state.heat.log ? 1u : 0u);
  if (warped && m_heatKey != heatKey && uploadHeat(state, warped)) m_heatKey = heatKey;
  state.timings.uploadMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  const View& v = state.view;
  const double sx = fbWidth / displayWidth, sy = fbHeight / displayHeight;
  glViewport(0, 0, fbWidth, fbHeight);
  glEnable(GL_SCISSOR_TEST);
  glScissor(static_cast<GLint>(v.canvasMin.x() * sx), static_cast<GLint>(fbHeight - (v.canvasMin.y() + v.canvasSize.y()) * sy),
            static_cast<GLsizei>(v.canvasSize.x() * sx), static_cast<GLsizei>(v.canvasSize.y() * sy));
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glUseProgram(m_program);
  const Vec2 origin = v.canvasMin + v.offset;
  glUniform2f(m_uScale, static_cast<float>(2.0 * v.zoom / displayWidth), static_cast<float>(-2.0 * v.zoom / displayHeight));
  glUniform2f(m_uOffset, static_cast<float>(origin.x() * 2.0 / displayWidth - 1.0),
              static_cast<float>(1.0 - origin.y() * 2.0 / displayHeight));
  glUniform1i(m_uTex, 0);
  glActiveTexture(GL_TEXTURE0);
  glUniform1f(m_uHeat, 0.0f);
  drawImageQuad(state, 2);  // the image rectangle: a checkerboard shows through transparent pixels
  if (warped && outside == OutsideMode::Fixed) drawImageQuad(state, 0);
  glUniform1i(m_uFlat, 0);
  glBindTexture(GL_TEXTURE_2D, masked ? m_maskedTexture : m_texture);
  const bool heat = warped && state.activeControl >= 0 &&
                    (state.tool == Tool::Brush ? state.heat.show : state.tool == Tool::Pose && state.heat.showInPose);
  glUniform1f(m_uHeat, heat ? state.heat.opacity : 0.0f);
  glUniform1i(m_uFlat, 0);
  glBindVertexArray(m_vao);
  glDrawElements(GL_TRIANGLES, m_indexCount, GL_UNSIGNED_INT, nullptr);
  if (state.show.mesh && warped) {
    glUniform1i(m_uFlat, 1);
    glUniform4f(m_uColor, 1.0f, 1.0f, 1.0f, 0.18f);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glDrawElements(GL_TRIANGLES, m_indexCount, GL_UNSIGNED_INT, nullptr);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_SCISSOR_TEST);
}

}  // namespace kc::ui
