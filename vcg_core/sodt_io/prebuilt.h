// SPDX-License-Identifier: GPL-3.0-or-later
// SodtSmoother for the project's own mesh types (MeshF, MeshD), compiled once
// in the sodt_prebuilt library. A file that includes this header instead of
// smoother.h does not compile the smoother again and must link sodt_prebuilt:
// the CLI and the tests do, which keeps their builds (and the sanitizer
// build's) short. Other mesh types, CMeshO among them, instantiate
// smoother.h as usual. A file built with other settings of smoother.h's
// macros (SODT_NO_LANES) must include smoother.h itself and not link
// sodt_prebuilt.
#pragma once

#include "mesh.h"
#include <sodt/smoother.h>

namespace sodt {

extern template struct SodtSmoother<MeshF>;
extern template struct SodtSmoother<MeshD>;

}  // namespace sodt
