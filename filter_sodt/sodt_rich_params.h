// SPDX-License-Identifier: GPL-3.0-or-later
// Translation between MeshLab's RichParameterList and the core's parameters.
// The parameters of a smoothing run come from sodt::paramTable() (params.h),
// which spells their stable keys, lowerCamelCase for MeshLab 2020.09 and
// lower_snake_case for MeshLab 2021.05+ and PyMeshLab; this file adds the
// filters' own `outputClass` and `selectFeatures`.
#pragma once

#include <sodt/params.h>

class MeshModel;
class RichParameterList;

/// Appends the parameters of "S-ODT Smoothing" to a filter's parameter list:
/// one per sodt::paramTable() entry, in its order, then `outputClass`
/// (RichBool, default true: write the classes to vertex quality and colour).
///
/// An entry becomes a RichInt, RichFloat (its shown value: `maxDeviation` in
/// percent), RichBool or RichEnum (entry i is enum value i, labelled with
/// ParamChoice::label for MeshLab 2020.09 and with the CLI's name for
/// 2021.05+), with the entry's key, dialog label and a tooltip made of its
/// help, range, unit, choices, the algorithms that use it and its details.
/// Every default is the SodtParams{} field's, except `selectedOnly`, which is
/// on when the mesh has a vertex or face selection (svn > 0 || sfn > 0).
/// \param list parameter list to extend; keys already present are not checked.
/// \param m    mesh the dialog is opened for; only its selection counts are read.
void appendSodtParams(RichParameterList& list, const MeshModel& m);

/// Reads back the core parameters appended by appendSodtParams.
///
/// Float values are read at float precision, as the shortest decimal with 7
/// significant digits (0.1 stays 0.1, not 0.100000001), so the plugin runs with
/// the values the user wrote; shown values are converted to the fields'
/// (ParamSpec::setShown: `maxDeviation` percent to a fraction).
/// \throw sodt::InvalidInput naming the key (as spelled for the API) when a
///        value lies outside its table range, e.g. "max_deviation must be in
///        [0, 100] (percent of the bounding-box diagonal), got 200".
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

/// Appends the parameters of the classification filter: the table entries
/// `epsilon` and `eta` (as in the smoothing filter) and `selectFeatures`
/// (RichBool, default false).
void appendClassifyParams(RichParameterList& list);

/// Reads back the values appended by appendClassifyParams.
/// \throw sodt::InvalidInput naming `epsilon` or `eta` when out of range.
/// \throw MLException (a std::exception) when a key is missing from the list.
SodtClassifyParams readClassifyParams(const RichParameterList& list);
