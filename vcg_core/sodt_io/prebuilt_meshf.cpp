// SPDX-License-Identifier: GPL-3.0-or-later
// The smoother for sodt::MeshF, compiled once (see prebuilt.h).
#include "prebuilt.h"

template struct sodt::SodtSmoother<sodt::MeshF>;
