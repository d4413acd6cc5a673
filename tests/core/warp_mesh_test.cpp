#include "kc/core/warp_mesh.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "kc/core/outside_motion.h"
#include "kc/core/parallel.h"
#include "warp_fixtures.h"

namespace kc {
namespace {

Image checker(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      const bool c = ((x / 10) + (y / 10)) % 2 == 0;
      p[0] = c ? 230 : 20;
      p[1] = static_cast<std::uint8_t>(2 * x);
      p[2] = static_cast<std::uint8_t>(2 * y);
      p[3] = 255;
    }
  return img;
}

/// The thesis's outside mode: every vertex keeps the field's weights (here mean value coordinates).
WarpMeshOptions deformEverywhere() {
  WarpMeshOptions o;
  o.outside = OutsideMode::Deform;
  return o;
}

TEST(WarpMesh, GridCoversTheImage) {
  const auto ax = gridAxis(100, 4.0);
  EXPECT_DOUBLE_EQ(ax.front(), -0.5);
  EXPECT_DOUBLE_EQ(ax.back(), 99.5);
  for (std::size_t k = 1; k < ax.size(); ++k) EXPECT_LE(ax[k] - ax[k - 1], 4.0 + 1e-12);
  const WarpMesh mesh(120, 100, lCage(), deformEverywhere());
  EXPECT_EQ(mesh.triangles().size(), std::size_t(2 * 30 * 25));
  EXPECT_EQ(mesh.restVertices().rows(), 31 * 26);
}

TEST(WarpMesh, AutomaticSpacingKeepsTheVertexCountWhenThePictureGrows) {
  // Up to about a megapixel at the default sample spacing: today's 4 px.
  EXPECT_DOUBLE_EQ(automaticMeshSpacing(320, 400, 6.0), 4.0);
  EXPECT_DOUBLE_EQ(automaticMeshSpacing(1024, 1024, 6.0), 4.0);
  EXPECT_DOUBLE_EQ(automaticMeshSpacing(1024, 1024, 0.0), 4.0);
  // A field sampled coarsely has no detail finer than its samples: 2h/3.
  EXPECT_DOUBLE_EQ(automaticMeshSpacing(500, 500, 30.0), 20.0);
  EXPECT_DOUBLE_EQ(automaticMeshSpacing(500, 500, std::nan("")), 4.0);
  EXPECT_DOUBLE_EQ(automaticMeshSpacing(500, 500, -3.0), 4.0);
  // A picture scaled by k gets k times the spacing (the same mesh relative to the picture) ...
  const double s1 = automaticMeshSpacing(2048, 1536), s3 = automaticMeshSpacing(3 * 2048, 3 * 1536);
  EXPECT_NEAR(s3, 3.0 * s1, 1e-9 * s3);
  // ... so the grid's vertex count stays near 2^16 from 1 to 64 megapixels.
  for (const auto& [w, h] : {std::pair{1155, 866}, {2309, 1732}, {4000, 3000}, {8192, 8192}, {16000, 4000}}) {
    const double s = automaticMeshSpacing(w, h, 6.0);
    const double vertices = double(gridAxis(w, s).size()) * double(gridAxis(h, s).size());
    EXPECT_GT(vertices, 0.9 * kAutoMeshVertices) << w << "x" << h;
    EXPECT_LT(vertices, 1.05 * kAutoMeshVertices) << w << "x" << h;
  }
}

TEST(WarpMesh, CompactWeightsKeepPartitionOfUnity) {
  const Cage cage = lCage();
  WarpMesh mesh(120, 100, cage, deformEverywhere());
  const Weights W = meanValueWeights(cage.C, mesh.restVertices());
  const CompactWeightsReport rep = mesh.setWeights(W);
  const auto& S = mesh.weights();
  EXPECT_EQ(rep.nonZeros, S.nonZeros());
  EXPECT_LE(rep.maxPerVertex, 8);
  EXPECT_EQ(rep.denseBytes, std::size_t(mesh.restVertices().rows()) * 8 * 8);
  for (Index v = 0; v < S.rows(); ++v) {
    double sum = 0;
    for (WarpMesh::SparseWeights::InnerIterator it(S, v); it; ++it) {
      EXPECT_GT(std::abs(it.value()), 1e-3 / 8);
      sum += it.value();
    }
    ASSERT_NEAR(sum, 1.0, 1e-12);
  }
  EXPECT_THROW(mesh.setWeights(Weights(W.rows(), 7)), std::invalid_argument);
  Weights bad = W;
  bad(3, 2) = std::nan("");
  EXPECT_THROW(mesh.setWeights(bad), std::invalid_argument);
}

TEST(WarpMesh, CompactStorageIsSmallerForLocalWeights) {
  // Local weights (each vertex influenced by ≤ 3 of 30 controls) take far less than dense.
  Points C(30, 2);
  for (int i = 0; i < 30; ++i) C.row(i) << 60 + 40 * std::cos(2 * std::numbers::pi * i / 30), 50 + 40 * std::sin(2 * std::numbers::pi * i / 30);
  WarpMesh mesh(120, 100, Cage::polygon(C), deformEverywhere());
  Weights W = Weights::Zero(mesh.restVertices().rows(), 30);
  for (Index v = 0; v < W.rows(); ++v) {
    const int k = int(v % 30);
    W(v, k) = 0.7, W(v, (k + 1) % 30) = 0.2999, W(v, (k + 2) % 30) = 1e-5;  // below 1e-3/30: dropped
  }
  const CompactWeightsReport rep = mesh.setWeights(W);
  EXPECT_EQ(rep.maxPerVertex, 2);
  EXPECT_NEAR(rep.droppedMass, 1e-5, 1e-12);
  EXPECT_LT(rep.compactBytes * 5, rep.denseBytes);
}

TEST(WarpMesh, AffinePoseMovesVerticesInsideTheCageByThatMap) {
  const Cage cage = lCage();
  WarpMesh mesh(120, 100, cage, deformEverywhere());
  mesh.setWeights(meanValueWeights(cage.C, mesh.restVertices()));
  EXPECT_THROW(mesh.deform(restPose(7)), std::invalid_argument);
  DeformReport rest = mesh.deform({});
  EXPECT_LT((mesh.deformedVertices() - mesh.restVertices()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(rest.flippedTriangles, 0);
  Eigen::Matrix2d A;
  A << 1.1, 0.2, -0.1, 0.95;
  const Vec2 b(3, 4);
  Points P(cage.size(), 2);
  for (Index i = 0; i < cage.size(); ++i) P.row(i) = (A * cage.C.row(i).transpose() + b).transpose();
  const DeformReport rep = mesh.deform(poseFromPositions(cage.C, P));
  EXPECT_EQ(rep.flippedTriangles, 0);
  double worst = 0;
  for (Index v = 0; v < mesh.restVertices().rows(); ++v) {
    const Vec2 x = mesh.restVertices().row(v).transpose();
    if (!insideCage(cage, x)) continue;
    worst = std::max(worst, (mesh.deformedVertices().row(v).transpose() - (A * x + b)).norm());
  }
  EXPECT_LT(worst, 0.05);  // only the dropped entries (≤ 1e-3/m each) perturb exact reproduction
  EXPECT_NEAR(rep.minJacobian, A.determinant(), 0.05);
}

TEST(WarpMesh, FoldOverIsReported) {
  Points C(4, 2);
  C << 10, 10, 90, 10, 90, 90, 10, 90;
  const Cage cage = Cage::polygon(C);
  WarpMesh mesh(100, 100, cage, {});
  mesh.setWeights(meanValueWeights(C, mesh.restVertices()));
  Pose pose = restPose(4);
  pose[2].translate = Vec2(-140, -140);  // drag the bottom-right corner past the top-left one
  const DeformReport rep = mesh.deform(pose);
  EXPECT_GT(rep.flippedTriangles, 0);
  EXPECT_GT(rep.flippedArea, 0.0);
  EXPECT_LE(rep.minJacobian, 0.0);
  Index count = 0;
  for (Index t = 0; t < mesh.jacobians().size(); ++t) count += mesh.jacobians()(t) <= 0 ? 1 : 0;
  EXPECT_EQ(count, rep.flippedTriangles);
}

TEST(WarpMesh, RestPoseRendersTheSourceImage) {
  const Cage cage = lCage();
  WarpMesh mesh(120, 100, cage, {});
  mesh.setWeights(meanValueWeights(cage.C, mesh.restVertices()));
  mesh.deform({});
  const Image src = checker(120, 100);
  const Image out = mesh.render(src);
  EXPECT_GT(psnr(out, src), 45.0);
}

TEST(WarpMesh, OutsideModes) {
  const Cage cage = lCage();
  const Image src = checker(120, 100);
  Pose pose = restPose(8);
  pose[3].translate = Vec2(6, -5);
  for (OutsideMode mode : {OutsideMode::Transparent, OutsideMode::Fixed}) {
    WarpMeshOptions opt;
    opt.outside = mode;
    WarpMesh mesh(120, 100, cage, opt);
    EXPECT_LT(mesh.triangles().size(), std::size_t(2 * 30 * 25));  // culled away from the cage
    mesh.setWeights(meanValueWeights(cage.C, mesh.restVertices()));
    mesh.deform(pose);
    const Image out = mesh.render(src);
    // (2, 98) and (118, 2) are far outside the cage (and its deformation).
    for (auto [x, y] : {std::pair{2, 98}, std::pair{118, 2}, std::pair{100, 20}}) {
      if (mode == OutsideMode::Transparent) EXPECT_EQ(out.at(x, y).a, 0);
      else EXPECT_EQ(out.at(x, y), src.at(x, y));
    }
    for (int c = 0; c < 4; ++c)  // inside, near controls that did not move: (almost) unchanged
      EXPECT_NEAR(out.pixel(20, 20)[c], src.pixel(20, 20)[c], 3);
  }
  OutsideMode m;
  EXPECT_TRUE(parseName("fixed", m));
  EXPECT_EQ(m, OutsideMode::Fixed);
  EXPECT_FALSE(parseName("gimp", m));
}

// The border and corners measureOutside reports are the picture's frame: a mesh of the inside
// alone has no vertex there, however far the cage's extreme points move.
TEST(WarpMesh, OutsideMotionMeasuresThePictureFrameNotTheMeshExtent) {
  const Cage cage = lCage();  // extremes: x 12 and 108, y 10 and 92, inside a 120×100 picture
  Pose pose = restPose(8);
  pose[4].translate = Vec2(6, -5);  // (108, 90): the cage's rightmost point
  pose[0].translate = Vec2(-4, -3);  // (15, 10): its topmost
  for (OutsideMode mode : {OutsideMode::Fixed, OutsideMode::Transparent, OutsideMode::Deform}) {
    WarpMeshOptions opt;
    opt.outside = mode;
    WarpMesh mesh(120, 100, cage, opt);
    mesh.setWeights(meanValueWeights(cage.C, mesh.restVertices()));
    mesh.deform(pose);
    const OutsideMotion om = measureOutside(mesh);
    if (mode == OutsideMode::Deform) {  // the whole picture's mesh: its frame moves with the weights
      EXPECT_GT(om.borderMoved, 0);
      EXPECT_GT(om.borderMax, 0.1);
      EXPECT_GT(om.cornerMax, 0.0);
    } else {
      EXPECT_EQ(om.borderMoved, 0) << toString(mode);
      EXPECT_EQ(om.borderMax, 0.0) << toString(mode);
      EXPECT_EQ(om.cornerMax, 0.0) << toString(mode);
    }
  }
}

TEST(WarpMesh, DeformAndRenderAreIdenticalForOneAndTwoThreads) {
  const Cage cage = lCage();
  WarpMesh mesh(120, 100, cage, {});
  mesh.setWeights(meanValueWeights(cage.C, mesh.restVertices()));
  Pose pose = restPose(8);
  pose[1] = {Vec2(10, 5), 0.3};
  pose[5] = {Vec2(-8, 2), -0.5};
  const Image src = checker(120, 100);
  Points f1, f2;
  Image i1, i2;
  {
    ScopedThreadCount t(1);
    mesh.deform(pose);
    f1 = mesh.deformedVertices();
    i1 = mesh.render(src);
  }
  {
    ScopedThreadCount t(2);
    mesh.deform(pose);
    f2 = mesh.deformedVertices();
    i2 = mesh.render(src);
  }
  EXPECT_EQ(f1, f2);
  EXPECT_EQ(i1.rgba, i2.rgba);
}

TEST(WarpMesh, RejectsBadConstruction) {
  EXPECT_THROW(WarpMesh(0, 10, lCage(), {}), std::invalid_argument);
  WarpMeshOptions opt;
  opt.spacing = 0.1;
  EXPECT_THROW(WarpMesh(10, 10, lCage(), opt), std::invalid_argument);
  WarpMesh mesh(120, 100, lCage(), {});
  EXPECT_THROW(mesh.deform({}), std::invalid_argument);  // no weights yet
  EXPECT_THROW(mesh.render(checker(10, 10)), std::invalid_argument);
}

}  // namespace
}  // namespace kc
