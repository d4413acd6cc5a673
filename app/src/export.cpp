#include "kc/app/export.h"

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace kc::app {

WarpMesh buildWarpMesh(const Session& session, const WarpMeshOptions& options, WarpExportReport* report,
                       FieldSampler* sampler, Weights* vertexWeights) {
  if (!session.hasField()) throw std::invalid_argument("the session has no coordinate field (bind first)");
  WarpMesh mesh(session.imageWidth, session.imageHeight, session.cage, options);
  const auto t0 = std::chrono::steady_clock::now();
  Weights W;
  if (sampler) {
    *sampler = FieldSampler(*session.field, mesh.restVertices());
    W = sampler->evaluate(*session.field);
  } else {
    W = session.field->weightsAt(mesh.restVertices());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const CompactWeightsReport cw = mesh.setWeights(W);
  if (vertexWeights) *vertexWeights = std::move(W);
  if (report) {
    report->weights = cw;
    report->weightSeconds = seconds;
  }
  return mesh;
}

Image warpSessionImage(const Session& session, const Image& source, const Pose& pose, const WarpExportOptions& options,
                       WarpExportReport* report) {
  if (source.width != session.imageWidth || source.height != session.imageHeight)
    throw std::invalid_argument("image is " + std::to_string(source.width) + "x" + std::to_string(source.height) +
                                " but the session was bound for " + std::to_string(session.imageWidth) + "x" +
                                std::to_string(session.imageHeight));
  validatePose(pose, session.cage.size());
  WarpExportReport local;
  WarpExportReport& r = report ? *report : local;
  WarpMesh mesh = buildWarpMesh(session, options.mesh, &r);
  r.deform = mesh.deform(pose);
  return mesh.render(source, options.raster, &r.raster);
}

std::string imagePathForSession(const std::string& imagePath, const std::string& sessionPath) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path dir = fs::absolute(fs::path(sessionPath), ec).parent_path();
  const fs::path rel = fs::relative(fs::absolute(imagePath, ec), dir, ec);
  return ec || rel.empty() ? fs::absolute(imagePath).string() : rel.string();
}

std::string resolveSessionImage(const std::string& stored, const std::string& sessionPath) {
  namespace fs = std::filesystem;
  if (stored.empty() || fs::path(stored).is_absolute()) return stored;
  return (fs::path(sessionPath).parent_path() / stored).lexically_normal().string();
}

}  // namespace kc::app
