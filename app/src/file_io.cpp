#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <utility>
#include <vector>

#include "json_util.h"
#include "kc/app/draft_cage.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"

namespace kc::app {

namespace {

namespace fs = std::filesystem;

/// Closes a descriptor on scope exit.
struct FileDescriptor {
  int fd = -1;
  explicit FileDescriptor(int f) : fd(f) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
  int release() { return std::exchange(fd, -1); }
};

std::string systemError(int err) { return std::strerror(err); }

/// The file a write to `path` replaces: `path`, or for a symbolic link (a chain of them) the
/// file the link names, which need not exist yet.
fs::path resolveOutput(const std::string& path) {
  fs::path p(path);
  for (int hops = 0; hops < 40; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
    std::error_code ec;
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) throw InputError(path, "cannot read the symbolic link: " + ec.message());
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  throw InputError(path, "too many levels of symbolic links");
}

/// Writes all of `content` to fd; 0 or the errno of the failure.
int writeAll(int fd, const std::string& content) {
  const char* p = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, std::min<std::size_t>(left, std::size_t(1) << 30));
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return 0;
}

std::string randomSuffix() {
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%08x%04x", rd(), (counter++ & 0xffffu));
  return buf;
}

/// Content, mode (and, where allowed, owner) written to fd and fsynced; 0 or an errno.
int fillTemp(int fd, const std::string& content, const struct stat* existing) {
  if (const int err = writeAll(fd, content)) return err;
  if (existing) {
    if (::fchmod(fd, existing->st_mode & 07777) != 0) return errno;
    if (::fchown(fd, existing->st_uid, existing->st_gid) != 0) {
      // Only root may give a file away: a save by another user owns its copy, as any editor's does.
    }
  }
  if (::fsync(fd) != 0) return errno;
  return 0;
}

}  // namespace

