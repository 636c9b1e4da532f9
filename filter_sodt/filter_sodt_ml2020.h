// SPDX-License-Identifier: GPL-3.0-or-later
// The S-ODT filters as a MeshLab 2020.09 plugin (MeshFilterInterface): ids,
// classes and the translation of sodt_filters.h to this API.
#pragma once

#include <common/interfaces.h>

/// Filter plugin "S-ODT" for MeshLab 2020.09 (MeshFilterInterface): the
/// smoothing filter and the vertex classification filter.
class FilterSodtPlugin : public QObject, public MeshFilterInterface {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
  Q_INTERFACES(MeshFilterInterface)

 public:
  FilterSodtPlugin();

  // Keep the base-class overloads (by QAction*, by MeshDocument&) visible.
  using MeshFilterInterface::filterInfo;
  using MeshFilterInterface::filterName;
  using MeshFilterInterface::initParameterSet;

  QString pluginName() const override;
  QString filterName(FilterIDType filter) const override;
  QString filterInfo(FilterIDType filter) const override;
  FilterClass getClass(QAction* a) override;
  FILTER_ARITY filterArity(QAction* a) const override;
  int getRequirements(QAction* a) override;
  int getPreConditions(QAction* a) const override;
  int postCondition(QAction* a) const override;
  void initParameterSet(QAction* a, MeshModel& m, RichParameterList& par) override;
  /// Runs the filter; never lets an exception escape (MeshLab 2020.09 would
  /// crash on anything but std::bad_alloc): a failure sets errorMessage, is
  /// logged (meshlabserver prints the log but not errorMessage) and returns false.
  bool applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                   vcg::CallBackPos* cb) override;
};
