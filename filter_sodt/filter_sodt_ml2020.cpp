// SPDX-License-Identifier: GPL-3.0-or-later
// MeshLab 2020.09 adapter of the S-ODT filters (sodt_filters.h).
#include "filter_sodt_ml2020.h"

#include "sodt_filters.h"
#include "sodt_rich_params.h"

#include <exception>

FilterSodtPlugin::FilterSodtPlugin() {
  typeList << sodt_plugin::kSmooth << sodt_plugin::kClassify;
  for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString FilterSodtPlugin::pluginName() const { return "FilterSodt"; }

QString FilterSodtPlugin::filterName(FilterIDType filter) const { return sodt_plugin::filterName(filter); }

QString FilterSodtPlugin::filterInfo(FilterIDType filter) const { return sodt_plugin::filterInfo(filter); }

MeshFilterInterface::FilterClass FilterSodtPlugin::getClass(QAction*) {
  // Both filters are listed under Smoothing only. A VertexColoring bit would
  // also list them under Color Creation, but the class is fixed per filter:
  // for the smoothing filter it would make the GUI switch to vertex colours
  // even with outputClass off, and the classification filter declares its
  // colours through postCondition and updateDataMask already. (MeshLab
  // throws while loading on Generic.)
  return MeshFilterInterface::Smoothing;
}

MeshFilterInterface::FILTER_ARITY FilterSodtPlugin::filterArity(QAction*) const { return SINGLE_MESH; }

int FilterSodtPlugin::getRequirements(QAction*) {
  // The core builds its own one-ring topology from the face list.
  return MeshModel::MM_NONE;
}

int FilterSodtPlugin::getPreConditions(QAction*) const { return MeshModel::MM_FACENUMBER; }

int FilterSodtPlugin::postCondition(QAction* a) const { return sodt_plugin::postConditionMask(ID(a)); }

void FilterSodtPlugin::initParameterSet(QAction* a, MeshModel& m, RichParameterList& par) {
  switch (ID(a)) {
    case sodt_plugin::kSmooth: appendSodtParams(par, m); break;
    case sodt_plugin::kClassify: appendClassifyParams(par); break;
  }
}

bool FilterSodtPlugin::applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                                   vcg::CallBackPos* cb) {
  errorMessage.clear();
  const int id = ID(a);
  const sodt_plugin::LogFn log = [this](sodt_plugin::LogLevel level, const std::string& line) {
    Log(level == sodt_plugin::LogLevel::Warning ? GLLogStream::WARNING : GLLogStream::FILTER, line);
  };
  sodt_plugin::Report report;  // MeshLab 2020.09 has no channel for it: the log says it all
  errorMessage = sodt_plugin::runFilter(id, a->text(), md.mm(), par, cb, log, report);
  if (errorMessage.isEmpty()) return true;
  Log(GLLogStream::WARNING, errorMessage.toStdString());
  return false;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterSodtPlugin)
