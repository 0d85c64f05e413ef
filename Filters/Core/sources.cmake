# Filters/Core's files, listed once: Filters/Core/CMakeLists.txt (the VTK module) and
# Wrapping/Pip/CMakeLists.txt (the wheel) both include this file, so that neither build
# can miss a file the other compiles. Paths are absolute.
set(hoembed_core_dir "${CMAKE_CURRENT_LIST_DIR}")
set(hoembed_core_headers
  hoembedShapeFunctions.h
  hoembedCsr.h
  hoembedElementGeometry.h
  hoembedTetMeshTopology.h
  hoembedBoundaryNormals.h
  hoembedMeshFingerprint.h
  hoembedSpatialOrder.h
  hoembedLanes.h
  hoembedParallel.h
  hoembedVector3.h
  hoembedArrayNames.h
  hoembedPropertyRange.h
  hoembedTetMeshInput.h
  hoembedTetMeshInputVTK.h
  hoembedQuadraticMap.h
  hoembedLagrangeTet.h
  hoembedLagrangeHex.h)
set(hoembed_core_sources
  hoembedShapeFunctions.cxx
  hoembedElementGeometry.cxx
  hoembedTetMeshTopology.cxx
  hoembedBoundaryNormals.cxx
  hoembedMeshFingerprint.cxx
  hoembedSpatialOrder.cxx
  hoembedTetMeshInput.cxx
  hoembedQuadraticMap.cxx
  hoembedLagrangeTet.cxx
  hoembedLagrangeHex.cxx)
list(TRANSFORM hoembed_core_headers PREPEND "${hoembed_core_dir}/")
list(TRANSFORM hoembed_core_sources PREPEND "${hoembed_core_dir}/")
