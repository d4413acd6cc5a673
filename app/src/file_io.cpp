#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "json_util.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"

namespace kc::app {

void writeFileAtomic(const std::string& path, const std::string& content) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(path, "folder '" + dir.string() + "' does not exist");
  const fs::path tmp = dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()));
  {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw InputError(path, std::string("cannot write: ") + std::strerror(errno));
    const bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size() && std::fflush(f) == 0 &&
                    ::fsync(::fileno(f)) == 0;
    const int err = errno;
    std::fclose(f);
    if (!ok) {
      fs::remove(tmp, ec);
      throw InputError(path, std::string("cannot write: ") + std::strerror(err));
    }
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path, "cannot replace the file: " + ec.message());
  }
}

std::string readTextFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, "is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Cage loadCage(const std::string& path) {
  const detail::json j = detail::parseJson(readTextFile(path), path);
  detail::checkVersion(j, path);
  return detail::parseCage(j, path, "");
}

void saveCage(const std::string& path, const Cage& cage) {
  detail::json j = {{"version", 1}};
  j.update(detail::cageToJson(cage));
  writeFileAtomic(path, j.dump(1) + "\n");
}

Pose loadPose(const std::string& path, const Points& C) {
  const detail::json j = detail::parseJson(readTextFile(path), path);
  detail::checkVersion(j, path);
  return detail::parsePose(j, C, path, "");
}

void savePose(const std::string& path, const Pose& pose) {
  detail::json j = {{"version", 1}};
  j.update(detail::poseToJson(pose));
  writeFileAtomic(path, j.dump(1) + "\n");
}

}  // namespace kc::app
