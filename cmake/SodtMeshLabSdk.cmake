# SPDX-License-Identifier: GPL-3.0-or-later
# Recognises the MeshLab tree the plugin is built against and where its vcglib
# lives. Two plugin APIs exist:
#   2020.09 (MeshFilterInterface): Debian's `apt-get source meshlab` tree, with
#            src/common/interfaces.h and vcglib/ at the top;
#   2021.05 and later (FilterPlugin): an upstream source tree (tag MeshLab-20xx.yy)
#            with src/common/plugins/interfaces/filter_plugin.h and src/vcglib/.
#
# sodt_detect_meshlab_sdk(DIR) sets, in the caller's scope:
#   SODT_MESHLAB_API      2020 or 2021
#   SODT_MESHLAB_VERSION  the tree's ML_VERSION (e.g. 2020.09, 2025.07)
#   SODT_VCGLIB_DIR       the tree's vcglib (the core is compiled against it)
# and stops with a message saying what was looked for when DIR is neither.
function(sodt_detect_meshlab_sdk dir)
  set(version "")
  if(EXISTS "${dir}/ML_VERSION")
    file(READ "${dir}/ML_VERSION" version)
    string(STRIP "${version}" version)
  endif()
  if(EXISTS "${dir}/src/common/plugins/interfaces/filter_plugin.h")
    if(NOT EXISTS "${dir}/src/vcglib/vcg/complex/complex.h")
      message(FATAL_ERROR
        "MESHLAB_SOURCE_DIR='${dir}' is a MeshLab ${version} tree without its vcglib: "
        "src/vcglib/vcg/complex/complex.h is missing. Clone it with --recursive (or unpack vcglib "
        "into src/vcglib); scripts/build-meshlab-2025.sh prepares a complete tree.")
    endif()
    if(NOT version MATCHES "^20[0-9][0-9]\\.[0-9][0-9]$")
      message(FATAL_ERROR "MESHLAB_SOURCE_DIR='${dir}': ML_VERSION '${version}' is not a YYYY.MM release.")
    endif()
    set(SODT_MESHLAB_API 2021 PARENT_SCOPE)
    set(SODT_VCGLIB_DIR "${dir}/src/vcglib" PARENT_SCOPE)
  elseif(EXISTS "${dir}/src/common/interfaces.h" AND EXISTS "${dir}/vcglib/vcg/complex/complex.h")
    file(STRINGS "${dir}/src/common/interfaces.h" has_old_api REGEX "class MeshFilterInterface")
    if(NOT has_old_api)
      message(FATAL_ERROR
        "MESHLAB_SOURCE_DIR='${dir}': src/common/interfaces.h declares no MeshFilterInterface; "
        "this MeshLab release is not supported (2020.09 or 2021.05 and later are).")
    endif()
    set(SODT_MESHLAB_API 2020 PARENT_SCOPE)
    set(SODT_VCGLIB_DIR "${dir}/vcglib" PARENT_SCOPE)
  else()
    message(FATAL_ERROR
      "MESHLAB_SOURCE_DIR='${dir}' is not a MeshLab tree the plugin can be built against. "
      "Looked for src/common/interfaces.h + vcglib/ (MeshLab 2020.09, Debian's 'apt-get source "
      "meshlab'; 'sudo scripts/install-deps.sh' fetches it into .deps/) and for "
      "src/common/plugins/interfaces/filter_plugin.h + src/vcglib/ (MeshLab 2021.05 or later; "
      "scripts/build-meshlab-2025.sh prepares MeshLab 2025.07). Pass -DMESHLAB_SOURCE_DIR=<tree>.")
  endif()
  set(SODT_MESHLAB_VERSION "${version}" PARENT_SCOPE)
endfunction()
