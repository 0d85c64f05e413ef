# TetGen for vtkTet10Mesher.
#
# 1. A system TetGen (tetgen.h + libtet) is used when found.
# 2. Otherwise TetGen 1.6.0 is compiled from the pinned `tetgen` source distribution on the
#    Python package index (it carries tetgen.cxx, tetgen.h, predicates.cxx). The archive is
#    fetched with `pip download`, its SHA-256 is checked, and the three files are compiled
#    into a static, position-independent library linked privately into FiltersMeshing.
#    Set HOEMBED_TETGEN_SOURCE_DIR to a folder holding those three files to skip the fetch.
#
# Patches applied to the compiled sources (copies in the build folder; the pinned archive
# and a given HOEMBED_TETGEN_SOURCE_DIR stay untouched):
# - cmake/tetgen-predicates-bounds.patch: Shewchuk's fast_expansion_sum_zeroelim reads
#   e[elen] / f[flen] (one past the end) after taking the last term. The value is never
#   used, so release builds compute the same results, but it is an out-of-bounds read
#   (AddressSanitizer found it on damaged surfaces); the patch skips the read.
# - cmake/tetgen-checkpoint.patch: a thread-local checkpoint callback polled at every new
#   tetrahedron and every flipnm call, through which hoembed::RunTetGen bounds TetGen's
#   work and lets a run be aborted (TetGen has no limit of its own on boundary recovery,
#   which can flip without end). Defines HOEMBED_TETGEN_CHECKPOINT for the bridge.
# A system TetGen is used unpatched: no work bound, no abort (hoembed::TetGenWorkIsBounded).
#
# TetGen is AGPL-3.0 (or a commercial licence from WIAS): see THIRD_PARTY_NOTICES.md.

set(HOEMBED_TETGEN_PYPI_VERSION "0.8.4")
set(HOEMBED_TETGEN_PYPI_URL "https://files.pythonhosted.org/packages/af/b6/bd320925cc4127c6f838c9127fdb0b2292147286500489d5ba6aac5d34e1/tetgen-0.8.4.tar.gz")
set(HOEMBED_TETGEN_PYPI_SHA256 "b6ca979ccecf43ddc0d31fa4f5a05da3cfeb4ab0705b8128530745bbab38bb86")
set(HOEMBED_TETGEN_SOURCE_DIR "" CACHE PATH "Folder with tetgen.cxx, tetgen.h, predicates.cxx (optional)")
option(HOEMBED_USE_SYSTEM_TETGEN "Use a system TetGen library when one is found" ON)

if (TARGET hoembed_tetgen)
  return ()
endif ()

if (HOEMBED_USE_SYSTEM_TETGEN AND NOT HOEMBED_TETGEN_SOURCE_DIR)
  find_path(TETGEN_INCLUDE_DIR tetgen.h PATH_SUFFIXES tetgen)
  find_library(TETGEN_LIBRARY NAMES tet tetgen)
  if (TETGEN_INCLUDE_DIR AND TETGEN_LIBRARY)
    message(STATUS "HOEmbed: using system TetGen ${TETGEN_LIBRARY}")
    add_library(hoembed_tetgen INTERFACE)
    target_include_directories(hoembed_tetgen SYSTEM INTERFACE "${TETGEN_INCLUDE_DIR}")
    target_link_libraries(hoembed_tetgen INTERFACE "${TETGEN_LIBRARY}")
    target_compile_definitions(hoembed_tetgen INTERFACE TETLIBRARY)
    return ()
  endif ()
endif ()

if (NOT HOEMBED_TETGEN_SOURCE_DIR)
  set(_tg_root "${CMAKE_BINARY_DIR}/_deps/tetgen")
  set(_tg_archive "${_tg_root}/tetgen-${HOEMBED_TETGEN_PYPI_VERSION}.tar.gz")
  set(HOEMBED_TETGEN_SOURCE_DIR "${_tg_root}/tetgen-${HOEMBED_TETGEN_PYPI_VERSION}/src")
  if (NOT EXISTS "${HOEMBED_TETGEN_SOURCE_DIR}/tetgen.cxx")
    if (NOT EXISTS "${_tg_archive}")
      message(STATUS "HOEmbed: downloading the tetgen==${HOEMBED_TETGEN_PYPI_VERSION} source archive")
      file(DOWNLOAD "${HOEMBED_TETGEN_PYPI_URL}" "${_tg_archive}"
        EXPECTED_HASH SHA256=${HOEMBED_TETGEN_PYPI_SHA256} STATUS _tg_status TLS_VERIFY ON)
      list(GET _tg_status 0 _tg_rc)
      if (NOT _tg_rc EQUAL 0)
        # Fall back on pip, which knows the index configured on this machine.
        file(REMOVE "${_tg_archive}")
        find_package(Python3 COMPONENTS Interpreter REQUIRED)
        execute_process(
          COMMAND "${Python3_EXECUTABLE}" -m pip download --no-deps --no-binary=:all: -q
                  -d "${_tg_root}" "tetgen==${HOEMBED_TETGEN_PYPI_VERSION}"
          RESULT_VARIABLE _tg_rc)
      endif ()
      if (NOT EXISTS "${_tg_archive}")
        message(FATAL_ERROR "HOEmbed: could not download the TetGen sources "
          "(${HOEMBED_TETGEN_PYPI_URL}: ${_tg_status}). Set HOEMBED_TETGEN_SOURCE_DIR "
          "to a folder with tetgen.cxx, tetgen.h and predicates.cxx.")
      endif ()
    endif ()
    file(SHA256 "${_tg_archive}" _tg_hash)
    if (NOT _tg_hash STREQUAL HOEMBED_TETGEN_PYPI_SHA256)
      file(REMOVE "${_tg_archive}")
      message(FATAL_ERROR "HOEmbed: SHA-256 mismatch for ${_tg_archive}: got ${_tg_hash}, "
        "expected ${HOEMBED_TETGEN_PYPI_SHA256}. The archive was removed.")
    endif ()
    file(ARCHIVE_EXTRACT INPUT "${_tg_archive}" DESTINATION "${_tg_root}"
      PATTERNS "tetgen-${HOEMBED_TETGEN_PYPI_VERSION}/src/tetgen.cxx"
               "tetgen-${HOEMBED_TETGEN_PYPI_VERSION}/src/tetgen.h"
               "tetgen-${HOEMBED_TETGEN_PYPI_VERSION}/src/predicates.cxx"
               "tetgen-${HOEMBED_TETGEN_PYPI_VERSION}/src/tetgen-license")
  endif ()
