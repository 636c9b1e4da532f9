// SPDX-License-Identifier: GPL-3.0-or-later
// MeshLab 2020.09 filter plugin exposing S-ODT surface mesh smoothing; the only
// file pair that depends on the MeshLab version (ids, names, masks, apply).
#pragma once

#include <common/interfaces.h>

/// Filter plugin "S-ODT" for MeshLab 2020.09 (MeshFilterInterface): the
/// smoothing filter and the vertex classification filter.
class FilterSodtPlugin : public QObject, public MeshFilterInterface {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
  Q_INTERFACES(MeshFilterInterface)

 public:
  /// Filter ids; new filters are appended, existing values never change.
  enum { FP_SODT_SMOOTH, FP_SODT_CLASSIFY };

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
  bool applyFilter(QAction* a, MeshDocument& md, const RichParameterList& par,
                   vcg::CallBackPos* cb) override;

 private:
  /// FP_SODT_SMOOTH: validates, runs sodt::SodtSmoother on the current mesh and
  /// logs the quality before and after. Never lets an exception escape.
  bool applySmooth(MeshDocument& md, const RichParameterList& par, vcg::CallBackPos* cb);
  /// FP_SODT_CLASSIFY: validates, classifies the vertices of the current mesh
  /// (never moves them), writes class codes and colours, optionally selects
  /// the feature vertices, logs the counts. Never lets an exception escape.
  bool applyClassify(MeshDocument& md, const RichParameterList& par);
  /// Sets errorMessage and also logs it (meshlabserver prints the filter log
  /// but not errorMessage); returns false.
  bool fail(const QString& why);
};
