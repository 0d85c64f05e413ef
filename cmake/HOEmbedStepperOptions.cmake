# The FE stepper's build options, one place for the VTK module (Filters/Simulation) and
# the pip wheel (Wrapping/Pip), which compile the same solver sources:
# - SuiteSparse CHOLMOD (supernodal, METIS/AMD orderings) for the sparse Cholesky factor
#   when found; without it Eigen's SimplicialLLT (same results, slower on meshes of
#   thousands of cells). Licence: CHOLMOD's Supernodal module is GPL-2.0-or-later (Core
#   and Cholesky LGPL-2.1+); a build linking it is bound by the GPL (compatible with
#   TetGen's AGPL-3) and needs libcholmod at run time.
# - -march=native for the solver kernels (element products and triangular solves are
#   worth the host's AVX2/FMA; Benchmarks/RESULTS.md, stepper). Eigen stays private to
#   these .cxx files, all compiled with the same flags, so this is ABI-safe. Off by
#   default (binaries for any x86-64); `make build` and `make test-pip` turn it on, so
#   both builds give the same bits (FMA contraction changes the last ones).
option(HOEMBED_USE_CHOLMOD "Use SuiteSparse CHOLMOD in the FE stepper when found" ON)
option(HOEMBED_SIMULATION_NATIVE "Compile the FE stepper kernels with -march=native" OFF)

# hoembed_stepper_options(<target> <kernel sources>...): call from the directory that
# compiles the sources (source properties are per directory).
function(hoembed_stepper_options target)
  get_property(aliased TARGET ${target} PROPERTY ALIASED_TARGET)
  if (aliased)
    set(target ${aliased})
  endif ()
  find_path(HOEMBED_CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
  find_library(HOEMBED_CHOLMOD_LIBRARY cholmod)
  if (HOEMBED_USE_CHOLMOD AND HOEMBED_CHOLMOD_INCLUDE_DIR AND HOEMBED_CHOLMOD_LIBRARY)
    message(STATUS "${target}: FE stepper with CHOLMOD (${HOEMBED_CHOLMOD_LIBRARY})")
    target_include_directories(${target} PRIVATE "${HOEMBED_CHOLMOD_INCLUDE_DIR}")
    target_link_libraries(${target} PRIVATE "${HOEMBED_CHOLMOD_LIBRARY}")
    target_compile_definitions(${target} PRIVATE HOEMBED_HAVE_CHOLMOD=1)
  endif ()
  if (HOEMBED_SIMULATION_NATIVE)
    include(CheckCXXCompilerFlag)
    check_cxx_compiler_flag("-march=native" HOEMBED_HAVE_MARCH_NATIVE)
    if (HOEMBED_HAVE_MARCH_NATIVE)
      set_source_files_properties(${ARGN} PROPERTIES COMPILE_OPTIONS "-march=native")
    endif ()
  endif ()
endfunction()