endif ()

foreach (_f tetgen.cxx tetgen.h predicates.cxx)
  if (NOT EXISTS "${HOEMBED_TETGEN_SOURCE_DIR}/${_f}")
    message(FATAL_ERROR "HOEmbed: ${HOEMBED_TETGEN_SOURCE_DIR}/${_f} is missing")
  endif ()
endforeach ()
# Patched copies in the build folder, redone when a patch or a source changes.
find_program(HOEMBED_PATCH_EXECUTABLE patch)
if (NOT HOEMBED_PATCH_EXECUTABLE)
  message(FATAL_ERROR "HOEmbed: the 'patch' program is needed to patch TetGen "
    "(Debian package 'patch'; scripts/setup.sh installs it).")
endif ()
set(_tg_patches
  "${CMAKE_CURRENT_LIST_DIR}/tetgen-predicates-bounds.patch"
  "${CMAKE_CURRENT_LIST_DIR}/tetgen-checkpoint.patch")
set(_tg_key "")
foreach (_f IN LISTS _tg_patches)
  file(SHA256 "${_f}" _h)
  string(APPEND _tg_key "${_h}")
endforeach ()
foreach (_f tetgen.cxx tetgen.h predicates.cxx)
  file(SHA256 "${HOEMBED_TETGEN_SOURCE_DIR}/${_f}" _h)
  string(APPEND _tg_key "${_h}")
endforeach ()
set(_tg_patched "${CMAKE_BINARY_DIR}/_deps/tetgen-patched")
set(_tg_stamp "${_tg_patched}/.hoembed-patched")
set(_tg_old_key "")
if (EXISTS "${_tg_stamp}")
  file(READ "${_tg_stamp}" _tg_old_key)
endif ()
if (NOT _tg_old_key STREQUAL _tg_key)
  file(REMOVE_RECURSE "${_tg_patched}")
  file(MAKE_DIRECTORY "${_tg_patched}")
  foreach (_f tetgen.cxx tetgen.h predicates.cxx)
    configure_file("${HOEMBED_TETGEN_SOURCE_DIR}/${_f}" "${_tg_patched}/${_f}" COPYONLY)
  endforeach ()
  foreach (_p IN LISTS _tg_patches)
    execute_process(COMMAND "${HOEMBED_PATCH_EXECUTABLE}" -p1 --batch --forward -s -i "${_p}"
      WORKING_DIRECTORY "${_tg_patched}" RESULT_VARIABLE _rc OUTPUT_VARIABLE _out ERROR_VARIABLE _out)
    if (NOT _rc EQUAL 0)
      message(FATAL_ERROR "HOEmbed: ${_p} does not apply to the TetGen sources in "
        "${HOEMBED_TETGEN_SOURCE_DIR} (a TetGen other than tetgen==${HOEMBED_TETGEN_PYPI_VERSION}?):\n${_out}")
    endif ()
  endforeach ()
  file(WRITE "${_tg_stamp}" "${_tg_key}")
endif ()
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_tg_patches})

message(STATUS "HOEmbed: compiling TetGen from ${HOEMBED_TETGEN_SOURCE_DIR} (patched copy in ${_tg_patched})")
add_library(hoembed_tetgen STATIC
  "${_tg_patched}/tetgen.cxx"
  "${_tg_patched}/predicates.cxx")
set_target_properties(hoembed_tetgen PROPERTIES POSITION_INDEPENDENT_CODE ON)
target_compile_definitions(hoembed_tetgen PUBLIC TETLIBRARY HOEMBED_TETGEN_CHECKPOINT_PATCH)
# Exact predicates rely on IEEE round-to-nearest without fused multiply-add.
target_compile_options(hoembed_tetgen PRIVATE -w -ffp-contract=off)
target_include_directories(hoembed_tetgen SYSTEM PUBLIC "$<BUILD_INTERFACE:${_tg_patched}>")
