#pragma once
/// Choosing files: the desktop's own dialog (zenity or kdialog, when installed) run off the main
/// thread, or kcwarp's in-app file browser (panels/dialogs.cpp) otherwise; the browser's
/// directory listing lives here so tests can check it without a window.

#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace kc::ui {

/// What a file is asked for (by menus, shortcuts, buttons and the unsaved-changes prompt).
enum class PathPurpose { None, Open, SaveSession, Export, LoadCage, SaveCage };

/// The title of the file dialog for `purpose`.
const char* dialogTitle(PathPurpose purpose);
/// True when the dialog for `purpose` names a file to write.
bool isSave(PathPurpose purpose);

/// Which native dialog program is used: "zenity", "kdialog" or "" (none found on $PATH).
std::string nativeDialogProgram();

/// The argument list (argv, program first) of a native dialog for `purpose`, starting at
/// `initial` (a file or folder). Empty when `program` is not zenity or kdialog.
std::vector<std::string> nativeDialogCommand(const std::string& program, PathPurpose purpose, const std::string& initial);

/// A native dialog running on its own thread (the window keeps drawing meanwhile).
class NativeDialog {
 public:
  /// Starts `argv`; `wakeup` (may be empty) is called from the dialog's thread when it closes.
  NativeDialog(std::vector<std::string> argv, PathPurpose purpose, std::function<void()> wakeup);
  /// True once the dialog has closed.
  bool done() const;
  /// The chosen path (empty optional: cancelled or failed). Only after done().
  std::optional<std::string> result();
  PathPurpose purpose() const { return m_purpose; }

 private:
  std::future<std::optional<std::string>> m_future;
  PathPurpose m_purpose;
};

/// Runs argv (program first) and returns its first line of standard output when it exits with 0.
std::optional<std::string> runForOutput(const std::vector<std::string>& argv);

/// One entry of the in-app browser.
struct DirEntry {
  std::string name;
  bool directory = false;
};

/// The entries of folder `dir` a browser for `purpose` shows: sub-folders (hidden ones left out),
/// then files with the purpose's extensions (images, sessions, cages, PNG), each group sorted by
/// name. Empty when the folder cannot be read.
std::vector<DirEntry> listFolder(const std::string& dir, PathPurpose purpose);

/// True when `name` has an extension a browser for `purpose` shows.
bool matchesPurpose(const std::string& name, PathPurpose purpose);

}  // namespace kc::ui
