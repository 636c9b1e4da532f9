// SPDX-License-Identifier: GPL-3.0-or-later
// Child processes and file-system chores of sodt_compare, with POSIX calls
// only (gnu++14 has no std::filesystem).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace sodtcmp {
namespace proc {

/// Runs argv[0] (an absolute path) with argv, the current environment plus
/// env (NAME=VALUE), stdout and stderr into logPath (appended when append),
/// in its own process group. Waits at most timeoutSec seconds, then kills the
/// group. Returns the exit status, 124 on timeout, 128+n for signal n, 127 when
/// it could not be started; seconds receives the wall time.
int run(const std::vector<std::string>& argv, const std::vector<std::string>& env, const std::string& logPath,
        int timeoutSec, double* seconds);

/// A virtual X server started with -displayfd (the server picks a free
/// display itself, so parallel runs do not race for one).
class Xvfb {
 public:
  Xvfb() = default;
  ~Xvfb() { stop(); }
  Xvfb(const Xvfb&) = delete;
  Xvfb& operator=(const Xvfb&) = delete;
  /// Starts `xvfbPath -displayfd FD -screen 0 1024x768x24 -nolisten tcp`,
  /// its output into logPath. Returns false with a message.
  bool start(const std::string& xvfbPath, const std::string& logPath, std::string& error);
  /// ":N" once started.
  const std::string& display() const { return display_; }
  /// Terminates the server this object started (by its process id).
  void stop();

 private:
  int pid_ = -1;
  std::string display_;
};

/// The first executable called name on PATH, or "".
std::string which(const std::string& name);
/// Removes a folder tree (does not follow symbolic links). True when gone.
bool removeTree(const std::string& path);
/// Copies a file, keeping it executable when mode says so.
bool copyFile(const std::string& from, const std::string& to, unsigned mode);
/// Symbolic link at `link` pointing to `target`.
bool symlinkTo(const std::string& target, const std::string& link);
/// Absolute path with links resolved, or "" when it does not exist.
std::string realPath(const std::string& path);
/// Names in a folder (no "." and ".."), sorted.
std::vector<std::string> listDir(const std::string& path);
/// The current working folder.
std::string currentDir();

}  // namespace proc
}  // namespace sodtcmp
