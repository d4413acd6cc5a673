#pragma once
/// Every limit kcwarp puts on its input, in one place (ARCHITECTURE.md, "Limits"). Each keeps
/// the work a file or an option can ask for bounded on the 2-core, 24 GB machines kcwarp is
/// built for: beyond a limit the input is refused up front (CLI exit 2, a GUI message), before
/// anything large is read, decoded or allocated.

#include <cstdint>
#include <string>

namespace kc::app {

inline constexpr std::uint64_t kMiB = 1024ull * 1024ull;

/// Cage, pose and structure files (JSON): 16 MiB (a 100,000-point cage is about 5 MiB).
inline constexpr std::uint64_t kMaxJsonFileBytes = 16 * kMiB;
/// Session files: 512 MiB (weights are #samples × #controls numbers, twice).
inline constexpr std::uint64_t kMaxSessionFileBytes = 512 * kMiB;
/// Points CSV files of `eval`: 256 MiB (about 10 million points).
inline constexpr std::uint64_t kMaxPointsFileBytes = 256 * kMiB;
/// Image files: 512 MiB.
inline constexpr std::uint64_t kMaxImageFileBytes = 512 * kMiB;

/// Most memory the parsed form of one JSON file (a session's document before its weights are
/// decoded) may need by estimate (a streaming count before the parse): 2 GiB. A compact session
/// of 512 MiB needs about 0.5 GiB; one of the same size made of tiny values would need ~16 GiB.
inline constexpr double kMaxJsonParseBytes = 2.0 * 1024 * 1024 * 1024;
/// Most weights `eval` computes (points × control points): 50 million, about 2 GB as doubles and
/// their CSV text.
inline constexpr long long kMaxEvalWeights = 50'000'000;

/// Largest image side, pixels (the header is read before any pixel is decoded).
inline constexpr int kMaxImageSide = 32768;
/// Largest image, pixels: 64 megapixels (8192 × 8192; 256 MB as RGBA, about 1 GB while decoding
/// and converting). A 100-megapixel picture is refused.
inline constexpr std::int64_t kMaxImagePixels = 64ll * 1024 * 1024;

/// Most cage control points (validation is O(n log n); weights are #samples × #points).
inline constexpr int kMaxCagePoints = 100000;
/// Largest |coordinate| of any position in a file (cage points, samples, pose positions and
/// translations), pixels.
inline constexpr double kMaxCoordinate = 1e7;
/// Largest |rotation| of a pose handle, radians (a thousand turns).
inline constexpr double kMaxRotation = 2000.0 * 3.141592653589793;
/// Largest |weight| in a session file (optimized weights lie in about [-1, 2]).
inline constexpr double kMaxWeight = 1e6;
/// Most heat-diffusion iterations (`--heat-iterations`; 0 = steady state, the default). One
/// iteration is one sparse product with the kernel matrix: 100,000 of them take minutes.
inline constexpr int kMaxHeatIterations = 100000;

/// Most vertices of a warp mesh (`warp --mesh-spacing`): the default 4 px spacing over the
/// largest image (64 megapixels) needs 4.2 million.
inline constexpr long long kMaxMeshVertices = 8000000;

/// Smallest sample spacing h, pixels.
inline constexpr double kMinSpacing = 0.05;
/// Most samples of one bind (estimated before sampling; see app::estimateBindCost).
inline constexpr long long kMaxBindSamples = 200000;
/// Most non-zeros of the kernel matrix K of one bind (#S × samples within 5σ).
inline constexpr long long kMaxKernelNonZeros = 40000000;
/// Most memory one bind may need by the estimate, bytes.
inline constexpr double kMaxBindBytes = 6.0 * 1024 * 1024 * 1024;
/// Estimated bytes per entry of the dense #S×m weight matrices a bind holds (W0, W, U and the
/// optimizer's and diffusion's work copies).
inline constexpr double kDenseBytesPerWeight = 48.0;
/// Estimated bytes per non-zero of K for K itself, its sparsity structure, its Cholesky factor
/// and the diffusion operator: a bind of 48,823 samples (3.1 million estimated non-zeros, h = 1.2
/// on 256×256) peaked at 556 MB.
inline constexpr double kBytesPerKernelNonZero = 180.0;

/// Narrowest cage feature a bind accepts, in sample spacings h: every edge at least this long
/// and edges that share no end point at least this far apart. Narrower features deepen the
/// negative lobes and the edge-linearity error quickly (at h/2 about three times the bundled
/// figure's; a 0.01 px edge gave weights down to −163.5).
inline constexpr double kMinFeatureSpacings = 1.0;
/// A cage feature narrower than this many spacings binds (≥ kMinFeatureSpacings) but coarsely
/// (at 2h the lobes and linearity error are within the bundled figure's): the automatic spacing stays
/// below narrowest/this where the limits allow, and a bind warns when it cannot.
inline constexpr double kNarrowFeatureSpacings = 2.0;

/// Throws InputError(where) when width × height is not a usable image size: each side in
/// 1..kMaxImageSide and the pixel count at most kMaxImagePixels. `what` names the size, e.g.
/// "image" or "image_size".
void checkImageSize(std::int64_t width, std::int64_t height, const std::string& where, const std::string& what = "image");

/// "1.5 GiB", "340 MiB", "12 KiB": a byte count for messages.
std::string byteText(double bytes);

}  // namespace kc::app
