// SPDX-License-Identifier: GPL-3.0-or-later
// Translation between MeshLab's RichParameterList and the core's parameters: the
// one place that spells the (stable) parameter keys of the filters, lowerCamelCase
// for MeshLab 2020.09 and lower_snake_case for MeshLab 2021.05+ and PyMeshLab.
#pragma once

#include <sodt/params.h>

class MeshModel;
class RichParameterList;

/// Appends the parameters of "S-ODT Smoothing" to a filter's parameter list.
///
/// Keys, in dialog order, as spelled for MeshLab 2020.09 (2021.05+ spells the
/// same keys in lower_snake_case: `max_backtracks`, `laplacian_fallback`, ...,
/// and labels the enum entries with the CLI's names, `basic`, `feature`, ...,
/// `none`, `fold`, `quality`): `algorithm` (RichEnum), `iterations` (RichInt),
/// `guard` (RichEnum), `maxBacktracks` (RichInt), `laplacianFallback`
/// (RichBool), `maxDeviation` (RichFloat, percent of the bounding-box
/// diagonal), `epsilon` (RichFloat), `eta` (RichFloat), `maxNormalStep`
/// (RichFloat, fraction of the mean edge length), `flips` (RichBool),
/// `flipMaxDihedral` (RichFloat, degrees), `keepBest` (RichBool), `tolerance`
/// (RichFloat, degrees), `threads` (RichInt, 0 = all cores), `selectedOnly`
/// (RichBool), `outputClass` (RichBool).
/// Enum indices equal the integer values of sodt::Algorithm and sodt::Guard.
/// Every default is read from sodt::SodtParams{} (`maxDeviation` = 100 *
/// maxDeviationRel, `flipMaxDihedral` = flipMaxDihedralDeg, `tolerance` =
/// toleranceDeg), except
/// `selectedOnly`, which is true when the mesh has a vertex or face selection
/// (svn > 0 || sfn > 0), and `outputClass`, which is true.
/// \param list parameter list to extend; keys already present are not checked.
/// \param m    mesh the dialog is opened for; only its selection counts are read.
void appendSodtParams(RichParameterList& list, const MeshModel& m);

/// Reads back the core parameters appended by appendSodtParams.
///
/// Float values are read at float precision, as the shortest decimal with 7
/// significant digits (0.1 stays 0.1, not 0.100000001), so the plugin runs with
/// the values the user wrote. `maxDeviation` is converted from percent to the
/// fraction SodtParams::maxDeviationRel. Everything else is passed through unchecked
/// (an out-of-range enum index or count coming from a script included), so
/// that sodt::SodtParams::validate() reports it with the core's message,
/// except the three ranges below.
/// \throw sodt::InvalidInput when `maxBacktracks` is not in [0, 60],
///        `maxDeviation` not in [0, 100] percent, `maxNormalStep` not in [0, 10],
///        `flipMaxDihedral` not in [0, 90] or `tolerance` not in [0, 180]
///        degrees: the core's message would name its own fields, not the keys.
/// \throw MLException (a std::exception) when a key is missing from the list.
sodt::SodtParams readSodtParams(const RichParameterList& list);

/// Reads `outputClass` of the smoothing filter: write the class codes to
/// vertex quality and the class palette to vertex colour after smoothing.
/// \throw MLException (a std::exception) when the key is missing from the list.
bool readOutputClass(const RichParameterList& list);

/// Settings of "S-ODT: Classify Feature Vertices".
struct SodtClassifyParams {
  double epsilon = sodt::SodtParams{}.epsilon;  ///< crease sensitivity of Eq. 10
  double eta = sodt::SodtParams{}.eta;          ///< corner sensitivity of Eq. 10
  bool selectFeatures = false;                  ///< select crease and corner vertices, clear the others

  /// Throws sodt::InvalidInput naming `epsilon` or `eta` (the core's checks).
  void validate() const {
    sodt::SodtParams p;
    p.epsilon = epsilon;
    p.eta = eta;
    p.validate();
  }
};

/// Appends the parameters of the classification filter: `epsilon`, `eta`
/// (RichFloat, defaults from sodt::SodtParams{}) and `selectFeatures`
/// (RichBool, default false). The keys equal those of the smoothing filter.
void appendClassifyParams(RichParameterList& list);

/// Reads back the values appended by appendClassifyParams, unvalidated.
/// \throw MLException (a std::exception) when a key is missing from the list.
SodtClassifyParams readClassifyParams(const RichParameterList& list);
