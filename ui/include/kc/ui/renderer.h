#pragma once
/// Draws the picture on the GPU as a textured triangle mesh: the warp mesh's deformed vertices
/// (uploaded when the pose or the mesh changed), rest positions as texture coordinates (the
/// texture is uploaded once per image), and the heatmap of the active control as vertex colours,
/// over a checkerboard on the image rectangle (transparent pixels show it). Outside modes as in
/// the export: fixed draws the picture at rest first and the inside of the cage over it; fixed and
/// transparent draw the mesh with a texture masked to the cage.
/// Needs a current OpenGL 3.3 core context.

#include <cstdint>
#include <vector>

#include "kc/ui/app_state.h"

namespace kc::ui {

class Renderer {
 public:
  Renderer() = default;
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Compiles the shaders and creates the buffers. Returns false with a reason in error().
  bool init();
  const std::string& error() const { return m_error; }

  /// Uploads whatever changed since the last call (texture, mesh, deformed vertices, heat colours)
  /// and draws the picture into the canvas of a framebuffer of fbWidth×fbHeight pixels whose
  /// logical size is displayWidth×displayHeight. Updates state.timings.uploadMs, heatLow/High.
  void draw(AppState& state, int fbWidth, int fbHeight, double displayWidth, double displayHeight);

 private:
  void uploadTexture(const Image& image, unsigned& texture);
  void uploadMesh(const AppState& state, bool warped);
  /// Uploads the active control's field weights as vertex colours; false while a job holds them.
  bool uploadHeat(AppState& state, bool warped);
  /// The image rectangle at rest as one quad, drawn with shader mode `flat` (0: the picture, under
  /// the warped inside in the fixed mode; 2: the transparency checkerboard).
  void drawImageQuad(const AppState& state, int flat);

  std::string m_error;
  unsigned m_program = 0, m_vao = 0, m_posBuffer = 0, m_uvBuffer = 0, m_heatBuffer = 0, m_indexBuffer = 0;
  unsigned m_texture = 0, m_maskedTexture = 0;  // masked: alpha 0 outside the bound cage
  unsigned m_quadVao = 0, m_quadBuffers[2] = {0, 0};
  std::uint64_t m_maskKey = ~0ull;
  int m_uScale = -1, m_uOffset = -1, m_uHeat = -1, m_uFlat = -1, m_uColor = -1, m_uTex = -1;
  std::uint64_t m_sourceRevision = ~0ull, m_meshRevision = ~0ull, m_deformKey = ~0ull, m_heatKey = ~0ull;
  bool m_warped = false;
  int m_indexCount = 0, m_vertexCount = 0;
  std::vector<float> m_scratch;
};

}  // namespace kc::ui
