# SPDX-License-Identifier: GPL-3.0-or-later
# The plugin for MeshLab 2025.07 next to the main build: two more builds of
# this project with SODT_PLUGIN_ONLY, one per precision MeshLab requires
#   gui        float,  MESHLAB_VERSION "2025.07",  the MeshLab 2025.07 GUI
#   pymeshlab  double, MESHLAB_VERSION "2025.07d", PyMeshLab 2025.7
# against the folder scripts/build-meshlab-2025.sh fills (SODT_MESHLAB2025_DIR).
# Sets SODT_PLUGIN_ML2025_GUI and SODT_PLUGIN_ML2025_PYMESHLAB (the built
# libfilter_sodt.so files), SODT_MESHLAB2025_GUI (the meshlab binary) and
# SODT_PYMESHLAB_PATH (the folder to put on PYTHONPATH).
include(ExternalProject)

set(_ml "${SODT_MESHLAB2025_DIR}")
foreach(needed src/meshlab/ML_VERSION gui/.done gui/src/distrib/meshlab pymeshlab/.done
               pymeshlab/pymeshlab/lib/libmeshlab-common.so)
  if(NOT EXISTS "${_ml}/${needed}")
    message(FATAL_ERROR
      "SODT_MESHLAB2025_DIR='${_ml}' is not a complete MeshLab 2025.07 / PyMeshLab folder "
      "(${needed} is missing). Run scripts/build-meshlab-2025.sh (it prints the folder with "
      "--print-dir), or leave SODT_MESHLAB2025_DIR empty.")
  endif()
endforeach()

set(SODT_MESHLAB2025_GUI "${_ml}/gui/src/distrib/meshlab")
set(SODT_PYMESHLAB_PATH "${_ml}/pymeshlab")
set(_flavours "gui|float|${_ml}/gui/src/distrib" "pymeshlab|double|${_ml}/pymeshlab/pymeshlab/lib")
foreach(entry IN LISTS _flavours)
  string(REPLACE "|" ";" fields "${entry}")
  list(GET fields 0 flavour)
  list(GET fields 1 scalar)
  list(GET fields 2 libdir)
  set(bin "${PROJECT_BINARY_DIR}/meshlab-2025.07-${flavour}")
  set(so "${bin}/filter_sodt/libfilter_sodt.so")
  ExternalProject_Add(filter_sodt_ml2025_${flavour}
    SOURCE_DIR "${PROJECT_SOURCE_DIR}"
    BINARY_DIR "${bin}"
    CMAKE_ARGS
      -DSODT_PLUGIN_ONLY=ON
      -DMESHLAB_SOURCE_DIR=${_ml}/src/meshlab
      -DMESHLAB_LIB_DIR=${libdir}
      -DMESHLAB_SCALAR=${scalar}
      -DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE}
      -DCMAKE_CXX_COMPILER=${CMAKE_CXX_COMPILER}
      -DSODT_USE_OPENMP=${SODT_USE_OPENMP}
    BUILD_ALWAYS ON
    INSTALL_COMMAND ""
    BUILD_BYPRODUCTS "${so}"
    USES_TERMINAL_BUILD ON)
  string(TOUPPER "${flavour}" up)
  set(SODT_PLUGIN_ML2025_${up} "${so}")
endforeach()
message(STATUS "sodt: also building the plugin for MeshLab 2025.07 (float) and PyMeshLab 2025.7 (double) from ${_ml}")
