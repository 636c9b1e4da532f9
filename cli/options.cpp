// SPDX-License-Identifier: GPL-3.0-or-later
// The `sodt` command line: CLI11 subcommands whose smoothing options come from
// sodt::paramTable(), their help (wrapped to 80 columns), and the strict
// checks of numbers, choices and file names (exit status 2 when one fails).
#include "options.h"

#include <sodt_io/io.h>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace sodt_cli {

std::string numberText(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

double creaseAngleDeg(double epsilon) { return std::acos(epsilon / (epsilon + 2.0)) * 180.0 / M_PI; }

std::string canonicalPath(const std::string& p) {
  if (char* r = ::realpath(p.c_str(), nullptr)) {
    std::string s(r);
    std::free(r);
    return s;
  }
  const std::size_t slash = p.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : p.substr(0, slash));
  const std::string base = slash == std::string::npos ? p : p.substr(slash + 1);
  if (char* r = ::realpath(dir.c_str(), nullptr)) {
    std::string s(r);
    std::free(r);
    return s + "/" + base;
  }
  return p;
}

namespace {

bool samePath(const std::string& a, const std::string& b) { return canonicalPath(a) == canonicalPath(b); }

const char* const kMainHelpCmd = "sodt --help";
const char* const kSmoothHelpCmd = "sodt smooth --help";
const char* const kClassifyHelpCmd = "sodt classify --help";
const char* const kStatsHelpCmd = "sodt stats --help";

// ---------------------------------------------------------------------------
// Help layout

constexpr std::size_t kHelpWidth = 80;    ///< columns of the help text
constexpr std::size_t kDescColumn = 24;  ///< where option descriptions start

/// Wraps text into lines of at most kHelpWidth columns, each indented by
/// `indent` spaces. A '\n' starts a new line; a line that begins with spaces
/// (a list entry "  name  text") continues under its text.
std::string wrap(const std::string& text, std::size_t indent) {
  std::string out;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    std::size_t hang = 0;
    if (!line.empty() && line[0] == ' ') {  // "  basic    text": continue under "text"
      const std::size_t word = line.find_first_not_of(' ');
      const std::size_t gap = line.find(' ', word);
      hang = gap == std::string::npos ? 0 : line.find_first_not_of(' ', gap);
      if (hang == std::string::npos) hang = 0;
    }
    std::string cur(indent, ' ');
    bool empty = true;  // no word on cur yet
    std::size_t pos = 0;
    while (pos < line.size()) {
      const std::size_t wordStart = line.find_first_not_of(' ', pos);
      if (wordStart == std::string::npos) break;
      std::size_t wordEnd = line.find(' ', wordStart);
      if (wordEnd == std::string::npos) wordEnd = line.size();
      // A range "[0, 90]" stays on one line.
      const std::size_t close = line.find_first_of("])", wordStart);
      if ((line[wordStart] == '[' || line[wordStart] == '(') && line[wordEnd - 1] == ',' &&
          close != std::string::npos && close > wordEnd && close - wordStart < 20) {
        const std::size_t after = line.find(' ', close);
        wordEnd = after == std::string::npos ? line.size() : after;
      }
      const std::string gap = line.substr(pos, wordStart - pos), word = line.substr(wordStart, wordEnd - wordStart);
      if (!empty && cur.size() + gap.size() + word.size() > kHelpWidth) {
        out += cur + "\n";
        cur = std::string(indent + hang, ' ') + word;
      } else {
        cur += gap + word;
      }
      empty = false;
      pos = wordEnd;
    }
    out += cur + "\n";
    if (end == text.size()) break;
    start = end + 1;
  }
  return out;
}

/// "  --name VALUE          description", the description wrapped in its column.
std::string optionHelp(const CLI::Option* o) {
  std::string name = o->get_name(false, true);
  for (std::size_t c = name.find(','); c != std::string::npos; c = name.find(',', c + 2)) name.insert(c + 1, " ");
  std::string left = "  " + name;
  if (!o->get_type_name().empty()) left += " " + o->get_type_name();
  const std::string desc = wrap(o->get_description(), kDescColumn);
  if (left.size() + 2 <= kDescColumn) return left + desc.substr(left.size());
  return left + "\n" + desc;
}

