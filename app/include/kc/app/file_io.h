#pragma once
/// Loading and saving kcwarp's JSON files (ARCHITECTURE.md, file formats). Every loader validates
/// shapes and names the file and the bad field (InputError); every save is atomic.

#include <string>

#include "kc/app/session.h"
#include "kc/core/cage.h"
#include "kc/core/deform.h"

namespace kc::app {

/// Writes `content` to `path` atomically: a temporary file in the same folder, flushed, then
/// renamed over the target. On failure the previous file is untouched and InputError is thrown.
void writeFileAtomic(const std::string& path, const std::string& content);
/// The whole file as a string; InputError when it cannot be read.
std::string readTextFile(const std::string& path);

/// Cage file {"version":1,"points":[[x,y],...],"closed":true, "edges"?: [[i,j],...]}; validated.
Cage loadCage(const std::string& path);
void saveCage(const std::string& path, const Cage& cage);

/// Pose file, "positions" or "handles" form; must have exactly one entry per control point of C.
Pose loadPose(const std::string& path, const Points& C);
void savePose(const std::string& path, const Pose& pose);

/// Session file (*.kcw.json). loadSession validates every field and rebuilds the coordinate field;
/// on any error it throws and nothing else changes.
Session loadSession(const std::string& path);
void saveSession(const std::string& path, const Session& session);

/// Sample file: {"version": 1, "samples": {"points", "kinds", "edge_ends"}} (the session's layout),
/// plus the keys of `extraJsonObject` (a JSON object as text, e.g. metrics). Atomic.
void saveSamples(const std::string& path, const SampleSet& samples, const std::string& extraJsonObject = "{}");

/// The same as text (used by the GUI's autosave and by tests).
std::string sessionToJson(const Session& session);
Session sessionFromJson(const std::string& text, const std::string& where);

}  // namespace kc::app
