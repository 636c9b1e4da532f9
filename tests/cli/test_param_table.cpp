// SPDX-License-Identifier: GPL-3.0-or-later
// sodt::paramTable() against what is built from it or written after it: the
// core's validate(), the CLI11 app of `sodt` (options, help, parsing), and the
// parameter tables of docs/parameters.md and filter_sodt/README.md, which are
// generated from the table here (SODT_UPDATE_DOCS=1 rewrites them).
#include <gtest/gtest.h>

#include "options.h"

#include <sodt/remesh/flips.h>
#include <sodt/params.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace {

using sodt::ParamSpec;
using sodt::ParamType;

// ---------------------------------------------------------------------------
// The core

TEST(ParamTable, EveryFieldHasOneEntryWithNamesHelpAndRange) {
  std::vector<std::string> seen, reported;
  for (const ParamSpec& s : sodt::paramTable()) {
    SCOPED_TRACE(s.field);
    for (const std::string& name : seen) {
      EXPECT_NE(name, s.field);
    }
    seen.push_back(s.field);
    if (s.reportName() != nullptr) {
      for (const std::string& name : reported) {
        EXPECT_NE(name, s.reportName());
      }
      reported.push_back(s.reportName());
    }
    EXPECT_STRNE(s.key, "");
    EXPECT_STRNE(s.pythonKey, "");
    EXPECT_STRNE(s.label, "");
    EXPECT_STRNE(s.help, "");
    EXPECT_EQ(std::string(s.cliOption).compare(0, 2, "--"), 0);
    // PyMeshLab lower-cases keys into keyword arguments.
    for (const char* c = s.pythonKey; *c; ++c) {
      EXPECT_FALSE(*c >= 'A' && *c <= 'Z') << s.pythonKey;
    }
    if (s.type == ParamType::Int || s.type == ParamType::Real) {
      EXPECT_LT(s.min, s.max);
    }
    if (s.type == ParamType::Choice) {
      EXPECT_GE(s.choices.size(), 2u);
    }
    // A switch can only turn a parameter on.
    if (s.cliValue == nullptr) {
      EXPECT_EQ(s.type, ParamType::Bool);
      EXPECT_EQ(s.defaultText(), "off");
    }
  }
}

/// A value just outside a bound: the bound itself when it is open.
double beyond(const ParamSpec& s, double bound, double direction) {
  const bool open = direction < 0 ? s.minOpen : s.maxOpen;
  if (open) return bound;
  return s.type == ParamType::Int ? bound + direction : bound + direction * std::max(1e-9, std::fabs(bound) * 1e-9);
}

TEST(ParamTable, ValidateChecksEveryRangeOfTheTable) {
  sodt::SodtParams{}.validate();
  for (const ParamSpec& s : sodt::paramTable()) {
    SCOPED_TRACE(s.field);
    if (s.type == ParamType::Bool) continue;
    sodt::SodtParams p;
    if (s.type == ParamType::Choice) {
      for (std::size_t i = 0; i < s.choices.size(); ++i) {
        s.set(p, static_cast<double>(i));
        EXPECT_NO_THROW(p.validate());
        EXPECT_EQ(s.valueText(s.shownValue(p)), s.choices[i].name);
      }
      s.set(p, static_cast<double>(s.choices.size()));
      EXPECT_THROW(p.validate(), sodt::InvalidInput);
      continue;
    }
    for (double bound : {s.min, s.max}) {
      const double dir = bound == s.min ? -1 : 1;
      if (!(dir < 0 ? s.minOpen : s.maxOpen)) {
        s.set(p, bound);
        EXPECT_NO_THROW(p.validate()) << bound;
      }
      s.set(p, beyond(s, bound, dir));
      try {
        p.validate();
        ADD_FAILURE() << "accepted " << s.get(p);
      } catch (const sodt::InvalidInput& e) {
        EXPECT_EQ(std::string(e.what()).find(std::string(s.field) + " must be "), 0u) << e.what();
      }
      p = sodt::SodtParams{};
    }
  }
}