std::string checkOutputFile(const std::string& path) {
  if (path.empty()) throw InputError("(output)", "empty file name");
  const fs::path target = resolveOutput(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    throw InputError(path, "folder '" + dir.string() + "' does not exist");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw InputError(path, "cannot write in folder '" + dir.string() + "': " + systemError(errno));
  if (::stat(target.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw InputError(path, "is a folder, not a file");
    if (!S_ISREG(st.st_mode))
      throw InputError(path, "is not a regular file (a device, FIFO or socket): kcwarp only writes regular files");
  }
  return target.string();
}

namespace {

/// A temporary name in `dir` for a file named `name`: "." + name + "." + 12 random hex digits +
/// ".tmp", the name cut so that the whole fits NAME_MAX (a legal output name of 238–255 bytes
/// would otherwise give a temporary name the file system refuses).
fs::path tempName(const fs::path& dir, const std::string& name) {
  constexpr std::size_t kAdded = 18;  // ".", ".", 12 hex digits, ".tmp"
  std::string temp = ".";             // appended piece by piece: GCC 12 warns falsely on "." + std::string at -O3
  temp += name.substr(0, NAME_MAX - kAdded);
  temp += '.';
  temp += randomSuffix();
  temp += ".tmp";
  return dir / temp;
}

/// One output written in full to a temporary in its target's folder, not yet in place: an unnamed
/// O_TMPFILE (fd) where the file system has it, else a named temporary (tmp).
struct PendingFile {
  std::string path;  ///< as given (messages)
  fs::path target, dir;
  int fd = -1;
  fs::path tmp;

  PendingFile() = default;
  PendingFile(PendingFile&& o) noexcept
      : path(std::move(o.path)), target(std::move(o.target)), dir(std::move(o.dir)), fd(std::exchange(o.fd, -1)), tmp(std::move(o.tmp)) {}
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;
  PendingFile& operator=(PendingFile&&) = delete;
  /// Removes what is not yet in place (the unnamed file goes with its descriptor).
  ~PendingFile() {
    if (fd >= 0) ::close(fd);
    if (!tmp.empty()) ::unlink(tmp.c_str());
  }

  /// Writes `content` (mode and owner of the file replaced, fsynced); InputError naming the file,
  /// nothing left behind, when it cannot.
  void write(const std::string& content) {
    target = checkOutputFile(path);
    dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    struct stat existing {};
    const bool exists = ::stat(target.c_str(), &existing) == 0;
    // 1. An unnamed temporary file: if kcwarp dies before it is named, nothing is left behind (it
    //    is named through /proc/self/fd, so only where that exists).
    if (::access("/proc/self/fd", X_OK) == 0) fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (fd >= 0) {
      if (const int err = fillTemp(fd, content, exists ? &existing : nullptr)) throw InputError(path, "cannot write: " + systemError(err));
      return;
    }
    // 2. A temporary file created exclusively (O_EXCL never follows or reuses an existing name).
    for (int attempt = 0; attempt < 100 && tmp.empty(); ++attempt) {
      const fs::path name = tempName(dir, target.filename().string());
      FileDescriptor f(::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666));
      if (f.fd < 0) {
        if (errno == EEXIST) continue;
        throw InputError(path, "cannot write: " + systemError(errno));
      }
      tmp = name;  // removed by the destructor from here on
      int err = fillTemp(f.fd, content, exists ? &existing : nullptr);
      if (!err && ::close(f.release()) != 0) err = errno;
      if (err) throw InputError(path, "cannot write: " + systemError(err));
    }
    if (tmp.empty()) throw InputError(path, "cannot create a temporary file in '" + dir.string() + "'");
  }

  /// Puts the file in place: a new file is linked under its name directly; one that exists is
  /// replaced by renaming a named temporary over it. The folder is fsynced. InputError naming the
  /// file when it cannot (the previous file untouched).
  void publish() {
    if (fd >= 0) {
      const std::string procPath = "/proc/self/fd/" + std::to_string(fd);
      if (::linkat(AT_FDCWD, procPath.c_str(), AT_FDCWD, target.c_str(), AT_SYMLINK_FOLLOW) == 0) {
        ::close(std::exchange(fd, -1));
        syncFolder();
        return;
      }
      for (int attempt = 0; attempt < 100 && tmp.empty(); ++attempt) {
        const fs::path name = tempName(dir, target.filename().string());
        if (::linkat(AT_FDCWD, procPath.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0) tmp = name;
        else if (errno != EEXIST) throw InputError(path, "cannot name the temporary file: " + systemError(errno));
      }
      if (tmp.empty()) throw InputError(path, "cannot create a temporary file in '" + dir.string() + "'");
      ::close(std::exchange(fd, -1));
    }
    if (::rename(tmp.c_str(), target.c_str()) != 0) throw InputError(path, "cannot replace the file: " + systemError(errno));
    tmp.clear();
    syncFolder();
  }

 private:
  void syncFolder() const {
    FileDescriptor dirFd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (dirFd.fd >= 0) ::fsync(dirFd.fd);  // the new name itself reaches the disk
  }
};

}  // namespace

void writeFileAtomic(const std::string& path, const std::string& content) {
  PendingFile f;
  f.path = path;
  f.write(content);
  f.publish();
}

std::string readTextFile(const std::string& path, std::uint64_t maxBytes) {
  FileDescriptor fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC));
  if (fd.fd < 0) {
    const int err = errno;
    if (err == ENOENT) throw InputError(path, "no such file");
    throw InputError(path, "cannot open: " + systemError(err));
  }
  struct stat st {};
  if (::fstat(fd.fd, &st) != 0) throw InputError(path, "cannot read: " + systemError(errno));
  if (S_ISDIR(st.st_mode)) throw InputError(path, "is a folder, not a file");
  if (!S_ISREG(st.st_mode)) throw InputError(path, "is not a regular file (a device, FIFO or socket): kcwarp reads only regular files");
  const auto tooLarge = [&](double bytes) {
    return InputError(path, "is " + byteText(bytes) + ", more than the " + byteText(double(maxBytes)) +
                                " kcwarp reads for this kind of file");
  };
  if (static_cast<std::uint64_t>(st.st_size) > maxBytes) throw tooLarge(double(st.st_size));
  std::string text(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t got = 0;
  for (;;) {
    if (got == text.size()) {
      if (text.size() >= maxBytes + 1) throw tooLarge(double(text.size()));  // grew while being read
      text.resize(std::min<std::uint64_t>(maxBytes + 1, text.size() + 65536));
    }
    const ssize_t n = ::read(fd.fd, text.data() + got, text.size() - got);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw InputError(path, "cannot read: " + systemError(errno));
    }
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  text.resize(got);
  return text;
}

void OutputBatch::reserve(const std::string& path) {
  for (const auto& f : m_files)
    if (f.first == path) return;
  checkOutputFile(path);
  m_files.emplace_back(path, std::string());
}

void OutputBatch::set(const std::string& path, std::string content) {
  reserve(path);
  for (auto& f : m_files)
    if (f.first == path) f.second = std::move(content);
}

void OutputBatch::commit() {
  // Every temporary written before any is put in place; on a failure the destructors remove them.
  std::vector<PendingFile> pending(m_files.size());
  for (std::size_t k = 0; k < m_files.size(); ++k) {
    pending[k].path = m_files[k].first;
    pending[k].write(m_files[k].second);
    std::string().swap(m_files[k].second);  // written: its memory is not needed any more
  }
  for (PendingFile& f : pending) f.publish();
}

Cage cageFromJson(const std::string& text, const std::string& where) {
  const detail::json j = detail::parseJson(text, where);
  detail::checkVersion(j, where);
  return detail::parseCage(j, where, "");
}

Cage loadCage(const std::string& path) { return cageFromJson(readTextFile(path), path); }

void saveCage(const std::string& path, const Cage& cage) {
  detail::json j = {{"version", 1}};
  j.update(detail::cageToJson(cage));
  writeFileAtomic(path, j.dump(1) + "\n");
}

Pose poseFromJson(const std::string& text, const Points& C, const std::string& where) {
  const detail::json j = detail::parseJson(text, where);
  detail::checkVersion(j, where);
  return detail::parsePose(j, C, where, "");
}

Pose loadPose(const std::string& path, const Points& C) { return poseFromJson(readTextFile(path), C, path); }

void savePose(const std::string& path, const Pose& pose) {
  detail::json j = {{"version", 1}};
  j.update(detail::poseToJson(pose));
  writeFileAtomic(path, j.dump(1) + "\n");
}

void saveDraftCage(const std::string& path, const DraftCage& draft) {
  detail::json j = {{"version", 1}};
  j.update(detail::cageToJson(draft.cage));
  detail::json edges = detail::json::array();  // always written: a draft's edges need not be its polygon's
  for (const auto& [a, b] : draft.cage.edges) edges.push_back({a, b});
  j["edges"] = edges;
  j["image"] = draft.image;
  if (draft.imageUpright) j["image_upright"] = true;
  writeFileAtomic(path, j.dump(1) + "\n");
}

DraftCage loadDraftCage(const std::string& path) {
  const detail::json j = detail::parseJson(readTextFile(path), path);
  detail::checkVersion(j, path);
  DraftCage draft;
  draft.cage = detail::parseCageDraft(j, path, "");
  const detail::json& image = detail::require(j, "image", path);
  if (!image.is_string()) throw InputError(path, "image must be the picture's path (a string)");
  draft.image = image.get<std::string>();
  if (j.contains("image_upright") && !j["image_upright"].is_boolean()) throw InputError(path, "image_upright must be true or false");
  draft.imageUpright = j.contains("image_upright") && j["image_upright"].get<bool>();
  return draft;
}

}  // namespace kc::app
