// SPDX-License-Identifier: GPL-3.0-or-later
// The S-ODT filters as a MeshLab 2021.05+ plugin (FilterPlugin; built and
// tested against MeshLab 2025.07 and PyMeshLab 2025.7): ids, classes, Python
// names and the translation of sodt_filters.h to this API.
#pragma once

#include <common/plugins/interfaces/filter_plugin.h>

/// Filter plugin "S-ODT" for MeshLab 2021.05 and later (FilterPlugin): the
/// smoothing filter and the vertex classification filter.
class FilterSodtPlugin : public QObject, public FilterPlugin {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
  Q_INTERFACES(FilterPlugin)

 public:
  FilterSodtPlugin();

  // Keep the base-class overloads (by QAction*, by MeshDocument&) visible.
  using FilterPlugin::filterInfo;
  using FilterPlugin::filterName;
  using FilterPlugin::initParameterList;
  using FilterPlugin::pythonFilterName;

  QString pluginName() const override;
  QString vendor() const override;
  QString filterName(ActionIDType filter) const override;
  QString pythonFilterName(ActionIDType filter) const override;
  QString filterInfo(ActionIDType filter) const override;
  FilterClass getClass(const QAction* a) const override;
  FilterArity filterArity(const QAction* a) const override;
  int getPreConditions(const QAction* a) const override;
  int postCondition(const QAction* a) const override;
  RichParameterList initParameterList(const QAction* a, const MeshModel& m) override;
  /// Runs the filter and returns its report (a Python dict in PyMeshLab). A
  /// failure is logged and thrown as MLException, the one exception type the
  /// GUI catches besides std::bad_alloc, with the mesh left unchanged.
  std::map<std::string, QVariant> applyFilter(const QAction* a, const RichParameterList& par,
                                              MeshDocument& md, unsigned int& postConditionMask,
                                              vcg::CallBackPos* cb) override;
};
