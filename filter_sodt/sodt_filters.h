// SPDX-License-Identifier: GPL-3.0-or-later
// The S-ODT filters, written once for both MeshLab plugin APIs: names, help,
// what they change, and the runs themselves with their log and report. The
// adapters (filter_sodt_ml2020.*, filter_sodt_ml2025.*) only translate this to
// their API's signatures and error conventions.
#pragma once

#include "sodt_meshlab_api.h"

#include <QString>
#include <QVariant>

#include <functional>
#include <map>
#include <string>

namespace sodt_plugin {

/// Filter ids; new filters are appended, existing values never change.
enum FilterId : int {
  kSmooth = 0,    ///< "S-ODT Smoothing"
  kClassify = 1,  ///< "S-ODT: Classify Feature Vertices"
};

/// Menu and script name (the .mlx filter name of MeshLab 2020.09 and the
/// name MeshLab 2021.05+ shows).
QString filterName(int id);
/// Python name in PyMeshLab: `apply_coord_sodt_smoothing` and
/// `compute_scalar_by_sodt_feature_class_per_vertex`, after MeshLab's own
/// naming families (apply_coord_*_smoothing, compute_scalar_by_*_per_vertex).
QString pythonFilterName(int id);
/// HTML help of the filter, with the paper's reference.
QString filterInfo(int id);
/// MeshModel::MM_* bits the filter may change.
int postConditionMask(int id);

enum class LogLevel { Info, Warning };
/// Where the runs write their log lines (MeshLab's log window / PyMeshLab's
/// verbose output).
using LogFn = std::function<void(LogLevel, const std::string&)>;

/// What a run returns to PyMeshLab as a Python dict (MeshLab 2020.09 has no
/// such channel and only logs). Values are int, double or bool only, the
/// QVariant types PyMeshLab converts; counters that could pass 2^31 - 1 are
/// doubles.
using Report = std::map<std::string, QVariant>;

/// Runs "S-ODT Smoothing" on `mm` with the parameters of
/// appendSodtParams(). Everything that can be rejected (parameters, a mesh
/// without faces, flips on per-wedge or polygonal data) is checked before
/// anything changes.
/// \return min/max angle and share below 30 deg before/after, volume before,
///         after and relative change (closed meshes), class counts, the move
///         counters, flips, threads, sweeps, seconds and the returned sweep.
/// \throw std::exception (sodt::InvalidInput for bad input) with a message for
///        the user; `mm` is then unchanged (a converted face selection is undone).
Report applySmoothing(MeshModel& mm, const RichParameterList& par, vcg::CallBackPos* cb,
                      const LogFn& log);

/// Runs "S-ODT: Classify Feature Vertices" on `mm` (never moves a vertex).
/// \return the class counts and, with selectFeatures, the selected vertices.
/// \throw std::exception with a message for the user; `mm` is then unchanged.
Report applyClassify(MeshModel& mm, const RichParameterList& par, const LogFn& log);

/// "S-ODT Smoothing failed: WHY" (or "... failed with an unknown error." when
/// `why` is null): the one message both adapters show for a failed run.
QString failureMessage(int id, const char* why);

/// Runs filter `id` (applySmoothing or applyClassify) on `mm`, the current
/// mesh or null, for both adapters: its report goes to `report`, and
/// nothing escapes. \return empty on success, else the message for the user
/// (failureMessage; `filterName` names an unknown id), after which the mesh
/// is as the filter found it.
QString runFilter(int id, const QString& filterName, MeshModel* mm, const RichParameterList& par,
                  vcg::CallBackPos* cb, const LogFn& log, Report& report);

}  // namespace sodt_plugin
