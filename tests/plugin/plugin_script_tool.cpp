// SPDX-License-Identifier: GPL-3.0-or-later
// Loads a built MeshLab 2020.09 filter plugin and writes the .mlx script of one
// of its filters with MeshLab's own serializer, or checks a shipped script.
//
// Usage:
//   sodt_plugin_script_tool PLUGIN.so "FILTER NAME" --write OUT.mlx [--set NAME=VALUE]...
//   sodt_plugin_script_tool PLUGIN.so "FILTER NAME" --check SHIPPED.mlx
//   sodt_plugin_script_tool PLUGIN.so "FILTER NAME" --check-table
// --write saves the filter's parameter list with its defaults, serialized by
// MeshLab (as the GUI's "Save filter script" does, minus descriptions); each
// --set replaces the default of an existing parameter by a value that MeshLab
// parses for its type (an enum index must be in range) and is recorded in the
// file's header comment. --check verifies that SHIPPED.mlx names the
// filter once and lists exactly the plugin's parameters, in order, with the
// same names and types, that MeshLab parses every value, and that enum values
// are in range: the conditions under which meshlabserver 2020.09 neither
// aborts nor silently falls back to a default. --check-table verifies that
// the filter's parameter list holds every sodt::paramTable() entry it should
// (all for the smoothing filter, epsilon and eta for the classification)
// with the entry's key, type, default, dialog label, enum labels, and a
// tooltip with its help, range, unit and details.
// Exit status: 0 ok, 1 check failed, 2 usage or loading error.

#include <common/filterscript.h>
#include <common/interfaces.h>
#include <common/meshmodel.h>

#include <sodt/params.h>

#include <QCoreApplication>
#include <QDomDocument>
#include <QFile>
#include <QFileInfo>
#include <QXmlStreamWriter>
#include <QPluginLoader>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <vector>

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: sodt_plugin_script_tool PLUGIN.so \"FILTER NAME\" --write OUT.mlx "
               "[--set NAME=VALUE]...\n"
               "       sodt_plugin_script_tool PLUGIN.so \"FILTER NAME\" --check SHIPPED.mlx\n"
               "       sodt_plugin_script_tool PLUGIN.so \"FILTER NAME\" --check-table\n");
  return 2;
}

/// One <Param> element of a script as written in the file.
struct XmlParam {
  QString name, type, value;
};

/// Reads the <Param> elements of every <filter name=filterName> in path.
/// Returns the number of such filters, or -1 when the file is not a script.
int readXmlParams(const QString& path, const QString& filterName, QList<XmlParam>& out) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly)) return -1;
  QDomDocument doc;
  if (!doc.setContent(&f)) return -1;
  const QDomElement root = doc.documentElement();
  if (root.nodeName() != "FilterScript") return -1;
  int found = 0;
  for (QDomElement e = root.firstChildElement("filter"); !e.isNull();
       e = e.nextSiblingElement("filter")) {
    if (e.attribute("name") != filterName) continue;
    ++found;
    for (QDomElement p = e.firstChildElement("Param"); !p.isNull();
         p = p.nextSiblingElement("Param"))
      out.append({p.attribute("name"), p.attribute("type"), p.attribute("value")});
  }
  return found;
}

