# Filters/Transfer's kernel and driver files (no vtk*.cxx), listed once:
# Filters/Transfer/CMakeLists.txt (the VTK module) and Wrapping/Pip/CMakeLists.txt (the
# wheel) both include this file, so that neither build can miss a file the other compiles
# or a flag it sets. Paths are absolute; the source properties apply in the including
# directory, where each build makes its target.
set(hoembed_transfer_dir "${CMAKE_CURRENT_LIST_DIR}")
set(hoembed_transfer_headers
  hoembedTransferDriver.h
  hoembedTransferKernel.h
  hoembedTransferNormals.h
  hoembedLagrangeTransfer.h)
set(hoembed_transfer_sources
  hoembedTransferDriver.cxx
  hoembedTransferKernel.cxx
  hoembedTransferKernelAvx2.cxx
  hoembedTransferNormals.cxx
  hoembedLagrangeTransfer.cxx)
list(TRANSFORM hoembed_transfer_headers PREPEND "${hoembed_transfer_dir}/")
list(TRANSFORM hoembed_transfer_sources PREPEND "${hoembed_transfer_dir}/")
include("${CMAKE_CURRENT_LIST_DIR}/../../cmake/HOEmbedKernelOptions.cmake")
hoembed_no_math_errno(${hoembed_transfer_sources})
# The per-vertex transfer kernel has an AVX2 copy (hoembedTransferKernelAvx2.cxx, chosen at
# run time on CPUs that have AVX2; the same bits as the plain one), on x86-64 GCC/Clang:
# the dispatch and the copy see the definition, in any binary for any x86-64.
if (CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang" AND CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
  set_source_files_properties(
    "${hoembed_transfer_dir}/hoembedTransferKernel.cxx"
    "${hoembed_transfer_dir}/hoembedTransferKernelAvx2.cxx"
    PROPERTIES COMPILE_DEFINITIONS HOEMBED_TRANSFER_AVX2)
endif ()
