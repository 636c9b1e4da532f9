// SPDX-License-Identifier: GPL-3.0-or-later
// RichParameterList <-> core parameters for the S-ODT filters; defaults come
// from SodtParams{} so the dialog, the script and the core always agree.
#include "sodt_rich_params.h"

#include "sodt_meshlab_api.h"

#include <QStringList>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

/// A parameter key in the spelling of the API built against (see
/// sodt_meshlab::kSnakeCaseKeys).
constexpr const char* key(const char* lowerCamel, const char* lowerSnake) {
  return sodt_meshlab::kSnakeCaseKeys ? lowerSnake : lowerCamel;
}

/// The key of a table entry in the spelling of the API built against.
const char* key(const sodt::ParamSpec& s) { return key(s.key, s.pythonKey); }

// The keys of the filters' own parameters (the others are in
// sodt::paramTable()). They become script attributes and Python keyword
// arguments, so they never change once released.
const char* const kOutputClass = key("outputClass", "output_class");
const char* const kSelectFeatures = key("selectFeatures", "select_features");

/// MeshLab keeps float parameters as float: 0.1 typed in a dialog, a script
/// or Python arrives as 0.100000001. Read back as the shortest decimal with a
/// float's 7 significant digits, the value is the one the user wrote, so the
/// plugin and the command line run with the same parameters.
double typedValue(double storedAsFloat) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.7g", static_cast<double>(static_cast<float>(storedAsFloat)));
  return std::strtod(buf, nullptr);
}

/// What the dialog adds to a table entry's help: the plugin's own side of
/// the parameter.
const char* dialogNote(const sodt::ParamSpec& s) {
  const std::string f = s.field;
  if (f == "flips")
    return "Refused on meshes with per-wedge texture coordinates, normals or colours, or with polygonal "
           "faces, which a flip would scramble.";
  if (f == "threads") return "The log reports the threads used.";
  if (f == "selectedOnly")
    return "With a face selection and no vertex selection, the vertices whose faces are all selected are "
           "selected first, so that faces outside the selection keep their shape.";
  return "";
}

/// "Feature-preserving (Algorithm 2), Feature-preserving denoising (Algorithm 3)".
QString algorithmLabels(unsigned bits) {
  QStringList names;
  const sodt::ParamSpec& a = sodt::paramSpec("algorithm");
  for (std::size_t i = 0; i < a.choices.size(); ++i)
    if (bits & sodt::algorithmBit(static_cast<sodt::Algorithm>(i))) names << a.choices[i].label;
  return names.join(", ");
}

/// The tooltip of a table entry: its help, range, unit, choices, the
/// algorithms that use it (in the smoothing dialog) and its details.
QString tooltip(const sodt::ParamSpec& s, bool smoothing) {
  QString t = QString::fromUtf8(s.help);
  if (!t.isEmpty()) t[0] = t[0].toUpper();
  t += ".";
  if (!s.rangeText().empty())
    t += QString(" Range %1%2%3.").arg(QString::fromStdString(s.rangeText()), s.unit[0] ? " " : "", s.unit);
  for (const sodt::ParamChoice& c : s.choices) t += QString(" %1: %2.").arg(c.label, c.help);
  if (smoothing && s.algorithms != sodt::kEveryAlgorithm) t += " Used by " + algorithmLabels(s.algorithms) + ".";
  for (const char* more : {s.details, smoothing ? dialogNote(s) : ""})
    if (more[0] != '\0') t += QString(" ") + QString::fromUtf8(more);
  return t;
}

