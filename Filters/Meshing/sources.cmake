# Filters/Meshing's kernel and driver files (no vtk*.cxx), listed once:
# Filters/Meshing/CMakeLists.txt (the VTK module) and Wrapping/Pip/CMakeLists.txt (the
# wheel) both include this file, so that neither build can miss a file the other
# compiles. Paths are absolute. Both link TetGen (cmake/HOEmbedTetGen.cmake) and CGAL.
set(hoembed_meshing_dir "${CMAKE_CURRENT_LIST_DIR}")
set(hoembed_meshing_headers
  hoembedBoundaryCrossings.h
  hoembedCurvedBoundary.h
  hoembedCurvedMeshBuilder.h
  hoembedFreeNodeFit.h
  hoembedLinearMeshSmoothing.h
  hoembedMesherDriver.h
  hoembedSurfaceCheck.h
  hoembedSurfaceRead.h
  hoembedSurfaceRefine.h
  hoembedSurfaceWrap.h
  hoembedTetGenBridge.h)
set(hoembed_meshing_sources
  hoembedBoundaryCrossings.cxx
  hoembedCurvedBoundary.cxx
  hoembedCurvedMeshBuilder.cxx
  hoembedFreeNodeFit.cxx
  hoembedLinearMeshSmoothing.cxx
  hoembedMesherDriver.cxx
  hoembedSurfaceCheck.cxx
  hoembedSurfaceRead.cxx
  hoembedSurfaceRefine.cxx
  hoembedSurfaceWrap.cxx
  hoembedTetGenBridge.cxx)
list(TRANSFORM hoembed_meshing_headers PREPEND "${hoembed_meshing_dir}/")
list(TRANSFORM hoembed_meshing_sources PREPEND "${hoembed_meshing_dir}/")
