// SPDX-License-Identifier: GPL-3.0-or-later
// The few MeshLab spellings that differ between the two plugin APIs the filter
// builds against, selected by SODT_MESHLAB_API (set by filter_sodt/CMakeLists.txt):
//   2020  MeshLab 2020.09, MeshFilterInterface (Debian 12's package)
//   2021  MeshLab 2021.05 and later, FilterPlugin (2025.07 and PyMeshLab 2025.7)
// Everything else in the plugin is written once against both.
#pragma once

#ifndef SODT_MESHLAB_API
#error "SODT_MESHLAB_API must be defined (2020 or 2021)"
#endif

#if SODT_MESHLAB_API >= 2021
#include <common/ml_document/mesh_model.h>
#include <common/parameters/rich_parameter_list.h>
#include <common/parameters/rich_parameters.h>
#else
#include <common/filter_parameter/rich_parameter_list.h>
#include <common/meshmodel.h>
#endif

namespace sodt_meshlab {

/// True when parameter keys are spelled lower_snake_case: PyMeshLab turns a
/// key into a Python keyword by lower-casing it, so camelCase keys could not
/// be passed from Python. MeshLab 2020.09 keeps the lowerCamelCase keys its
/// .mlx scripts were written with.
constexpr bool kSnakeCaseKeys = SODT_MESHLAB_API >= 2021;

/// Bounding box and normals after the coordinates changed.
inline void updateBoxAndNormals(MeshModel& mm) {
#if SODT_MESHLAB_API >= 2021
  mm.updateBoxAndNormals();
#else
  mm.UpdateBoxAndNormals();
#endif
}

}  // namespace sodt_meshlab