/// Appends the parameter of a table entry with the given default (as shown).
void appendTableParam(RichParameterList& list, const sodt::ParamSpec& s, double shownDefault, bool smoothing) {
  const QString label = QString::fromUtf8(s.label), tip = tooltip(s, smoothing);
  switch (s.type) {
    case sodt::ParamType::Int:
      list.addParam(RichInt(key(s), static_cast<int>(shownDefault), label, tip));
      break;
    case sodt::ParamType::Real:
      list.addParam(RichFloat(key(s), static_cast<float>(shownDefault), label, tip));
      break;
    case sodt::ParamType::Bool:
      list.addParam(RichBool(key(s), shownDefault != 0, label, tip));
      break;
    case sodt::ParamType::Choice: {
      // With snake_case keys (MeshLab 2021.05+) the entries are the command
      // line's names, so that Python passes algorithm='feature' as the CLI
      // takes --algorithm feature.
      QStringList entries;
      for (const sodt::ParamChoice& c : s.choices) entries << (sodt_meshlab::kSnakeCaseKeys ? c.name : c.label);
      list.addParam(RichEnum(key(s), static_cast<int>(shownDefault), entries, label, tip));
      break;
    }
  }
}

/// Reads a table entry's value back into p, checked against its range.
/// \throw sodt::InvalidInput naming the key when it is out of range.
void readTableParam(const RichParameterList& list, const sodt::ParamSpec& s, sodt::SodtParams& p) {
  double v = 0;
  switch (s.type) {
    case sodt::ParamType::Int: v = list.getInt(key(s)); break;
    case sodt::ParamType::Real: v = typedValue(list.getFloat(key(s))); break;
    case sodt::ParamType::Bool: v = list.getBool(key(s)) ? 1 : 0; break;
    case sodt::ParamType::Choice: v = list.getEnum(key(s)); break;
  }
  s.check(v, key(s));
  s.setShown(p, v);
}

}  // namespace

void appendSodtParams(RichParameterList& list, const MeshModel& m) {
  const sodt::SodtParams d{};
  for (const sodt::ParamSpec& s : sodt::paramTable())
    appendTableParam(list, s, s.defaultOnWithSelection ? (m.cm.svn > 0 || m.cm.sfn > 0) : s.shownValue(d), true);
  list.addParam(RichBool(
      kOutputClass, true, "Output vertex class",
      "After smoothing, write the class of every vertex to its quality (0 smooth, 1 crease, "
      "2 corner, 3 fixed: border or non-manifold) and colour it with a fixed palette (smooth "
      "light grey, crease blue, corner red, fixed yellow). These are the classes the run used: "
      "computed on the input by Algorithms 2 and 3; with Basic every interior vertex is "
      "smooth. Replaces the vertex quality and colour. meshlabserver saves them with -m vq vc."));
}

sodt::SodtParams readSodtParams(const RichParameterList& list) {
  sodt::SodtParams p;
  for (const sodt::ParamSpec& s : sodt::paramTable()) readTableParam(list, s, p);
  return p;
}

bool readOutputClass(const RichParameterList& list) { return list.getBool(kOutputClass); }

/// The classification's parameters in the smoothing filter's table.
const char* const kClassifyFields[] = {"epsilon", "eta"};

void appendClassifyParams(RichParameterList& list) {
  const sodt::SodtParams d{};
  for (const char* f : kClassifyFields) {
    const sodt::ParamSpec& s = sodt::paramSpec(f);
    appendTableParam(list, s, s.shownValue(d), false);
  }
  list.addParam(RichBool(
      kSelectFeatures, SodtClassifyParams{}.selectFeatures, "Select feature vertices",
      "Select exactly the crease and corner vertices and clear the selection of every other "
      "vertex (the face selection is left alone). Handy for inspecting the features or for "
      "protecting them from filters that have an 'Affect only selection' option."));
}

SodtClassifyParams readClassifyParams(const RichParameterList& list) {
  sodt::SodtParams p;
  for (const char* f : kClassifyFields) readTableParam(list, sodt::paramSpec(f), p);
  SodtClassifyParams c;
  c.epsilon = p.epsilon;
  c.eta = p.eta;
  c.selectFeatures = list.getBool(kSelectFeatures);
  return c;
}
