// SPDX-License-Identifier: GPL-3.0-or-later
// The smoother for sodt::MeshD, compiled once (see prebuilt.h); a file of its
// own so that the two mesh types compile in parallel.
#include "prebuilt.h"

template struct sodt::SodtSmoother<sodt::MeshD>;