TEST(ParamTable, ShownValuesConvertOnlyByTheScale) {
  const ParamSpec& d = sodt::paramSpec("maxDeviationRel");
  sodt::SodtParams p;
  d.setShown(p, 0.5);  // percent
  EXPECT_EQ(p.maxDeviationRel, 0.5 / 100.0);
  EXPECT_EQ(d.shownValue(p), 100.0 * p.maxDeviationRel);
  EXPECT_EQ(d.defaultText(), "0.1");
  EXPECT_THROW(sodt::paramSpec("noSuchField"), std::logic_error);
}

TEST(ParamTable, FlipRulesTakeTheirDefaultFromSodtParams) {
  EXPECT_DOUBLE_EQ(sodt::FlipRules{}.maxDihedralRad, sodt::SodtParams{}.flipMaxDihedralDeg * sodt::kPi / 180.0);
}

TEST(ParamTable, ResolveThreads) {
#ifdef _OPENMP
  EXPECT_EQ(sodt::resolveThreads(3), 3);
  EXPECT_GE(sodt::resolveThreads(0), 1);
#else
  EXPECT_EQ(sodt::resolveThreads(3), 1);
  EXPECT_EQ(sodt::resolveThreads(0), 1);
#endif
}

// ---------------------------------------------------------------------------
// The CLI

/// `sodt smooth in.ply out.ply EXTRA...` parsed; throws UsageError.
sodt::SodtParams parseSmooth(const std::vector<std::string>& extra) {
  sodt_cli::CommandLine cl;
  std::vector<std::string> args = {"smooth", "in.ply", "out.ply"};
  args.insert(args.end(), extra.begin(), extra.end());
  EXPECT_EQ(cl.parse(args), sodt_cli::Command::Smooth);
  return cl.smooth.params;
}

/// A shown value as the command line takes it.
std::string cliText(const ParamSpec& s, double shown) {
  if (s.type == ParamType::Bool) return shown != 0 ? "on" : "off";
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", shown);
  return s.type == ParamType::Choice ? s.valueText(shown) : b;
}

TEST(ParamTableCli, EveryEntryIsAnOptionOfSmoothWithItsHelpRangeAndDefault) {
  sodt_cli::CommandLine cl;
  const CLI::App* smooth = cl.app().get_subcommand("smooth");
  for (const ParamSpec& s : sodt::paramTable()) {
    SCOPED_TRACE(s.field);
    const CLI::Option* o = cl.smoothOption(s);
    ASSERT_NE(o, nullptr);
    EXPECT_EQ(o, smooth->get_option(s.cliOption));
    EXPECT_EQ(o->get_type_name(), s.cliValue == nullptr ? "" : s.cliValue);
    const std::string& d = o->get_description();
    EXPECT_NE(d.find(s.help), std::string::npos) << d;
    EXPECT_NE(d.find("default " + s.defaultText()), std::string::npos) << d;
    EXPECT_NE(d.find(s.rangeText() + (s.unit[0] ? std::string(" ") + s.unit : "")), std::string::npos) << d;
    EXPECT_NE(d.find(s.details), std::string::npos) << d;
    for (const sodt::ParamChoice& c : s.choices) {
      EXPECT_NE(d.find(c.name), std::string::npos) << d;
      EXPECT_NE(d.find(c.help), std::string::npos) << d;
    }
  }
  // classify takes the classification's two entries, alike.
  const CLI::App* classify = cl.app().get_subcommand("classify");
  for (const char* f : {"epsilon", "eta"}) {
    const ParamSpec& s = sodt::paramSpec(f);
    EXPECT_NE(classify->get_option(s.cliOption)->get_description().find("default " + s.defaultText()),
              std::string::npos);
  }
}

TEST(ParamTableCli, NoOptionsGiveTheDefaultsAndEachOptionSetsItsField) {
  const sodt::SodtParams d{};
  const sodt::SodtParams none = parseSmooth({});
  for (const ParamSpec& s : sodt::paramTable()) {
    SCOPED_TRACE(s.field);
    EXPECT_EQ(s.get(none), s.get(d));
    if (s.cliValue == nullptr) {
      EXPECT_EQ(s.get(parseSmooth({s.cliOption})), 1);
      continue;
    }
    // The default written out, and every choice.
    EXPECT_EQ(s.get(parseSmooth({s.cliOption, cliText(s, s.shownValue(d))})), s.get(d));
    for (std::size_t i = 0; i < s.choices.size(); ++i)
      EXPECT_EQ(s.get(parseSmooth({s.cliOption, s.choices[i].name})), static_cast<double>(i));
  }
}