/// Help of an app: its description (usage and what it does), its options
/// group by group with -h/--help last, and its footer.
class HelpFormatter : public CLI::Formatter {
 public:
  std::string make_help(const CLI::App* app, std::string, CLI::AppFormatMode) const override {
    std::string out = app->get_description();
    std::string group;
    for (const CLI::Option* o : app->get_options()) {
      if (o->get_positional() || o->get_group().empty() || o == app->get_help_ptr()) continue;
      if (o->get_group() != group) {
        group = o->get_group();
        out += "\n" + group + ":\n";
      }
      out += optionHelp(o);
    }
    if (!group.empty() && app->get_help_ptr() != nullptr) out += optionHelp(app->get_help_ptr());
    const std::string footer = app->get_footer();
    return footer.empty() ? out : out + "\n" + footer;
  }
};

const char* const kMainHelp =
    "usage: sodt <command> [options]\n"
    "       sodt --help | --version\n"
    "\n"
    "S-ODT surface mesh smoothing: moves every interior vertex in its tangent plane to\n"
    "the closed-form minimiser of the suboptimal Delaunay triangulation energy, which\n"
    "improves triangle angles while keeping the surface (paper Algorithm 1); variants\n"
    "keep creases and corners (Algorithm 2) or also remove noise (Algorithm 3).\n"
    "\n"
    "commands:\n"
    "  smooth IN OUT       smooth the triangle mesh IN and write it to OUT\n"
    "  classify IN OUT.ply mark every vertex of IN smooth, crease or corner (nothing moves)\n"
    "  stats IN            print quality measures of IN as JSON\n"
    "\n"
    "Mesh files are PLY, OFF, OBJ or STL (binary or ASCII), chosen by extension\n"
    "(case-insensitive). Polygons are fan-triangulated on input; the corners of STL\n"
    "triangles with equal coordinates are welded into one vertex. STL is written in\n"
    "binary single precision (refused when rounding would merge vertices), without\n"
    "the vertices no face uses. PLY keeps vertex normals, texture coordinates,\n"
    "colour, quality and selection; 'smooth' warns of what OUT does not keep.\n"
    "Run 'sodt <command> --help' for the options of a command.\n"
    "\n"
    "exit status: 0 success, 1 unreadable or invalid input or I/O failure,\n"
    "             2 bad command line. Output files are replaced only at the very\n"
    "             end of a successful run, never partially written.\n";

const char* const kSmoothIntro =
    "usage: sodt smooth IN OUT [options]\n"
    "\n"
    "Smooths the triangle mesh IN with S-ODT and writes the result to OUT (PLY or\n"
    "OFF by OUT's extension; PLY is written binary). Border and non-manifold\n"
    "vertices stay fixed. OUT keeps the per-vertex quality, colour and selection\n"
    "flags found in IN (PLY; OFF keeps colour only). OUT and the other output\n"
    "files are written under temporary names and renamed at the very end, so a\n"
    "failed or interrupted run leaves them as they were; OUT may be IN itself.\n";

const char* const kClassifyIntro =
    "usage: sodt classify IN OUT.ply [--epsilon X] [--eta X] [--json FILE]\n"
    "\n"
    "Classifies every vertex of IN by the normal tensor of its one-ring (paper\n"
    "Eq. 9-10), as 'sodt smooth --algorithm feature' does before smoothing, and\n"
    "writes IN unmoved to OUT (PLY only) with the class as per-vertex quality\n"
    "(0 smooth, 1 crease, 2 corner, 3 fixed: border or non-manifold) and colour\n"
    "(grey, blue, red, yellow). Prints the number of vertices in each class.\n"
    "(--algorithm denoise classifies the input after removing its noise; see\n"
    "'sodt smooth --classes-out'.)\n";

const char* const kStatsIntro =
    "usage: sodt stats IN [--reference REF] [--json FILE]\n"
    "\n"
    "Prints as JSON: vertices, faces, closed, min_angle, max_angle, angle_histogram\n"
    "(180 one-degree bins of all corner angles), frac_below_30, frac_above_90,\n"
    "p1_tri_min_angle (1st percentile of the per-triangle smallest angle), volume\n"
    "(null when the mesh is not closed and consistently oriented), border_length\n"
    "(the length of the edges with one face; 0 for a closed mesh) and noise_estimate\n"
    "(the noise along the normals in mean edge lengths, from how well a quadric\n"
    "through each vertex's two-ring predicts it; below 0.05: nearly noise-free).\n";