/// Compares a shipped script with the plugin's parameter list; prints every
/// problem and returns how many there are.
int checkScript(const QString& path, const QString& filterName, const RichParameterList& plugin) {
  int problems = 0;
  auto problem = [&problems](const QString& what) {
    std::fprintf(stderr, "mlx check: %s\n", qUtf8Printable(what));
    ++problems;
  };

  QList<XmlParam> xml;
  const int filters = readXmlParams(path, filterName, xml);
  if (filters < 0) {
    problem("'" + path + "' is not a readable FilterScript XML file");
    return problems;
  }
  if (filters != 1)
    problem(QString("expected exactly one <filter name=\"%1\">, found %2").arg(filterName).arg(filters));

  // What meshlabserver itself makes of the file: a value it cannot parse is
  // dropped silently and the default is used instead.
  FilterScript parsed;
  if (!parsed.open(path)) problem("MeshLab's FilterScript::open rejects '" + path + "'");
  int parsedCount = 0;
  for (const FilterNameParameterValuesPair& f : parsed)
    if (f.filterName() == filterName) parsedCount += f.second.size();
  if (parsedCount != xml.size())
    problem(QString("MeshLab parsed %1 of the %2 <Param> values (a value it cannot parse is "
                    "replaced by the default)")
                .arg(parsedCount)
                .arg(xml.size()));

  std::vector<const RichParameter*> expected;
  for (const RichParameter& rp : plugin) expected.push_back(&rp);
  if (int(expected.size()) != xml.size())
    problem(QString("the plugin has %1 parameters, the script lists %2")
                .arg(int(expected.size()))
                .arg(xml.size()));
  const int n = std::min(int(expected.size()), xml.size());
  for (int i = 0; i < n; ++i) {
    const RichParameter& rp = *expected[size_t(i)];
    const XmlParam& xp = xml[i];
    if (xp.name != rp.name())
      problem(QString("parameter %1: script name '%2', plugin name '%3'").arg(i).arg(xp.name, rp.name()));
    if (xp.type != rp.stringType())
      problem(QString("parameter '%1': script type '%2', plugin type '%3'")
                  .arg(rp.name(), xp.type, rp.stringType()));
    if (rp.value().isEnum()) {
      const int card = static_cast<const RichEnum&>(rp).enumvalues.size();
      bool ok = false;
      const int v = xp.value.toInt(&ok);
      if (!ok || v < 0 || v >= card)
        problem(QString("parameter '%1': enum value '%2' is not in [0, %3)").arg(rp.name(), xp.value).arg(card));
    }
  }
  return problems;
}

/// Compares the filter's parameters with the sodt::paramTable() entries it
/// is built from; prints every problem and returns how many there are.
int checkTable(const QString& filterName, const RichParameterList& plugin) {
  int problems = 0;
  auto problem = [&problems](const QString& what) {
    std::fprintf(stderr, "table check: %s\n", qUtf8Printable(what));
    ++problems;
  };
  std::vector<const sodt::ParamSpec*> specs;
  for (const sodt::ParamSpec& s : sodt::paramTable())
    if (filterName == "S-ODT Smoothing" || std::strcmp(s.field, "epsilon") == 0 || std::strcmp(s.field, "eta") == 0)
      specs.push_back(&s);
  static const char* const types[] = {"RichInt", "RichFloat", "RichBool", "RichEnum"};
  const sodt::SodtParams d{};
  for (const sodt::ParamSpec* s : specs) {
    const RichParameter* rp = nullptr;
    for (const RichParameter& p : plugin)
      if (p.name() == s->key) rp = &p;
    const QString key = s->key;
    if (rp == nullptr) {
      problem("no parameter '" + key + "'");
      continue;
    }
    if (rp->stringType() != types[static_cast<int>(s->type)]) {
      problem(QString("'%1' is a %2, the table says %3").arg(key, rp->stringType(), types[static_cast<int>(s->type)]));
      continue;
    }
    // On an empty mesh without selection, as the script's defaults.
    const double want = s->defaultOnWithSelection ? 0 : s->shownValue(d);
    double got = 0;
    switch (s->type) {
      case sodt::ParamType::Int: got = rp->value().getInt(); break;
      case sodt::ParamType::Real: got = rp->value().getFloat(); break;
      case sodt::ParamType::Bool: got = rp->value().getBool() ? 1 : 0; break;
      case sodt::ParamType::Choice: got = rp->value().getEnum(); break;
    }
    const double wantStored = s->type == sodt::ParamType::Real ? static_cast<float>(want) : want;
    if (got != wantStored) problem(QString("'%1' defaults to %2, the table to %3").arg(key).arg(got).arg(want));
    if (rp->fieldDescription() != s->label)
      problem(QString("'%1' is labelled '%2', the table says '%3'").arg(key, rp->fieldDescription(), s->label));
    if (s->type == sodt::ParamType::Choice) {
      QStringList labels;
      for (const sodt::ParamChoice& c : s->choices) labels << c.label;
      if (static_cast<const RichEnum*>(rp)->enumvalues != labels)
        problem(QString("'%1' offers '%2', the table '%3'")
                    .arg(key, static_cast<const RichEnum*>(rp)->enumvalues.join("', '"), labels.join("', '")));
    }
    // The tooltip starts with the help (capitalized) and holds the rest.
    const QString tip = rp->toolTip();
    QStringList parts{QString::fromUtf8(s->help).mid(1), QString::fromStdString(s->rangeText()), s->unit,
                      s->details};
    for (const sodt::ParamChoice& c : s->choices) parts << c.help;
    for (const QString& part : parts)
      if (!tip.contains(part)) problem(QString("the tooltip of '%1' lacks '%2': %3").arg(key, part, tip));
  }
  return problems;
}

