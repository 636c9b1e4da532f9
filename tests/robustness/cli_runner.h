// SPDX-License-Identifier: GPL-3.0-or-later
// Runs the built `sodt` binary under a time limit in a scratch directory, for
// the robustness tests: exit status, crash/timeout detection, captured output.
#pragma once

#include <dirent.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#ifndef SODT_BIN
#error "SODT_BIN must name the sodt executable"
#endif

namespace sodt_zoo {

/// A fresh directory under $TMPDIR (or /tmp), removed with its files.
class TempDir {
 public:
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string templ = std::string(base && *base ? base : "/tmp") + "/sodt_robustness_XXXXXX";
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    if (::mkdtemp(buf.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = buf.data();
  }
  ~TempDir() {
    for (const std::string& name : entries()) {
      const std::string p = path_ + "/" + name;
      if (::unlink(p.c_str()) != 0) ::rmdir(p.c_str());
    }
    ::rmdir(path_.c_str());
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }
  /// Names in the directory, sorted, without "." and "..".
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    if (DIR* d = ::opendir(path_.c_str())) {
      while (dirent* e = ::readdir(d)) {
        const std::string n = e->d_name;
        if (n != "." && n != "..") names.push_back(n);
      }
      ::closedir(d);
    }
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  std::string path_;
};

inline bool fileExists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

/// Single-quotes a word for /bin/sh.
inline std::string shellQuote(const std::string& s) {
  std::string r = "'";
  for (char c : s) r += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return r + "'";
}

struct RunResult {
  int exitCode = -1;     ///< exit status; -1 when the process did not exit normally
  int signal = 0;        ///< the signal that killed it (directly or reported by timeout)
  bool timedOut = false; ///< killed by the time limit
  std::string out, err;

  /// A crash or a hang: the one outcome that is never acceptable.
  bool crashed() const { return timedOut || signal != 0 || exitCode < 0; }
  /// Lines of stderr (a final newline does not start a line).
  std::vector<std::string> errLines() const {
    std::vector<std::string> lines;
    std::istringstream in(err);
    std::string l;
    while (std::getline(in, l)) lines.push_back(l);
    return lines;
  }
  std::string describe() const {
    std::ostringstream s;
    if (timedOut) s << "timed out";
    else if (signal) s << "killed by signal " << signal;
    else s << "exit status " << exitCode;
    s << "; stderr: '" << err << "'";
    return s.str();
  }
};

inline std::string slurp(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// Runs `sodt ARGS` in dir with stdin from /dev/null, killed after
/// limitSeconds (coreutils timeout). stdout/stderr are captured in files
/// outside dir, so dir's listing only shows what sodt left there.
inline RunResult runSodt(const std::vector<std::string>& args, int limitSeconds = 60) {
  static int serial = 0;
  const char* base = std::getenv("TMPDIR");
  const std::string stem = std::string(base && *base ? base : "/tmp") + "/sodt_robustness_run_" +
                           std::to_string(::getpid()) + "_" + std::to_string(serial++);
  const std::string outPath = stem + ".out", errPath = stem + ".err";
  std::string cmd = "timeout -s KILL " + std::to_string(limitSeconds) + " " + shellQuote(SODT_BIN);
  for (const std::string& a : args) cmd += " " + shellQuote(a);
  cmd += " </dev/null >" + shellQuote(outPath) + " 2>" + shellQuote(errPath);
  const int status = std::system(cmd.c_str());
  RunResult r;
  if (status != -1 && WIFEXITED(status)) {
    const int code = WEXITSTATUS(status);
    if (code == 137) {  // timeout -s KILL: the limit was reached
      r.timedOut = true;
    } else if (code > 128) {  // the shell reports a child killed by a signal as 128 + n
      r.signal = code - 128;
    } else {
      r.exitCode = code;
    }
  } else if (status != -1 && WIFSIGNALED(status)) {
    r.signal = WTERMSIG(status);
  }
  r.out = slurp(outPath);
  r.err = slurp(errPath);
  ::unlink(outPath.c_str());
  ::unlink(errPath.c_str());
  return r;
}

}  // namespace sodt_zoo