TEST(ParamTableCli, RangesAreTheTables) {
  for (const ParamSpec& s : sodt::paramTable()) {
    if (s.type != ParamType::Int && s.type != ParamType::Real) continue;
    SCOPED_TRACE(s.field);
    for (double bound : {s.min, s.max}) {
      const double dir = bound == s.min ? -1 : 1;
      if (!(dir < 0 ? s.minOpen : s.maxOpen)) {
        EXPECT_EQ(s.get(parseSmooth({s.cliOption, cliText(s, s.shown(bound))})), bound);
      }
      const std::string bad = cliText(s, s.shown(beyond(s, bound, dir)));
      try {
        sodt_cli::CommandLine cl;
        cl.parse({"smooth", "in.ply", "out.ply", s.cliOption, bad});
        ADD_FAILURE() << "accepted " << s.cliOption << " " << bad;
      } catch (const sodt_cli::UsageError& e) {
        EXPECT_EQ(std::string(e.what()).find(std::string(s.cliOption) + " must be "), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find(ParamSpec::numberText(s.shown(s.max))), std::string::npos) << e.what();
      }
    }
  }
}

// ---------------------------------------------------------------------------
// The docs: their parameter tables are generated from sodt::paramTable().

const char* const kBegin =
    "<!-- Generated from sodt::paramTable() (vcg_core/sodt/params.h) by tests/cli/test_param_table.cpp; "
    "SODT_UPDATE_DOCS=1 ctest -R ParamTableDocs rewrites it. -->\n";
const char* const kEnd = "<!-- End of the generated table. -->\n";

/// Markdown cell text: no '|' and no line break.
std::string cell(std::string s) {
  for (std::size_t i = s.find('|'); i != std::string::npos; i = s.find('|', i + 2)) s.replace(i, 1, "\\|");
  return s;
}

/// "Used by feature and denoise." (nothing when every algorithm uses it).
std::string usedBy(const ParamSpec& s) {
  if (s.algorithms == sodt::kEveryAlgorithm) return "";
  std::string names;
  int n = 0, count = 0;
  for (int a = 0; a <= static_cast<int>(sodt::Algorithm::Filtered); ++a)
    count += (s.algorithms & sodt::algorithmBit(static_cast<sodt::Algorithm>(a))) ? 1 : 0;
  for (int a = 0; a <= static_cast<int>(sodt::Algorithm::Filtered); ++a)
    if (s.algorithms & sodt::algorithmBit(static_cast<sodt::Algorithm>(a)))
      names += std::string(n++ == 0 ? "" : n == count ? " and " : ", ") + "`" +
               sodt::toString(static_cast<sodt::Algorithm>(a)) + "`";
  return " Used by " + names + ".";
}

/// A Markdown table with one row per table entry.
std::string markdownTable(const std::vector<std::string>& header,
                          const std::function<std::vector<std::string>(const ParamSpec&)>& row) {
  std::string out, rule;
  for (const std::string& h : header) {
    out += "| " + h + " ";
    rule += "|---";
  }
  out += "|\n" + rule + "|\n";
  for (const ParamSpec& s : sodt::paramTable()) {
    for (const std::string& c : row(s)) out += "| " + cell(c) + " ";
    out += "|\n";
  }
  return out;
}

/// "[0, 100] percent of the bounding-box diagonal"; "" for on/off and choices.
std::string rangeWithUnit(const ParamSpec& s) {
  const std::string r = s.rangeText();
  return r.empty() || s.unit[0] == '\0' ? r : r + " " + s.unit;
}

