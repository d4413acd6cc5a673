#include "kc/ui/renderer.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "kc/ui/buffer_updates.h"
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

// vUv is the rest position in the picture ([0, 1]², pixel edges): the display texture covers all
// of it, the detail texture the rectangle uDetailRect (u0, v0, u1, v1) and wins where it covers.
const char* kFragmentShader = R"(#version 330 core
in vec2 vUv;
in vec4 vHeat;
uniform sampler2D uTex;
uniform sampler2D uDetail;
uniform vec4 uDetailRect;
uniform int uUseDetail;
uniform sampler2D uMask;
uniform int uMasked;
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
  if (uUseDetail == 1) {
    vec2 d = (vUv - uDetailRect.xy) / (uDetailRect.zw - uDetailRect.xy);
    vec4 cd = texture(uDetail, d);
    if (all(greaterThanEqual(d, vec2(0.0))) && all(lessThanEqual(d, vec2(1.0)))) c = cd;
  }
  if (uMasked == 1) c.a *= texture(uMask, vUv).r;
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

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// Runs closer than this many equal elements are sent as one glBufferSubData.
constexpr std::size_t kRunGap = 256;

}  // namespace

Renderer::~Renderer() {
  if (!m_program) return;
  glDeleteProgram(m_program);
  const GLuint buffers[] = {m_posBuffer, m_uvBuffer, m_heatBuffer, m_indexBuffer};
  glDeleteBuffers(4, buffers);
  glDeleteVertexArrays(1, &m_vao);
  glDeleteBuffers(2, m_quadBuffers);
  glDeleteVertexArrays(1, &m_quadVao);
  for (unsigned t : {m_display.id, m_detail.id, m_maskTexture})
    if (t) glDeleteTextures(1, &t);
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
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &m_maxTextureSize);
  m_uScale = glGetUniformLocation(m_program, "uScale");
  m_uOffset = glGetUniformLocation(m_program, "uOffset");
  m_uHeat = glGetUniformLocation(m_program, "uHeat");
  m_uFlat = glGetUniformLocation(m_program, "uFlat");
  m_uColor = glGetUniformLocation(m_program, "uColor");
  m_uTex = glGetUniformLocation(m_program, "uTex");
  m_uDetail = glGetUniformLocation(m_program, "uDetail");
  m_uDetailRect = glGetUniformLocation(m_program, "uDetailRect");
  m_uUseDetail = glGetUniformLocation(m_program, "uUseDetail");
  m_uMask = glGetUniformLocation(m_program, "uMask");
  m_uMasked = glGetUniformLocation(m_program, "uMasked");
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

template <class T>
std::size_t Renderer::uploadChanged(unsigned buffer, std::vector<T>& shadow, const std::vector<T>& next, unsigned target) {
  glBindBuffer(target, buffer);
  const std::size_t bytes = next.size() * sizeof(T);
  if (shadow.size() != next.size()) {
    glBufferData(target, static_cast<GLsizeiptr>(bytes), next.data(), GL_DYNAMIC_DRAW);
    shadow = next;
    return bytes;
  }
  std::size_t sent = 0;
  for (const ElementRun& r : changedRuns(shadow.data(), next.data(), next.size(), sizeof(T), kRunGap)) {
    const std::size_t n = (r.second - r.first) * sizeof(T);
    glBufferSubData(target, static_cast<GLintptr>(r.first * sizeof(T)), static_cast<GLsizeiptr>(n), next.data() + r.first);
    std::copy(next.begin() + static_cast<std::ptrdiff_t>(r.first), next.begin() + static_cast<std::ptrdiff_t>(r.second),
              shadow.begin() + static_cast<std::ptrdiff_t>(r.first));
    sent += n;
  }
  return sent;
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
  bindPicture(false);
  glDrawArrays(GL_TRIANGLES, 0, 6);
  glBindVertexArray(0);
}