/// Position of an attribute in the written file: the ones a reader needs
/// first, then the enum entries in index order, then anything else.
int attributeRank(const QString& a) {
  static const QStringList first{"name", "type", "value", "enum_cardinality"};
  const int i = first.indexOf(a);
  if (i >= 0) return i;
  if (a.startsWith("enum_val")) return 100 + a.mid(8).toInt();
  return 1000000;
}

/// A --set NAME=VALUE of write mode.
struct Override {
  QString name, value;
};

/// Checks that value is what MeshLab 2020.09's script parser accepts for the
/// parameter's type (RichParameterAdapter: toInt, toFloat, "true"/"false"),
/// and that an enum index is in range. Prints the problem and returns false.
bool overrideParses(const RichParameter& rp, const QString& value) {
  bool ok = false;
  const QString t = rp.stringType();
  if (t == "RichBool") {
    ok = value == "true" || value == "false";
  } else if (t == "RichInt") {
    value.toInt(&ok);
  } else if (t == "RichEnum") {
    const int v = value.toInt(&ok);
    ok = ok && v >= 0 && v < static_cast<const RichEnum&>(rp).enumvalues.size();
  } else if (t == "RichFloat") {
    value.toFloat(&ok);
  } else {
    std::fprintf(stderr, "--set %s: parameters of type %s are not supported\n", qUtf8Printable(rp.name()),
                 qUtf8Printable(t));
    return false;
  }
  if (!ok)
    std::fprintf(stderr, "--set %s=%s: not a valid %s value\n", qUtf8Printable(rp.name()),
                 qUtf8Printable(value), qUtf8Printable(t));
  return ok;
}

/// Writes a script with one filter, each <Param> serialized by MeshLab's own
/// RichParameter::fillToXMLDocument (values only, no description or tooltip),
/// with the attributes in a fixed order so the output is reproducible (QtXml
/// orders them by a randomly seeded hash). The value of a parameter named in
/// overrides is replaced (the caller checked that it parses).
bool writeScript(const QString& path, const QString& filterName, const RichParameterList& params,
                 const QList<Override>& overrides) {
  QByteArray xml;
  QXmlStreamWriter w(&xml);
  w.setAutoFormatting(true);
  w.setAutoFormattingIndent(1);
  w.writeComment(" SPDX-License-Identifier: GPL-3.0-or-later ");
  w.writeComment(" meshlabserver 2020.09 script running \"" + filterName +
                 "\" with every parameter listed (a missing or misspelled one aborts meshlabserver). ");
  // No double hyphen: it ends an XML comment early.
  w.writeComment(" Generated from the built plugin by tests/plugin/sodt_plugin_script_tool (write "
                 "mode); a test checks that it still matches the plugin. ");
  if (!overrides.isEmpty()) {
    QStringList sets;
    for (const Override& o : overrides) sets << "set " + o.name + "=" + o.value;
    w.writeComment(" Defaults changed in write mode: " + sets.join(", ") + " ");
  }
  w.writeDTD("<!DOCTYPE FilterScript>");
  w.writeStartElement("FilterScript");
  w.writeStartElement("filter");
  w.writeAttribute("name", filterName);
  QDomDocument doc;
  for (const RichParameter& rp : params) {
    const QDomElement e = rp.fillToXMLDocument(doc, false);
    const QDomNamedNodeMap attrs = e.attributes();
    QStringList names;
    for (int i = 0; i < attrs.count(); ++i) names << attrs.item(i).nodeName();
    std::stable_sort(names.begin(), names.end(), [](const QString& a, const QString& b) {
      const int ra = attributeRank(a), rb = attributeRank(b);
      return ra != rb ? ra < rb : a < b;
    });
    QString value = e.attribute("value");
    for (const Override& o : overrides)
      if (o.name == rp.name()) value = o.value;
    w.writeEmptyElement("Param");
    for (const QString& n : names) w.writeAttribute(n, n == "value" ? value : e.attribute(n));
  }
  w.writeEndElement();
  w.writeEndElement();
  if (w.hasError()) return false;
  QFile f(path);
  if (!f.open(QIODevice::WriteOnly | QIODevice::Truncate)) return false;
  f.write(xml.trimmed() + "\n");
  f.close();
  return f.error() == QFileDevice::NoError;
}

