// SPDX-License-Identifier: GPL-3.0-or-later
// Translation between MeshLab's RichParameterList and sodt::SodtParams: the one
// place that spells the (stable, lowerCamelCase) parameter keys of the filter.
#pragma once

#include <sodt/params.h>

class MeshModel;
class RichParameterList;

/// Appends the S-ODT parameters to a filter's parameter list.
///
/// Keys: `algorithm` (RichEnum), `iterations` (RichInt), `guard` (RichEnum),
/// `maxBacktracks` (RichInt), `selectedOnly` (RichBool). Enum indices equal the
/// integer values of sodt::Algorithm and sodt::Guard. Every default is read from
/// sodt::SodtParams{}, except `selectedOnly`, which is true when the mesh has a
/// vertex or face selection (svn > 0 || sfn > 0).
/// \param list parameter list to extend; keys already present are not checked.
/// \param m    mesh the dialog is opened for; only its selection counts are read.
void appendSodtParams(RichParameterList& list, const MeshModel& m);

/// Reads back the values appended by appendSodtParams.
///
/// The result is not validated: an out-of-range enum index or count coming
/// from a script is passed through, so that sodt::SodtParams::validate()
/// reports it with the core's message.
/// \throw MLException (a std::exception) when a key is missing from the list.
sodt::SodtParams readSodtParams(const RichParameterList& list);
