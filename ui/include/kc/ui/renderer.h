#pragma once
/// Draws the picture on the GPU as a textured triangle mesh: the warp mesh's deformed vertices,
/// rest positions as texture coordinates and the heatmap of the active control as vertex
/// colours, over a checkerboard on the image rectangle (transparent pixels show it). Outside
/// modes as in the export: fixed draws the picture at rest first and the inside of the cage over
/// it; fixed and transparent multiply the mesh's picture by a mask of the bound cage.
///
/// The picture is drawn from textures sized for the screen (display_texture.h): the display
/// texture (the whole picture, at most displayTextureLimit texels on its longest side, made once
/// per picture) and, when the view zooms in past its resolution and has stopped moving, a detail
/// texture (the part on screen at the resolution the screen shows, from the full-resolution
/// picture), used where it covers the rest position. Nothing is re-uploaded to textures while a
/// pose is dragged or a stroke painted; vertex buffers get only the elements that changed
/// (positions after a deform, colours after a stroke or a change of the active control), and a
/// new weight set on the same mesh re-uploads neither its texture coordinates nor its triangles.
/// Needs a current OpenGL 3.3 core context.

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "kc/ui/app_state.h"
#include "kc/ui/display_texture.h"

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

  /// Uploads whatever changed since the last call (textures, mesh, deformed vertices, heat
  /// colours) and draws the picture into the canvas of a framebuffer of fbWidth×fbHeight pixels
  /// whose logical size is displayWidth×displayHeight. Updates state.timings (uploadMs,
  /// uploadBytes, textureMs, detailMs), state.display and heatLow/High.
  void draw(AppState& state, int fbWidth, int fbHeight, double displayWidth, double displayHeight);

 private:
  /// A texture and the part of the picture it shows: `rect` in image pixels, `scale` texels per pixel.
  struct PictureTexture {
    unsigned id = 0;
    PixelRect rect;
    double scale = 1.0;
    int width = 0, height = 0;  ///< Texels (level 0).
    int levels = 0;             ///< Mipmap levels of its storage.
  };
  /// The display texture (and the cage mask, dropped) for a new picture or a larger framebuffer.
  void updateDisplayTexture(AppState& state, int limit);
  /// The detail texture for the current view (when it zooms in past the display texture), built
  /// once the view and the pose have stopped moving.
  void updateDetailTexture(AppState& state, double texelsPerPixel, bool warped);
  void updateMask(const AppState& state);
  void uploadImage(const Image& image, PictureTexture& texture, bool mipmaps);
  /// Texture coordinates and triangles of the mesh (or the picture's quad): uploaded only when
  /// they differ from what the GPU holds.
  void uploadMesh(AppState& state, bool warped);
  void uploadPositions(AppState& state);
  /// Uploads the active control's field weights as vertex colours (the changed runs only); false
  /// while a job holds them.
  bool uploadHeat(AppState& state, bool warped);
  /// glBufferSubData of the runs where `next` differs from `shadow` (glBufferData when the size
  /// changed), then shadow = next. Returns the bytes sent.
  template <class T>
  std::size_t uploadChanged(unsigned buffer, std::vector<T>& shadow, const std::vector<T>& next, unsigned target);
  /// The image rectangle at rest as one quad, drawn with shader mode `flat` (0: the picture, under
  /// the warped inside in the fixed mode; 2: the transparency checkerboard).
  void drawImageQuad(const AppState& state, int flat);
  void bindPicture(bool masked);

  std::string m_error;
  unsigned m_program = 0, m_vao = 0, m_posBuffer = 0, m_uvBuffer = 0, m_heatBuffer = 0, m_indexBuffer = 0;
  PictureTexture m_display, m_detail;
  unsigned m_maskTexture = 0;  // R8 at the display texture's size: 1 inside the bound cage
  Points m_maskCage;           // the cage of m_maskTexture
  unsigned m_quadVao = 0, m_quadBuffers[2] = {0, 0};
  int m_uScale = -1, m_uOffset = -1, m_uHeat = -1, m_uFlat = -1, m_uColor = -1, m_uTex = -1, m_uDetail = -1,
      m_uDetailRect = -1, m_uUseDetail = -1, m_uMask = -1, m_uMasked = -1;
  int m_maxTextureSize = 4096, m_displayLimit = 0;
  // What the GPU holds, by what it was made from: the picture (source), the mesh (mesh, warped),
  // the deformed positions (the deform) and the heatmap colours (active control, log scale).
  CachedEffect<Version> m_pictureUpload;
  CachedEffect<std::pair<Version, bool>> m_meshUpload;
  CachedEffect<std::optional<DeformKey>> m_positionsUpload;
  CachedEffect<std::pair<Index, bool>> m_heatUpload;
  /// The view and pose of the last frame and since when they have not changed (detail texture).
  double m_viewZoom = 0.0, m_stillSince = 0.0;
  Vec2 m_viewOffset = Vec2::Zero();
  std::optional<Version> m_viewPose;
  int m_indexCount = 0;
  std::size_t m_uploadedBytes = 0;  // this frame's buffer uploads
  // What the GPU's buffers hold (compared with the next upload).
  std::vector<float> m_uploadedUv, m_uploadedPos;
  std::vector<unsigned> m_uploadedIndices;
  std::vector<Rgba> m_uploadedHeat;
};

}  // namespace kc::ui