/// Loads the plugin and fills params with the filter's parameters on an
/// empty mesh without selection (the defaults a script gets on any mesh).
/// Prints why and returns false when it cannot.
bool loadParams(const QString& pluginPath, const QString& filterName, MeshDocument& md, RichParameterList& params) {
  QPluginLoader loader(pluginPath);
  QObject* instance = loader.instance();
  if (instance == nullptr) {
    std::fprintf(stderr, "cannot load plugin '%s': %s\n", qUtf8Printable(pluginPath),
                 qUtf8Printable(loader.errorString()));
    return false;
  }
  MeshFilterInterface* filters = qobject_cast<MeshFilterInterface*>(instance);
  if (filters == nullptr) {
    std::fprintf(stderr, "'%s' is not a MeshLab 2020.09 filter plugin\n", qUtf8Printable(pluginPath));
    return false;
  }
  QAction* action = nullptr;
  for (QAction* a : filters->actions())
    if (a->text() == filterName) action = a;
  if (action == nullptr) {
    std::fprintf(stderr, "the plugin has no filter named '%s'\n", qUtf8Printable(filterName));
    return false;
  }
  md.addNewMesh("", "empty");
  filters->initParameterSet(action, md, params);
  return true;
}

/// --check-table.
int runCheckTable(char** argv) {
  const QString pluginPath = QFileInfo(QString::fromLocal8Bit(argv[1])).absoluteFilePath();
  const QString filterName = QString::fromUtf8(argv[2]);
  MeshDocument md;
  RichParameterList params;
  if (!loadParams(pluginPath, filterName, md, params)) return 2;
  const int problems = checkTable(filterName, params);
  if (problems == 0)
    std::printf("the parameters of '%s' are those of sodt::paramTable()\n", qUtf8Printable(filterName));
  return problems == 0 ? 0 : 1;
}

int run(int argc, char** argv) {
  if (argc == 4 && std::strcmp(argv[3], "--check-table") == 0) return runCheckTable(argv);
  if (argc < 5) return usage();
  // QPluginLoader searches the library path for a relative name.
  const QString pluginPath = QFileInfo(QString::fromLocal8Bit(argv[1])).absoluteFilePath();
  const QString filterName = QString::fromUtf8(argv[2]);
  const QString mode = QString::fromLocal8Bit(argv[3]);
  const QString scriptPath = QString::fromLocal8Bit(argv[4]);
  if (mode != "--write" && mode != "--check") return usage();
  QList<Override> overrides;
  for (int i = 5; i < argc; i += 2) {
    if (mode != "--write" || i + 1 >= argc || std::strcmp(argv[i], "--set") != 0) return usage();
    const QString kv = QString::fromLocal8Bit(argv[i + 1]);
    const int eq = kv.indexOf('=');
    if (eq <= 0) return usage();
    overrides.append({kv.left(eq), kv.mid(eq + 1)});
  }

  MeshDocument md;
  RichParameterList params;
  if (!loadParams(pluginPath, filterName, md, params)) return 2;

  if (mode == "--write") {
    for (const Override& o : overrides) {
      const RichParameter* rp = nullptr;
      for (const RichParameter& p : params)
        if (p.name() == o.name) rp = &p;
      if (rp == nullptr) {
        std::fprintf(stderr, "--set %s: '%s' has no such parameter\n", qUtf8Printable(o.name),
                     qUtf8Printable(filterName));
        return 2;
      }
      if (!overrideParses(*rp, o.value)) return 2;
    }
    if (!writeScript(scriptPath, filterName, params, overrides)) {
      std::fprintf(stderr, "cannot write '%s'\n", qUtf8Printable(scriptPath));
      return 2;
    }
    std::printf("wrote %d parameters of '%s' to %s\n", params.size(), qUtf8Printable(filterName),
                qUtf8Printable(scriptPath));
    return 0;
  }
  const int problems = checkScript(scriptPath, filterName, params);
  if (problems == 0)
    std::printf("%s lists all %d parameters of '%s' with the plugin's names and types\n",
                qUtf8Printable(scriptPath), params.size(), qUtf8Printable(filterName));
  return problems == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  QCoreApplication app(argc, argv);
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
