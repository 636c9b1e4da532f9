// SPDX-License-Identifier: GPL-3.0-or-later
// The command line of `sodt`: its subcommands and options as a CLI11 app whose
// smoothing options are built from sodt::paramTable(), the help they print,
// and the checks of the values and file names given.
#pragma once

#include <sodt/params.h>

#include <CLI/CLI.hpp>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace sodt_cli {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

/// A bad command line: exit status 2 and a pointer to the help.
class UsageError : public std::runtime_error {
 public:
  UsageError(const std::string& msg, const std::string& helpCmd)
      : std::runtime_error(msg), helpCommand(helpCmd) {}
  std::string helpCommand;  ///< e.g. "sodt smooth --help"
};

/// `sodt smooth IN OUT [options]`.
struct SmoothOptions {
  std::string in, out, report, classesOut;
  sodt::SodtParams params;
  bool quiet = false;
  bool distance = true;  ///< measure the surface distance between IN and OUT
};

/// `sodt classify IN OUT.ply [options]`: params holds epsilon and eta.
struct ClassifyOptions {
  std::string in, out, json;
  sodt::SodtParams params;
};

/// `sodt stats IN [options]`.
struct StatsOptions {
  std::string in, reference, json;
};

/// What the command line asks for.
enum class Command {
  Done,     ///< the help was printed
  Version,  ///< print the version
  Smooth,
  Classify,
  Stats,
};

/// Shortest decimal text of a parameter value for messages and summaries ("2", "0.05").
std::string numberText(double x);

/// Smallest angle (degrees) between the normals of two equally weighted
/// planes at which a vertex between them is a crease: Eq. 10 with
/// nu = (1 + cos t, 1 - cos t, 0) gives crease when cos t < eps / (eps + 2).
double creaseAngleDeg(double epsilon);

/// Path with symbolic links and "." / ".." resolved as far as it exists.
std::string canonicalPath(const std::string& p);

/// The `sodt` command line: one CLI11 app with the subcommands smooth,
/// classify and stats. Every option of `sodt smooth` that sets a SodtParams
/// field (and classify's --epsilon and --eta) is made from its
/// sodt::paramTable() entry: name, value placeholder, help, range and
/// default; its value is checked against the same entry.
class CommandLine {
 public:
  CommandLine();
  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;
  ~CommandLine();

  /// Parses the arguments after the program name and checks them. Prints
  /// the help itself (and returns Command::Done).
  /// \throw UsageError naming the option or argument that is wrong.
  Command parse(const std::vector<std::string>& args);

  SmoothOptions smooth;
  ClassifyOptions classify;
  StatsOptions stats;

  /// The app, for its help text and for the tests ("smooth", "classify",
  /// "stats" are its subcommands).
  const CLI::App& app() const { return app_; }

  /// The option of `sodt smooth` built from a table entry, nullptr if none.
  const CLI::Option* smoothOption(const sodt::ParamSpec& s) const;

 private:
  struct TableOption;  // one option made from a table entry, with its raw text
  void addTableOption(CLI::App* sub, const sodt::ParamSpec& s, const char* note);
  void readTableOptions(const CLI::App* sub, sodt::SodtParams& p, const std::string& helpCmd) const;
  void checkSmooth();
  void checkClassify();
  void checkStats();

  CLI::App app_;
  CLI::App* smoothCmd_ = nullptr;
  CLI::App* classifyCmd_ = nullptr;
  CLI::App* statsCmd_ = nullptr;
  bool version_ = false;
  std::vector<std::string> files_[3];  ///< positionals of smooth, classify, stats
  std::string distance_;
  std::vector<std::unique_ptr<TableOption>> tableOptions_;
};

}  // namespace sodt_cli
