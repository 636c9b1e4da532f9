// SPDX-License-Identifier: GPL-3.0-or-later
// MeshLab 2021.05+ adapter of the S-ODT filters (sodt_filters.h).
#include "filter_sodt_ml2025.h"

#include "sodt_filters.h"
#include "sodt_rich_params.h"

#include <common/mlexception.h>

#include <exception>
#include <stdexcept>

FilterSodtPlugin::FilterSodtPlugin() {
  typeList = {sodt_plugin::kSmooth, sodt_plugin::kClassify};
  for (ActionIDType id : types()) actionList.push_back(new QAction(filterName(id), this));
}

QString FilterSodtPlugin::pluginName() const { return "FilterSodt"; }

QString FilterSodtPlugin::vendor() const { return "sodt"; }

QString FilterSodtPlugin::filterName(ActionIDType filter) const { return sodt_plugin::filterName(filter); }

QString FilterSodtPlugin::pythonFilterName(ActionIDType filter) const {
  return sodt_plugin::pythonFilterName(filter);
}

QString FilterSodtPlugin::filterInfo(ActionIDType filter) const { return sodt_plugin::filterInfo(filter); }

FilterPlugin::FilterClass FilterSodtPlugin::getClass(const QAction*) const {
  // Both filters under Filters > Smoothing, Fairing and Deformation (see the
  // MeshLab 2020.09 adapter for why not also under Color Creation).
  return FilterPlugin::Smoothing;
}

FilterPlugin::FilterArity FilterSodtPlugin::filterArity(const QAction*) const { return SINGLE_MESH; }

int FilterSodtPlugin::getPreConditions(const QAction*) const { return MeshModel::MM_FACENUMBER; }

int FilterSodtPlugin::postCondition(const QAction* a) const { return sodt_plugin::postConditionMask(ID(a)); }

RichParameterList FilterSodtPlugin::initParameterList(const QAction* a, const MeshModel& m) {
  RichParameterList par;
  switch (ID(a)) {
    case sodt_plugin::kSmooth: appendSodtParams(par, m); break;
    case sodt_plugin::kClassify: appendClassifyParams(par); break;
  }
  return par;
}

std::map<std::string, QVariant> FilterSodtPlugin::applyFilter(const QAction* a, const RichParameterList& par,
                                                              MeshDocument& md, unsigned int& postConditionMask,
                                                              vcg::CallBackPos* cb) {
  const int id = ID(a);
  const sodt_plugin::LogFn logLine = [this](sodt_plugin::LogLevel level, const std::string& line) {
    log(level == sodt_plugin::LogLevel::Warning ? GLLogStream::WARNING : GLLogStream::FILTER, line);
  };
  postConditionMask = static_cast<unsigned int>(sodt_plugin::postConditionMask(id));
  sodt_plugin::Report report;
  const QString error = sodt_plugin::runFilter(id, a->text(), md.mm(), par, cb, logLine, report);
  if (error.isEmpty()) return report;
  log(GLLogStream::WARNING, error.toStdString());
  throw MLException(error);
}