void Renderer::uploadImage(const Image& image, PictureTexture& texture, bool mipmaps) {
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  // Mipmaps made on the CPU: glGenerateMipmap is slow in a software OpenGL (display_texture.h).
  // Storage for all levels at once (a level added to a defined texture can make the driver copy
  // it), allocated level by level with glTexImage2D: glTexStorage2D needs OpenGL 4.2 and the
  // window asks for 3.3.
  const std::vector<Image> levels = mipmaps ? mipmapLevels(image) : std::vector<Image>{};
  if (texture.width != image.width || texture.height != image.height || texture.levels != int(levels.size()) + 1) {
    glDeleteTextures(1, &texture.id);  // a new size is a new texture
    glGenTextures(1, &texture.id);
    glBindTexture(GL_TEXTURE_2D, texture.id);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    for (std::size_t k = 0; k < levels.size(); ++k)
      glTexImage2D(GL_TEXTURE_2D, static_cast<GLint>(k) + 1, GL_RGBA8, levels[k].width, levels[k].height, 0, GL_RGBA,
                   GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, static_cast<GLint>(levels.size()));
  } else {
    glBindTexture(GL_TEXTURE_2D, texture.id);
  }
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
  for (std::size_t k = 0; k < levels.size(); ++k)
    glTexSubImage2D(GL_TEXTURE_2D, static_cast<GLint>(k) + 1, 0, 0, levels[k].width, levels[k].height, GL_RGBA, GL_UNSIGNED_BYTE,
                    levels[k].rgba.data());
  texture.levels = static_cast<int>(levels.size()) + 1;
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, mipmaps ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  texture.width = image.width;
  texture.height = image.height;
}

void Renderer::updateDisplayTexture(AppState& state, int limit) {
  const auto t0 = std::chrono::steady_clock::now();
  const Image& source = state.source;
  const auto [w, h] = displayTextureSize(source.width, source.height, limit);
  if (w == source.width && h == source.height) uploadImage(source, m_display, true);  // small enough: as it is
  else uploadImage(displayImage(source, limit), m_display, true);
  m_display.rect = {0, 0, source.width, source.height};
  m_display.scale = double(w) / source.width;
  m_displayLimit = limit;
  m_detail.rect = {};  // the detail and the mask were of the previous picture or size
  m_maskCage.resize(0, 2);
  state.display = {w, h, 0, 0, 0.0};
  state.timings.textureMs = msSince(t0);
}

