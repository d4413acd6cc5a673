#pragma once
/// Loading and saving kcwarp's JSON files (ARCHITECTURE.md, file formats). Every loader validates
/// shapes and names the file and the bad field (InputError); every save is atomic.

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "kc/app/limits.h"
#include "kc/app/session.h"
#include "kc/core/cage.h"
#include "kc/core/deform.h"

namespace kc::app {

/// Checks that `path` can be written by writeFileAtomic without writing anything: its folder
/// exists and is writable, and the path is not a folder, a device, a FIFO or a socket. A symbolic
/// link is followed to the file it names (kcwarp replaces that file and keeps the link). Returns
/// the file a save would replace. InputError naming `path` otherwise.
std::string checkOutputFile(const std::string& path);

/// Writes `content` to `path` atomically: an unnamed temporary file (O_TMPFILE; where the file
/// system lacks it, a file created exclusively with O_EXCL under a random name that fits NAME_MAX)
/// in the folder of the file replaced, written and fsynced; then a new file is linked under its
/// name, an existing one replaced by a rename, and the folder fsynced. The mode of an existing
/// file is kept (a new one gets 0666 less the umask); a symbolic link is written through (see
/// checkOutputFile). On failure the previous file is untouched, no temporary file is left behind,
/// and InputError names the file and the system's reason.
void writeFileAtomic(const std::string& path, const std::string& content);

/// The whole file as a string. Only regular files are read (a FIFO, a device or a folder is
/// refused without blocking: the file is opened non-blocking and checked with fstat first), and
/// only up to maxBytes. InputError naming the file otherwise.
std::string readTextFile(const std::string& path, std::uint64_t maxBytes = kMaxJsonFileBytes);

/// Outputs of one command, checked when added and written together at the end, so a command
/// that fails while computing writes nothing ("validate everything, write last").
class OutputBatch {
 public:
  /// Checks `path` now (checkOutputFile) and remembers it; InputError when it cannot be written.
  void reserve(const std::string& path);
  /// Sets the content of a reserved (or new, then checked) path.
  void set(const std::string& path, std::string content);
  /// Writes every output: first each one's temporary file in full (as writeFileAtomic), then,
  /// when all are written, puts them in place in the order they were first reserved. A failure
  /// while writing (a full disk, a folder made read-only since) removes every temporary and
  /// leaves every output as it was; InputError names the file.
  void commit();

 private:
  std::vector<std::pair<std::string, std::string>> m_files;
};

/// Cage file {"version":1,"points":[[x,y],...],"closed":true, "edges"?: [[i,j],...]}; validated.
Cage loadCage(const std::string& path);
/// The same from the file's text; `where` names it in messages.
Cage cageFromJson(const std::string& text, const std::string& where);
void saveCage(const std::string& path, const Cage& cage);

/// Pose file, "positions" or "handles" form; must have exactly one entry per control point of C.
Pose loadPose(const std::string& path, const Points& C);
/// The same from the file's text; `where` names it in messages.
Pose poseFromJson(const std::string& text, const Points& C, const std::string& where);
void savePose(const std::string& path, const Pose& pose);

/// Session file (*.kcw.json). loadSession validates every field and rebuilds the coordinate field;
/// on any error it throws and nothing else changes.
Session loadSession(const std::string& path);
void saveSession(const std::string& path, const Session& session);

/// Sample file: {"version": 1, "samples": {"points", "kinds", "edge_ends"}} (the session's layout),
/// plus the keys of `extraJsonObject` (a JSON object as text, e.g. metrics). Atomic.
void saveSamples(const std::string& path, const SampleSet& samples, const std::string& extraJsonObject = "{}");
/// The text saveSamples writes.
std::string samplesText(const SampleSet& samples, const std::string& extraJsonObject = "{}");

/// How a session file holds its weight matrices (weights.optimized, weights.initial, a mesh
/// field's weights): Compact writes `<key>_b64` = {"shape": [n, m], "dtype": "f64le", "base64"}
/// (little-endian doubles, bit-exact; the bound figure's file 3.1 MB instead of 5.5 MB);
/// Rows writes `<key>` = [[w_0, ..., w_m-1], ...] as files before the compact form did. Loading
/// reads either.
enum class WeightsForm { Compact, Rows };

/// The same as text (used by the GUI's autosave and by tests).
std::string sessionToJson(const Session& session, WeightsForm form = WeightsForm::Compact);
Session sessionFromJson(const std::string& text, const std::string& where);

/// How a coordinate field of one kind (CoordinateField::kind()) is kept in the session's `field`
/// block. Built in: "kernel" and "mesh" (ARCHITECTURE.md, Session file).
struct FieldCodec {
  std::string_view kind;
  /// The block for s.field (of this kind), "kind" included; `form` says how weights are written.
  std::function<nlohmann::json(const Session& s, WeightsForm form)> write;
  /// Reads the block into s (s.samples, s.W and s.params are read): builds s.field and returns
  /// true, or checks the block and returns false (the backend's rebuildField makes the field).
  /// Throws InputError(where, …) naming the bad entry.
  std::function<bool(const nlohmann::json& block, Session& s, const std::string& where)> read;
};
/// Makes sessions keep fields of codec.kind (a static object's, as registerBackend's backends):
/// without a codec a field is not written and the load rebuilds it. Returns true; throws
/// std::invalid_argument when the kind has a codec already.
bool registerFieldCodec(const FieldCodec& codec);

}  // namespace kc::app