/// What `sodt smooth --help` adds to a table entry's text: the command
/// line's own side of the parameter.
const char* smoothNote(const sodt::ParamSpec& s) {
  const std::string f = s.field;
  if (f == "flips")
    return "When the returned mesh has other faces than IN, the report's inverted_faces compares each face "
           "with the face of IN nearest its centroid instead of face by face.";
  if (f == "threads")
    return "OUT and the report are bit-identical for every N, apart from the report's seconds and threads.";
  if (f == "selectedOnly")
    return "The selection is read from the PLY per-vertex 'flags' property (MeshLab: export with 'Flags' "
           "ticked); plain PLY and OFF files select nothing, which is an error.";
  return "";
}

/// The names of the algorithms that use a parameter: "feature and denoise".
std::string algorithmNames(unsigned bits) {
  std::vector<std::string> names;
  for (int a = 0; a <= static_cast<int>(sodt::Algorithm::Filtered); ++a)
    if (bits & sodt::algorithmBit(static_cast<sodt::Algorithm>(a)))
      names.push_back(sodt::toString(static_cast<sodt::Algorithm>(a)));
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i)
    s += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  return s;
}

/// The help of a table entry's option: its one-line help, range, unit and
/// default, the choices, which algorithms use it (for smooth), its details
/// and a note.
std::string tableOptionHelp(const sodt::ParamSpec& s, const char* note, bool smoothing) {
  std::string t = s.help;
  if (!s.rangeText().empty()) {
    t += "; " + s.rangeText();
    if (s.unit[0] != '\0') t += std::string(" ") + s.unit;
    t += ",";
  } else {
    t += ";";
  }
  t += " default " + s.defaultText();
  if (s.type == sodt::ParamType::Choice) {
    t += ":";
    for (const sodt::ParamChoice& c : s.choices) {
      std::string name = c.name;
      name.resize(std::max<std::size_t>(name.size() + 1, 10), ' ');
      t += std::string("\n  ") + name + c.help;
    }
  } else {
    t += ".";
  }
  std::string more;
  if (smoothing && s.algorithms != sodt::kEveryAlgorithm) more += "Used by " + algorithmNames(s.algorithms) + ".";
  for (const char* extra : {s.details, note})
    if (extra[0] != '\0') more += std::string(more.empty() ? "" : " ") + extra;
  if (!more.empty()) t += (s.type == sodt::ParamType::Choice ? "\n" : " ") + more;
  return t;
}