void Renderer::updateMask(const AppState& state) {
  const Points& C = state.bound->cage.C;
  if (m_maskTexture && m_maskCage.rows() == C.rows() && m_maskCage == C) return;
  // The cage's polygon at the display texture's resolution: texel centre i is at picture
  // x = (i + 0.5)/scale − 0.5.
  const double sx = double(m_display.width) / state.source.width, sy = double(m_display.height) / state.source.height;
  Points scaled(C.rows(), 2);
  for (Index i = 0; i < C.rows(); ++i) scaled.row(i) << (C(i, 0) + 0.5) * sx - 0.5, (C(i, 1) + 0.5) * sy - 0.5;
  const std::vector<std::uint8_t> mask = polygonMask(scaled, m_display.width, m_display.height);
  if (!m_maskTexture) glGenTextures(1, &m_maskTexture);
  glBindTexture(GL_TEXTURE_2D, m_maskTexture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, m_display.width, m_display.height, 0, GL_RED, GL_UNSIGNED_BYTE, mask.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  m_maskCage = C;
}

void Renderer::updateDetailTexture(AppState& state, double texelsPerPixel, bool warped) {
  const View& v = state.view;
  const bool moved = v.zoom != m_viewZoom || v.offset != m_viewOffset || m_viewPose != state.poseVersion;
  m_viewZoom = v.zoom;
  m_viewOffset = v.offset;
  m_viewPose = state.poseVersion;
  const double want = std::min(1.0, texelsPerPixel);
  if (want <= m_display.scale * 1.05) {  // the display texture shows all the screen can
    m_detail.rect = {};
    return;
  }
  // Built once the view, the pose and the mouse are still (the frame after the last change):
  // meanwhile the last detail texture is drawn where it covers, the display texture elsewhere.
  if (moved || state.canvasDrag.button >= 0) {
    state.frameWanted = true;
    return;
  }
  const int W = state.source.width, H = state.source.height;
  // The rest-position rectangle of the picture on screen (around the canvas by `margin` of its size).
  auto restRegion = [&](double margin) {
    const Vec2 a = v.toImage(v.canvasMin - margin * v.canvasSize), b = v.toImage(v.canvasMin + (1.0 + margin) * v.canvasSize);
    Vec2 lo = a.cwiseMin(b), hi = a.cwiseMax(b);
    if (warped) {
      const Points& F = state.mesh.deformedVertices();
      const Points& R = state.mesh.restVertices();
      const double pad = 2.0 * state.mesh.options().spacing;  // a triangle reaching in from outside
      for (Index i = 0; i < F.rows(); ++i)
        if (F(i, 0) >= a.x() && F(i, 0) <= b.x() && F(i, 1) >= a.y() && F(i, 1) <= b.y()) {
          lo = lo.cwiseMin(R.row(i).transpose() - Vec2(pad, pad));
          hi = hi.cwiseMax(R.row(i).transpose() + Vec2(pad, pad));
        }
    }
    PixelRect r;
    r.x0 = std::clamp(static_cast<int>(std::floor(lo.x() + 0.5)), 0, W);
    r.y0 = std::clamp(static_cast<int>(std::floor(lo.y() + 0.5)), 0, H);
    r.width = std::clamp(static_cast<int>(std::ceil(hi.x() + 0.5)), 0, W) - r.x0;
    r.height = std::clamp(static_cast<int>(std::ceil(hi.y() + 0.5)), 0, H) - r.y0;
    return r;
  };
  const PixelRect need = restRegion(0.05);
  if (need.empty()) return;
  const PixelRect& have = m_detail.rect;
  const bool covers = !have.empty() && have.x0 <= need.x0 && have.y0 <= need.y0 &&
                      have.x0 + have.width >= need.x0 + need.width && have.y0 + have.height >= need.y0 + need.height;
  // Within 5% of the wanted scale is kept, except at 100% and beyond: there a detail short of full
  // resolution (made on the way in, one wheel step per frame) blurs one-pixel detail.
  if (covers && m_detail.scale >= 0.95 * want && (want < 1.0 || m_detail.scale >= 1.0)) return;
  const auto t0 = std::chrono::steady_clock::now();
  const PixelRect crop = restRegion(0.3);
  const double scale = std::min(want, double(m_displayLimit) / std::max(crop.width, crop.height));
  if (covers && scale <= m_detail.scale) return;  // nothing finer fits the texture limit
  const int ow = std::clamp(static_cast<int>(std::lround(crop.width * scale)), 1, crop.width);
  const int oh = std::clamp(static_cast<int>(std::lround(crop.height * scale)), 1, crop.height);
  if (scale <= m_display.scale * 1.05) return;  // no finer than the display texture
  uploadImage(resampleArea(state.source, crop, ow, oh), m_detail, false);
  m_detail.rect = crop;
  m_detail.scale = scale;
  state.timings.detailMs = msSince(t0);
}

void Renderer::bindPicture(bool masked) {
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, m_display.id);
  glUniform1i(m_uTex, 0);
  const bool detail = !m_detail.rect.empty();
  glUniform1i(m_uUseDetail, detail ? 1 : 0);
  if (detail) {
    const PixelRect& r = m_detail.rect;
    const double W = m_display.rect.width, H = m_display.rect.height;
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, m_detail.id);
    glUniform1i(m_uDetail, 1);
    glUniform4f(m_uDetailRect, float(r.x0 / W), float(r.y0 / H), float((r.x0 + r.width) / W), float((r.y0 + r.height) / H));
  }
  glUniform1i(m_uMasked, masked ? 1 : 0);
  if (masked) {
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, m_maskTexture);
    glUniform1i(m_uMask, 2);
  }
  glActiveTexture(GL_TEXTURE0);
}

void Renderer::uploadMesh(AppState& state, bool warped) {
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
  m_indexCount = static_cast<int>(indices.size());
  std::vector<float> uv(static_cast<std::size_t>(rest.rows()) * 2);
  for (Index v = 0; v < rest.rows(); ++v) {
    uv[2 * v] = static_cast<float>((rest(v, 0) + 0.5) / w);
    uv[2 * v + 1] = static_cast<float>((rest(v, 1) + 0.5) / h);
  }
  m_uploadedBytes += uploadChanged(m_uvBuffer, m_uploadedUv, uv, GL_ARRAY_BUFFER);
  glBindVertexArray(m_vao);  // the element buffer binding belongs to the vertex array
  m_uploadedBytes += uploadChanged(m_indexBuffer, m_uploadedIndices, indices, GL_ELEMENT_ARRAY_BUFFER);
  glBindVertexArray(0);
  if (!warped || m_uploadedPos.size() != uv.size()) {  // rest positions (a warped mesh's follow from its deform)
    std::vector<float> pos(uv.size());
    for (Index v = 0; v < rest.rows(); ++v) {
      pos[2 * v] = static_cast<float>(rest(v, 0));
      pos[2 * v + 1] = static_cast<float>(rest(v, 1));
    }
    m_uploadedBytes += uploadChanged(m_posBuffer, m_uploadedPos, pos, GL_ARRAY_BUFFER);
  }
  if (m_uploadedHeat.size() != static_cast<std::size_t>(rest.rows()))  // no colours yet
    m_uploadedBytes += uploadChanged(m_heatBuffer, m_uploadedHeat, std::vector<Rgba>(static_cast<std::size_t>(rest.rows())),
                                     GL_ARRAY_BUFFER);
}

