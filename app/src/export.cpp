#include "kc/app/export.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <span>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "kc/app/backend.h"
#include "kc/app/errors.h"
#include "kc/app/pipeline.h"
#include "kc/core/parallel.h"
#include "kc/core/weights/sample_qec.h"

namespace kc::app {
namespace {

/// Rows of W with no weights (points outside a mesh field's domain) get the weights of the
/// nearest cage point: linear along its edge (thesis 4.7), which is what a mesh field of the cage
/// interior holds there. Continuous across the cage, partition of unity and w ≥ 0; no reproduction.
void extendByNearestCagePoint(const Cage& cage, const Points& P, Weights& W) {
  const auto edges = cageEdges(cage);
  parallelFor(P.rows(), [&](Index v) {
    if (W.row(v).sum() != 0.0) return;
    const Vec2 x = P.row(v);
    double best = std::numeric_limits<double>::infinity();
    std::size_t at = 0;
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const double d = pointSegmentDistance(x, cage.C.row(edges[e][0]), cage.C.row(edges[e][1]));
      if (d < best) {
        best = d;
        at = e;
      }
    }
    const Vec2 a = cage.C.row(edges[at][0]), b = cage.C.row(edges[at][1]);
    const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    edgeWeights(cage.C, edges[at][0], edges[at][1], a + t * (b - a), std::span<double>(&W(v, 0), std::size_t(W.cols())));
  }, 256);
}

}  // namespace

WarpMeshOptions warpMeshOptionsFor(int width, int height, double fieldSpacing, OutsideMode outside) {
  WarpMeshOptions o;
  o.outside = outside;
  o.spacing = automaticMeshSpacing(width, height, fieldSpacing);
  return o;
}

WarpMeshOptions warpMeshOptionsFor(const Session& session, OutsideMode outside) {
  const double detail = session.lbcMeshSpacing > 0.0 ? session.lbcMeshSpacing : weightSpacing(session.params);
  return warpMeshOptionsFor(session.imageWidth, session.imageHeight, detail, outside);
}

WarpMesh buildWarpMesh(const Session& session, const WarpMeshOptions& options, WarpExportReport* report,
                       FieldSampler* sampler, Weights* vertexWeights) {
  if (!session.hasField()) throw std::invalid_argument("the session has no coordinate field (bind first)");
  if (options.outside == OutsideMode::Deform && !sessionCapabilities(session).outsideCage)
    throw InputError("outside mode 'deform'", "needs weights outside the cage, and this session has none (" +
                                                  sessionCapabilities(session).why + "); use pinned, fixed or transparent");
  WarpMesh mesh(session.imageWidth, session.imageHeight, session.cage, options);
  const auto t0 = std::chrono::steady_clock::now();
  Weights W;
  if (sampler) {
    *sampler = FieldSampler(*session.field, mesh.restVertices());
    W = sampler->evaluate(*session.field);
  } else {
    W = session.field->weightsAt(mesh.restVertices());
  }
  if (session.field->domain() == FieldDomain::Mesh) extendByNearestCagePoint(session.cage, mesh.restVertices(), W);
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