/// Parses a whole decimal integer ("12", "-1", "+3"); the range is checked by the caller.
int parseInt(const std::string& option, const std::string& s, const std::string& helpCmd) {
  std::size_t i = (!s.empty() && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
  bool digits = i < s.size();
  for (std::size_t k = i; k < s.size(); ++k) digits = digits && s[k] >= '0' && s[k] <= '9';
  if (!digits) throw UsageError("option '" + option + "' needs an integer, got '" + s + "'", helpCmd);
  errno = 0;
  const long long v = std::strtoll(s.c_str(), nullptr, 10);
  if (errno == ERANGE || v < INT_MIN || v > INT_MAX)
    throw UsageError("option '" + option + "': " + s + " is out of range", helpCmd);
  return static_cast<int>(v);
}

/// Parses a whole decimal number ("2", "-0.5", "1e-3"): no spaces, no
/// hexadecimal, nan or inf; the range is checked by the caller.
double parseNumber(const std::string& option, const std::string& s, const std::string& helpCmd) {
  const std::size_t i = (!s.empty() && s[0] == '-') ? 1 : 0;
  bool ok = i < s.size() && ((s[i] >= '0' && s[i] <= '9') || s[i] == '.');
  for (std::size_t k = i; k < s.size(); ++k) {
    const char c = s[k];
    ok = ok && ((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-');
  }
  errno = 0;
  char* end = nullptr;
  const double v = ok ? std::strtod(s.c_str(), &end) : 0.0;
  if (!ok || end != s.c_str() + s.size())
    throw UsageError("option '" + option + "' needs a number, got '" + s + "'", helpCmd);
  if (errno == ERANGE || !std::isfinite(v))
    throw UsageError("option '" + option + "': " + s + " is out of range", helpCmd);
  return v;
}

/// "on" or "off".
bool parseOnOff(const std::string& option, const std::string& s, const std::string& helpCmd) {
  if (s != "on" && s != "off") throw UsageError("option '" + option + "' takes on or off, got '" + s + "'", helpCmd);
  return s == "on";
}

/// Rejects a file name whose extension is not .ply (per-vertex quality is PLY only).
void checkPlyPath(const std::string& option, const std::string& path, const std::string& helpCmd) {
  bool ply = false;
  try {
    ply = sodt::meshFormatFromPath(path) == sodt::MeshFormat::Ply;
  } catch (const sodt::InvalidInput&) {
  }
  if (!ply)
    throw UsageError(option + " must be a .ply file (only PLY stores per-vertex quality), got '" + path + "'",
                     helpCmd);
}

/// Rejects a file-name option given an empty name ("--report ''").
void checkFileName(const CLI::Option* o, const std::string& v, const std::string& helpCmd) {
  if (o->count() > 0 && v.empty())
    throw UsageError("option '" + o->get_name() + "' needs a file name", helpCmd);
}

/// "'sodt smooth' needs an input and an output file, got 3 file arguments".
void checkFileCount(const std::vector<std::string>& files, std::size_t want, const std::string& what,
                    const std::string& helpCmd) {
  if (files.size() == want) return;
  throw UsageError(what + ", got " + std::to_string(files.size()) + " file argument" +
                       (files.size() == 1 ? "" : "s"),
                   helpCmd);
}

/// CLI11's message as one of ours: "option '--x' needs a value" for a
/// missing value, "option '--x' takes no value" for a switch given one.
std::string usageMessage(const CLI::ParseError& e) {
  const std::string m = e.what();
  const std::string missing = " missing", override = " was given a disallowed flag override";
  const std::size_t colon = m.find(": ");
  if (colon != std::string::npos && m.size() > missing.size() &&
      m.compare(m.size() - missing.size(), missing.size(), missing) == 0)
    return "option '" + m.substr(0, colon) + "' needs a value";
  const std::size_t at = m.find(override);
  if (at != std::string::npos) {
    const std::string name = m.substr(0, at);
    return "option '" + (name.compare(0, 1, "-") == 0 ? name : "--" + name) + "' takes no value";
  }
  return m;
}

}  // namespace

struct CommandLine::TableOption {
  TableOption(const sodt::ParamSpec& s, const CLI::App* app) : spec(&s), sub(app) {}
  const sodt::ParamSpec* spec;
  const CLI::App* sub;
  CLI::Option* option = nullptr;
  std::string text;    ///< the value given
  bool given = false;  ///< a switch was given
};

CommandLine::CommandLine() : app_(kMainHelp, "sodt") {
  app_.formatter(std::make_shared<HelpFormatter>());
  // Unknown arguments are collected, not thrown, so that the message can
  // say which command or option is unknown.
  app_.allow_extras();
  // A repeated option: the last one counts.
  app_.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app_.set_help_flag("-h,--help", "show this help")->group("");
  app_.add_flag("--version", version_, "print the version")->group("")->disable_flag_override();
  app_.require_subcommand(0, 1);

  const std::string group = "options";
  smoothCmd_ = app_.add_subcommand("smooth", kSmoothIntro);
  classifyCmd_ = app_.add_subcommand("classify", kClassifyIntro);
  statsCmd_ = app_.add_subcommand("stats", kStatsIntro);
  CLI::App* subs[3] = {smoothCmd_, classifyCmd_, statsCmd_};
  for (int i = 0; i < 3; ++i) {
    subs[i]->allow_extras();
    subs[i]->set_help_flag("-h,--help", "show this help");
    subs[i]->add_option("files", files_[i]);
  }

  // smooth: every table entry, then the command line's own options.
  smoothCmd_->option_defaults()->group("options (defaults are those of the library, sodt::SodtParams)");
  tableOptions_.reserve(sodt::paramTable().size() + 2);
  for (const sodt::ParamSpec& s : sodt::paramTable()) addTableOption(smoothCmd_, s, smoothNote(s));
  smoothCmd_->add_option("--report", smooth.report,
                         "write measures before/after, distances, counters and the class counts as JSON")
      ->type_name("FILE.json");
  smoothCmd_->add_option("--distance", distance_,
                         "measure the sampled surface distance between IN and OUT for the summary and the report "
                         "(default on). It is the slowest measure: on a large mesh it takes about as long as the "
                         "smoothing. off leaves it out (the report's distances are null); OUT is the same either "
                         "way")
      ->type_name("on|off");
  smoothCmd_->add_option("--classes-out", smooth.classesOut,
                         "also write the smoothed mesh with the class of every vertex as per-vertex quality "
                         "(0 smooth, 1 crease, 2 corner, 3 fixed: border or non-manifold) and colour (grey, "
                         "blue, red, yellow); PLY only. With basic every interior vertex is smooth")
      ->type_name("FILE.ply");
  smoothCmd_->add_flag("--quiet", smooth.quiet, "no summary on stdout and no progress bar")
      ->disable_flag_override();
  smoothCmd_->footer("The progress bar is drawn on stderr only when stderr is a terminal.\n");

  // classify: the classification's two table entries.
  classifyCmd_->option_defaults()->group(group);
  for (const char* f : {"epsilon", "eta"}) addTableOption(classifyCmd_, sodt::paramSpec(f), "");
  classifyCmd_->add_option("--json", classify.json, "also write the counts and parameters as JSON to FILE")
      ->type_name("FILE");

  statsCmd_->option_defaults()->group(group);
  statsCmd_->add_option("--reference", stats.reference,
                        "also hausdorff_rel, hausdorff_edges_rel (with points along every edge too) and "
                        "mean_distance_rel (sampled surface distances relative to REF's bounding-box diagonal) "
                        "and inverted_faces (faces turned by more than 90 degrees "
                        "against REF: face by face when REF has the same vertices and faces, else each "
                        "face against the face of REF nearest its centroid)")
      ->type_name("REF");
  statsCmd_->add_option("--json", stats.json, "write the JSON to FILE instead of stdout")->type_name("FILE");
}

CommandLine::~CommandLine() = default;

void CommandLine::addTableOption(CLI::App* sub, const sodt::ParamSpec& s, const char* note) {
  tableOptions_.emplace_back(new TableOption(s, sub));
  TableOption& t = *tableOptions_.back();
  const std::string help = tableOptionHelp(s, note, sub == smoothCmd_);
  if (s.cliValue == nullptr)
    t.option = sub->add_flag(s.cliOption, t.given, help)->disable_flag_override();
  else
    t.option = sub->add_option(s.cliOption, t.text, help)->type_name(s.cliValue);
}

const CLI::Option* CommandLine::smoothOption(const sodt::ParamSpec& s) const {
  for (const auto& t : tableOptions_)
    if (t->sub == smoothCmd_ && t->spec == &s) return t->option;
  return nullptr;
}

void CommandLine::readTableOptions(const CLI::App* sub, sodt::SodtParams& p, const std::string& helpCmd) const {
  for (const auto& t : tableOptions_) {
    if (t->sub != sub || t->option->count() == 0) continue;
    const sodt::ParamSpec& s = *t->spec;
    const std::string name = s.cliOption;
    try {
      switch (s.type) {
        case sodt::ParamType::Bool:
          s.set(p, s.cliValue == nullptr ? 1 : parseOnOff(name, t->text, helpCmd));
          break;
        case sodt::ParamType::Choice:
          s.set(p, s.choiceIndex(t->text, s.field));
          break;
        case sodt::ParamType::Int: {
          const int v = parseInt(name, t->text, helpCmd);
          s.check(v, name);
          s.setShown(p, v);
          break;
        }
        case sodt::ParamType::Real: {
          const double v = parseNumber(name, t->text, helpCmd);
          s.check(v, name);
          s.setShown(p, v);
          break;
        }
      }
    } catch (const sodt::InvalidInput& e) {
      const std::string what = e.what();
      throw UsageError(what.compare(0, name.size(), name) == 0 ? what : "option '" + name + "': " + what, helpCmd);
    }
  }
  try {
    p.validate();
  } catch (const sodt::InvalidInput& e) {
    throw UsageError(e.what(), helpCmd);
  }
}

Command CommandLine::parse(const std::vector<std::string>& args) {
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
  try {
    app_.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    const std::vector<CLI::App*> subs = app_.get_subcommands();
    std::fputs((subs.empty() ? app_.help() : subs[0]->help()).c_str(), stdout);
    return Command::Done;
  } catch (const CLI::ParseError& e) {
    const std::vector<CLI::App*> subs = app_.get_subcommands();
    throw UsageError(usageMessage(e), subs.empty() ? kMainHelpCmd : "sodt " + subs[0]->get_name() + " --help");
  }
  const std::vector<std::string> extra = app_.remaining();
  if (!extra.empty()) {
    if (extra[0] == "help") {
      std::fputs(app_.help().c_str(), stdout);
      return Command::Done;
    }
    if (extra[0].compare(0, 1, "-") == 0 && extra[0].size() > 1)
      throw UsageError("unknown option '" + extra[0] + "'", kMainHelpCmd);
    throw UsageError("unknown command '" + extra[0] + "' (expected smooth, classify or stats)", kMainHelpCmd);
  }
  if (version_) return Command::Version;
  const std::vector<CLI::App*> subs = app_.get_subcommands();
  if (subs.empty()) throw UsageError("no command given", kMainHelpCmd);
  for (const std::string& r : subs[0]->remaining())
    if (r != "--") throw UsageError("unknown option '" + r + "'", "sodt " + subs[0]->get_name() + " --help");
  if (subs[0] == smoothCmd_) {
    checkSmooth();
    return Command::Smooth;
  }
  if (subs[0] == classifyCmd_) {
    checkClassify();
    return Command::Classify;
  }
  checkStats();
  return Command::Stats;
}

void CommandLine::checkSmooth() {
  SmoothOptions& o = smooth;
  const std::string h = kSmoothHelpCmd;
  readTableOptions(smoothCmd_, o.params, h);
  if (smoothCmd_->get_option("--distance")->count() > 0) o.distance = parseOnOff("--distance", distance_, h);
  checkFileName(smoothCmd_->get_option("--report"), o.report, h);
  checkFileName(smoothCmd_->get_option("--classes-out"), o.classesOut, h);
  checkFileCount(files_[0], 2, "'sodt smooth' needs an input and an output file", h);
  o.in = files_[0][0];
  o.out = files_[0][1];
  try {
    sodt::meshFormatFromPath(o.out);
  } catch (const sodt::InvalidInput& e) {
    throw UsageError(std::string("output ") + e.what(), h);
  }
  if (!o.report.empty()) {
    if (samePath(o.report, o.out)) throw UsageError("--report and OUT are the same file", h);
    if (samePath(o.report, o.in)) throw UsageError("--report would overwrite the input", h);
  }
  if (!o.classesOut.empty()) {
    checkPlyPath("--classes-out", o.classesOut, h);
    if (samePath(o.classesOut, o.out)) throw UsageError("--classes-out and OUT are the same file", h);
    if (samePath(o.classesOut, o.in)) throw UsageError("--classes-out would overwrite the input", h);
    if (!o.report.empty() && samePath(o.classesOut, o.report))
      throw UsageError("--classes-out and --report are the same file", h);
  }
}

void CommandLine::checkClassify() {
  ClassifyOptions& o = classify;
  const std::string h = kClassifyHelpCmd;
  readTableOptions(classifyCmd_, o.params, h);
  checkFileName(classifyCmd_->get_option("--json"), o.json, h);
  checkFileCount(files_[1], 2, "'sodt classify' needs an input and an output file", h);
  o.in = files_[1][0];
  o.out = files_[1][1];
  checkPlyPath("OUT", o.out, h);
  if (samePath(o.out, o.in)) throw UsageError("OUT would overwrite the input", h);
  if (!o.json.empty()) {
    if (samePath(o.json, o.out)) throw UsageError("--json and OUT are the same file", h);
    if (samePath(o.json, o.in)) throw UsageError("--json would overwrite the input", h);
  }
}

void CommandLine::checkStats() {
  StatsOptions& o = stats;
  const std::string h = kStatsHelpCmd;
  checkFileName(statsCmd_->get_option("--reference"), o.reference, h);
  checkFileName(statsCmd_->get_option("--json"), o.json, h);
  if (files_[2].size() != 1)
    throw UsageError("'sodt stats' needs exactly one input file, got " + std::to_string(files_[2].size()), h);
  o.in = files_[2][0];
  if (!o.json.empty() && (samePath(o.json, o.in) || (!o.reference.empty() && samePath(o.json, o.reference))))
    throw UsageError("--json would overwrite an input file", h);
}

}  // namespace sodt_cli
