# Filters/Simulation's solver and driver files (no vtk*.cxx), listed once:
# Filters/Simulation/CMakeLists.txt (the VTK module) and Wrapping/Pip/CMakeLists.txt (the
# wheel) both include this file, so that neither build can miss a file the other
# compiles. Paths are absolute. The solver's build options (CHOLMOD, -march=native):
# cmake/HOEmbedStepperOptions.cmake, on hoembed_simulation_kernel_sources.
set(hoembed_simulation_dir "${CMAKE_CURRENT_LIST_DIR}")
set(hoembed_simulation_headers
  hoembedTetElementMatrices.h
  hoembedCorotationalSolver.h
  hoembedHyperelasticMaterial.h
  hoembedStepperDriver.h)
set(hoembed_simulation_kernel_sources
  hoembedTetElementMatrices.cxx
  hoembedCorotationalSolver.cxx
  hoembedCorotationalSolverLinear.cxx
  hoembedCorotationalBlockFactor.cxx
  hoembedCorotationalSolverAssembly.cxx
  hoembedHyperelasticMaterial.cxx
  hoembedHyperelasticSolver.cxx)
# the set-up and stepping loop around the solver (the filter and the pip wheel call it);
# not a kernel: compiled with the filter's flags (no -march=native, whose FMA contraction
# would change the clamp tolerance's bits)
set(hoembed_simulation_driver_sources
  hoembedStepperDriver.cxx)
set(hoembed_simulation_private_headers
  hoembedCorotationalSolverImpl.h)
foreach (list headers kernel_sources driver_sources private_headers)
  list(TRANSFORM hoembed_simulation_${list} PREPEND "${hoembed_simulation_dir}/")
endforeach ()
