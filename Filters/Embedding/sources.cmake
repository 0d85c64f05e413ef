# Filters/Embedding's kernel and driver files (no vtk*.cxx), listed once:
# Filters/Embedding/CMakeLists.txt (the VTK module) and Wrapping/Pip/CMakeLists.txt (the
# wheel) both include this file, so that neither build can miss a file the other compiles
# or a flag it sets. Paths are absolute; the source properties apply in the including
# directory, where each build makes its target.
set(hoembed_embedding_dir "${CMAKE_CURRENT_LIST_DIR}")
set(hoembed_embedding_headers
  hoembedAabbTree.h
  hoembedBoxGrid.h
  hoembedClosestPoint.h
  hoembedClosestPointCertify.h
  hoembedEmbeddingDriver.h
  hoembedEmbeddingFlood.h
  hoembedEmbeddingMesh.h
  hoembedEmbeddingSearch.h
  hoembedSurfaceTriangles.h
  hoembedTetBarycentric.h
  hoembedLagrangeEmbedding.h
  hoembedLagrangeHexEmbedding.h)
set(hoembed_embedding_sources
  hoembedAabbTree.cxx
  hoembedBoxGrid.cxx
  hoembedClosestPoint.cxx
  hoembedClosestPointCertify.cxx
  hoembedClosestPointNewton.cxx
  hoembedEmbeddingDriver.cxx
  hoembedEmbeddingFlood.cxx
  hoembedEmbeddingMesh.cxx
  hoembedEmbeddingSearch.cxx
  hoembedSurfaceTriangles.cxx
  hoembedTetBarycentric.cxx
  hoembedLagrangeEmbedding.cxx
  hoembedLagrangeFaceSearch.cxx
  hoembedLagrangeHexEmbedding.cxx)
set(hoembed_embedding_private_headers
  hoembedClosestPointInternal.h
  hoembedLagrangeEmbeddingInternal.h)
list(TRANSFORM hoembed_embedding_headers PREPEND "${hoembed_embedding_dir}/")
list(TRANSFORM hoembed_embedding_sources PREPEND "${hoembed_embedding_dir}/")
list(TRANSFORM hoembed_embedding_private_headers PREPEND "${hoembed_embedding_dir}/")
include("${CMAKE_CURRENT_LIST_DIR}/../../cmake/HOEmbedKernelOptions.cmake")
hoembed_no_math_errno(${hoembed_embedding_sources})
