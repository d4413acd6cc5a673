#include "kc/ui/automation.h"

#include <GL/gl.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/app/session.h"
#include "kc/ui/canvas.h"
#include "kc/ui/rigidity_edits.h"

namespace kc::ui {

std::string stateJson(const AppState& state, const int window[4], int screenshots, int exports) {
  using nlohmann::json;
  json j;
  const bool busy = state.worker.busy();
  j["busy"] = busy;
  j["bound"] = state.bound != nullptr;
  j["idle"] = !busy && state.canvasDrag.button < 0;
  j["tool"] = state.tool == Tool::Pose    ? "pose"
              : state.tool == Tool::Brush ? "brush"
              : state.tool == Tool::Lines ? "lines"
              : state.tool == Tool::Rigid ? "rigid"
                                          : "cage";
  j["method"] = std::string(app::toString(state.bound ? state.bound->method : Method::QP));
  j["bind_switches"] = {{"auto_spacing", state.autoSpacing},  // the Bind panel's kc check boxes
                        {"auto_sigma", !(state.bindParams.kc.sigma > 0.0)},
                        {"local_targets", state.bindParams.kc.locality.rule != app::Locality::Rule::Off}};
  j["bind_backend"] = state.bindParams.backend;  // the Bind panel's choice (the bound session's after a bind)
  j["lbc_mesh"] = state.bound ? state.bound->report.meshVertices() : 0;  // LBC mesh vertices of the bound session, 0 when not LBC
  j["window"] = {window[0], window[1], window[2], window[3]};
  json controls = json::array();
  if (state.bound) {
    const Points P = posedControls(state.bound->cage.C, state.pose);
    for (Index i = 0; i < P.rows(); ++i) {
      const Vec2 s = state.view.toScreen(P.row(i).transpose());
      controls.push_back({s.x(), s.y()});
    }
  }
  j["controls"] = controls;
  json cage = json::array();
  for (Index i = 0; i < state.cage.size(); ++i) {
    const Vec2 s = state.view.toScreen(state.cage.C.row(i).transpose());
    cage.push_back({s.x(), s.y()});
  }
  j["cage"] = cage;
  j["cage_valid"] = state.cageValid;
  json lines = json::array();  // the document's lines: ends on screen (rest picture) and group
  for (const StructureLine& l : state.lines.lines) {
    const Vec2 a = state.view.toScreen(l.a), b = state.view.toScreen(l.b);
    lines.push_back({{"a", {a.x(), a.y()}}, {"b", {b.x(), b.y()}}, {"group", l.group >= 0 ? state.lines.groups[static_cast<std::size_t>(l.group)] : ""}});
  }
  j["lines"] = lines;
  j["bound_lines"] = state.bound ? state.bound->lines.size() : 0;
  j["line_selection"] = state.lineSelection;
  const std::vector<double>& rho = boundRigidity(state);
  j["rigid_samples"] = std::count_if(rho.begin(), rho.end(), [](double r) { return r > 0.0; });
  j["rigid_regions"] = state.lines.rigid.size();
  j["cage_status"] = state.cageStatus;
  json widgets = json::object();
  for (const auto& [name, c] : state.widgets) widgets[name] = {c.x(), c.y()};
  j["widgets"] = widgets;
  j["view"] = {{"zoom", state.view.zoom},
               {"origin", {state.view.canvasMin.x() + state.view.offset.x(), state.view.canvasMin.y() + state.view.offset.y()}}};
  j["active_control"] = state.activeControl;
  j["selection"] = state.selection;
  j["undo"] = state.undo.undoCount();
  j["redo"] = state.undo.redoCount();
  j["unsaved"] = state.unsaved;
  j["prompt"] = state.unsavedPrompt ? state.unsavedPrompt->what : std::string();
  j["question"] = state.unsavedPrompt ? state.unsavedPrompt->question : std::string();
  // A fingerprint of the bound weights (Σ W_ij·(1 + (i+j) mod 7)): tells one bind's weights from another's.
  double fingerprint = 0.0;
  if (state.session)
    for (Index i = 0; i < state.session->W.rows(); ++i)
      for (Index k = 0; k < state.session->W.cols(); ++k) fingerprint += state.session->W(i, k) * double(1 + (i + k) % 7);
  j["weights_fingerprint"] = fingerprint;
  j["file_dialog"] = state.pathDialog != PathPurpose::None;
  j["file_dialog_text"] = state.pathDialog != PathPurpose::None ? state.pathDialogText : std::string();
  j["file_dialog_focused"] = state.pathDialog != PathPurpose::None && state.pathDialogFocused;
  j["image_path"] = state.imagePath;
  j["image_size"] = {state.source.width, state.source.height};
  j["session_path"] = state.sessionPath;
  j["recent_files"] = state.recentFiles;
  j["show_original"] = state.showOriginal;
  j["hide_cage"] = state.hideCage;
  j["pose_translate"] = nlohmann::json::array();
  for (const HandlePose& h : state.pose) j["pose_translate"].push_back({h.translate.x(), h.translate.y()});
  j["mesh_revision"] = state.meshVersion.count();
  j["pose_revision"] = state.poseVersion.count();
  j["flipped_triangles"] = state.deformReport.flippedTriangles;
  j["screenshots"] = screenshots;
  j["exports"] = exports;
  json messages = json::array();
  for (const Message& m : state.messages) messages.push_back({{"text", m.text}, {"error", m.error}});
  j["messages"] = messages;
  const Timings& t = state.timings;
  j["timings"] = {{"release_to_picture_ms", t.releaseToPictureMs},
                  {"release_job_ms", t.releaseJobMs},
                  {"release_frame_ms", t.releaseFrameMs},
                  {"reoptimize_ms", t.reoptimizeMs},
                  {"reoptimize_samples", t.reoptimizeSamples},
                  {"mesh_weights_ms", t.meshWeightsMs},
                  {"mesh_set_weights_ms", t.meshSetWeightsMs},
                  {"deform_ms", t.deformMs},
                  {"upload_ms", t.uploadMs},
                  {"upload_bytes", t.uploadBytes},
                  {"open_ms", t.openMs},
                  {"texture_ms", t.textureMs},
                  {"detail_ms", t.detailMs},
                  {"bind_s", t.bindSeconds}};
  j["display_texture"] = {state.display.width, state.display.height};
  j["detail_texture"] = {{"size", {state.display.detailWidth, state.display.detailHeight}}, {"scale", state.display.detailScale}};
  return j.dump(1);
}

bool writeAtomically(const std::string& path, const std::string& text) {
  try {
    app::writeFileAtomic(path, text);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

bool saveScreenshot(const std::string& path, int fbWidth, int fbHeight) {
  Image img(fbWidth, fbHeight);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  std::vector<std::uint8_t> raw(img.rgba.size());
  glReadPixels(0, 0, fbWidth, fbHeight, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
  const std::size_t row = static_cast<std::size_t>(fbWidth) * 4;
  for (int y = 0; y < fbHeight; ++y)  // GL rows are bottom-up
    std::copy_n(raw.data() + static_cast<std::size_t>(fbHeight - 1 - y) * row, row, img.rgba.data() + y * row);
  for (std::size_t k = 3; k < img.rgba.size(); k += 4) img.rgba[k] = 255;
  try {
    app::saveImage(path, img);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

bool FrameLog::write(const std::string& path) const {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f, "frame,time_s,frame_ms,deform_ms,upload_ms,dragging,deformed,vertices,upload_bytes,apply_ms,ui_ms,gl_ms,swap_ms\n");
  for (std::size_t k = 0; k < m_rows.size(); ++k) {
    const Row& r = m_rows[k];
    std::fprintf(f, "%zu,%.4f,%.3f,%.3f,%.3f,%d,%d,%ld,%ld,%.3f,%.3f,%.3f,%.3f\n", k, r.time, r.frameMs, r.deformMs, r.uploadMs,
                 r.dragging ? 1 : 0, r.deformed ? 1 : 0, r.vertices, r.uploadBytes, r.applyMs, r.uiMs, r.glMs, r.swapMs);
  }
  return std::fclose(f) == 0;
}

}  // namespace kc::ui
