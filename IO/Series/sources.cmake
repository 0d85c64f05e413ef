# IO/Series's VTK-free files (no vtk*.cxx), listed once: IO/Series/CMakeLists.txt (the
# VTK module) and Wrapping/Pip/CMakeLists.txt (the wheel) both include this file.
# Paths are absolute.
set(hoembed_series_headers "${CMAKE_CURRENT_LIST_DIR}/hoembedSeriesFiles.h")
set(hoembed_series_sources "${CMAKE_CURRENT_LIST_DIR}/hoembedSeriesFiles.cxx")