/// The table of docs/parameters.md: every name, type, default, range and help.
std::string parametersTable() {
  return markdownTable(
      {"MeshLab 2020.09 key", "Python key (MeshLab 2025.07)", "CLI option", "type", "default", "range", "meaning"},
      [](const ParamSpec& s) -> std::vector<std::string> {
        static const char* const types[] = {"integer", "number", "on/off", "choice"};
        std::string def = "`" + s.defaultText() + "`";
        if (s.defaultOnWithSelection) def += "; plugin: on when the mesh has a selection";
        std::string meaning = s.help;
        meaning[0] = static_cast<char>(std::toupper(meaning[0]));
        meaning += ".";
        for (std::size_t i = 0; i < s.choices.size(); ++i)
          meaning += std::string(i == 0 ? " " : "; ") + "`" + s.choices[i].name + "` (" + std::to_string(i) +
                     "): " + s.choices[i].help + (i + 1 == s.choices.size() ? "." : "");
        meaning += usedBy(s);
        if (s.details[0]) meaning += std::string(" ") + s.details;
        const std::string cli = s.cliValue ? std::string(s.cliOption) + " " + s.cliValue : s.cliOption;
        return {std::string("`") + s.key + "`", std::string("`") + s.pythonKey + "`", "`" + cli + "`",
                types[static_cast<int>(s.type)], def, rangeWithUnit(s), meaning};
      });
}

/// The table of filter_sodt/README.md: the dialog's view (types, defaults as
/// the dialog shows them, the algorithms of the paper that use each).
std::string pluginTable() {
  return markdownTable(
      {"Key (2020.09)", "Key (2025.07, Python)", "Type", "Default", "Alg.", "Meaning"},
      [](const ParamSpec& s) -> std::vector<std::string> {
        static const char* const types[] = {"RichInt", "RichFloat", "RichBool", "RichEnum"};
        const double v = s.shownValue(sodt::SodtParams{});
        std::string def;
        switch (s.type) {
          case ParamType::Bool: def = s.defaultOnWithSelection ? "selection exists" : v != 0 ? "true" : "false"; break;
          case ParamType::Choice: def = std::to_string(static_cast<int>(v)); break;
          default: def = s.defaultText();
        }
        std::string alg;
        for (int a = 0; a < 3; ++a)
          if (s.algorithms & sodt::algorithmBit(static_cast<sodt::Algorithm>(a)))
            alg += (alg.empty() ? "" : " ") + std::to_string(a + 1);
        std::string meaning = s.help;
        if (!s.rangeText().empty()) meaning += "; " + rangeWithUnit(s);
        for (std::size_t i = 0; i < s.choices.size(); ++i)
          meaning += std::string(i == 0 ? ": " : ", ") + std::to_string(i) + " = " + s.choices[i].label;
        return {std::string("`") + s.key + "`", std::string("`") + s.pythonKey + "`", types[static_cast<int>(s.type)],
                def, alg, meaning};
      });
}

std::string readText(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

/// Compares the generated block of a Markdown file with `table`; rewrites it
/// when SODT_UPDATE_DOCS=1.
void expectGenerated(const std::string& path, const std::string& table) {
  const std::string text = readText(path);
  const std::size_t begin = text.find(kBegin), end = text.find(kEnd);
  ASSERT_NE(begin, std::string::npos) << path << " has no generated table (" << kBegin << ")";
  ASSERT_NE(end, std::string::npos) << path;
  const std::size_t from = begin + std::string(kBegin).size();
  const std::string committed = text.substr(from, end - from);
  const char* update = std::getenv("SODT_UPDATE_DOCS");
  if (committed != table && update != nullptr && std::string(update) == "1") {
    std::ofstream(path, std::ios::binary) << text.substr(0, from) << table << text.substr(end);
    return;
  }
  if (committed == table) return;
  // The first row that differs, not the whole table.
  std::istringstream a(committed), b(table);
  std::string la, lb;
  while (std::getline(a, la) && std::getline(b, lb) && la == lb) {
  }
  ADD_FAILURE() << path << " differs from sodt::paramTable() (SODT_UPDATE_DOCS=1 rewrites it):\n  committed: " << la
                << "\n  generated: " << lb;
}

TEST(ParamTableDocs, ParametersMdIsTheTable) {
  expectGenerated(std::string(SODT_SOURCE_DIR) + "/docs/parameters.md", parametersTable());
}

TEST(ParamTableDocs, PluginReadmeIsTheTable) {
  expectGenerated(std::string(SODT_SOURCE_DIR) + "/filter_sodt/README.md", pluginTable());
}

}  // namespace