void Renderer::uploadPositions(AppState& state) {
  const Points& F = state.mesh.deformedVertices();
  std::vector<float> pos(static_cast<std::size_t>(F.rows()) * 2);
  for (Index v = 0; v < F.rows(); ++v) {
    pos[2 * v] = static_cast<float>(F(v, 0));
    pos[2 * v + 1] = static_cast<float>(F(v, 1));
  }
  m_uploadedBytes += uploadChanged(m_posBuffer, m_uploadedPos, pos, GL_ARRAY_BUFFER);
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
  m_uploadedBytes += uploadChanged(m_heatBuffer, m_uploadedHeat, colors, GL_ARRAY_BUFFER);
  return true;
}

void Renderer::draw(AppState& state, int fbWidth, int fbHeight, double displayWidth, double displayHeight) {
  if (!m_program || state.source.empty()) return;
  const auto t0 = std::chrono::steady_clock::now();
  m_uploadedBytes = 0;
  const int limit = displayTextureLimit(fbWidth, fbHeight, m_maxTextureSize);
  const bool reduced = m_display.width < state.source.width || m_display.height < state.source.height;
  if (reduced && limit > m_displayLimit) m_pictureUpload.invalidate();  // the screen takes a larger texture now
  m_pictureUpload.get(state.sourceVersion, [&] {
    updateDisplayTexture(state, limit);
    m_meshUpload.invalidate();
  });
  const bool warped = showsWarp(state);
  m_meshUpload.get({state.meshVersion, warped}, [&] {
    uploadMesh(state, warped);  // sends only what differs: a new weight set on the same mesh sends nothing here
    m_positionsUpload.invalidate();
    m_heatUpload.invalidate();
  });
  if (warped) m_positionsUpload.get(state.deformed.key(), [&] { uploadPositions(state); });
  const OutsideMode outside = state.mesh.options().outside;
  const bool masked = warped && (outside == OutsideMode::Fixed || outside == OutsideMode::Transparent);
  if (masked) updateMask(state);  // the export's mask: the bound cage's polygon
  const std::pair<Index, bool> heatKey{state.activeControl, state.heat.log};
  if (warped && !m_heatUpload.current(heatKey) && uploadHeat(state, warped)) m_heatUpload.set(heatKey);
  const double fbScale = fbWidth / displayWidth;
  updateDetailTexture(state, state.view.zoom * fbScale, warped);
  state.display.detailWidth = m_detail.rect.empty() ? 0 : m_detail.width;
  state.display.detailHeight = m_detail.rect.empty() ? 0 : m_detail.height;
  state.display.detailScale = m_detail.rect.empty() ? 0.0 : m_detail.scale;
  state.timings.uploadBytes = m_uploadedBytes;
  state.timings.uploadMs = msSince(t0);

  const View& v = state.view;
  const double sx = fbScale, sy = fbHeight / displayHeight;
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
  glUniform1f(m_uHeat, 0.0f);
  drawImageQuad(state, 2);  // the image rectangle: a checkerboard shows through transparent pixels
  if (warped && outside == OutsideMode::Fixed) drawImageQuad(state, 0);
  glUniform1i(m_uFlat, 0);
  bindPicture(masked);
  const bool heat = warped && state.activeControl >= 0 &&
                    (state.tool == Tool::Brush ? state.heat.show : state.tool == Tool::Pose && state.heat.showInPose);
  glUniform1f(m_uHeat, heat ? state.heat.opacity : 0.0f);
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
