# ctest script: install HOEmbed into a scratch prefix, build Examples/Cxx against it with
# find_package(HOEmbed), run it and check the series it writes.
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -P example_build_test.cmake
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix"
  RESULT_VARIABLE rc OUTPUT_QUIET)
if (NOT rc EQUAL 0)
  message(FATAL_ERROR "install failed")
endif ()
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE_DIR}/Examples/Cxx" -B "${WORK_DIR}/build"
  "-DHOEmbed_DIR=${WORK_DIR}/prefix/lib/cmake/HOEmbed" -DCMAKE_BUILD_TYPE=Release
  RESULT_VARIABLE rc)
if (NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the example with find_package(HOEmbed) failed")
endif ()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${WORK_DIR}/build" RESULT_VARIABLE rc)
if (NOT rc EQUAL 0)
  message(FATAL_ERROR "building the example failed")
endif ()
execute_process(COMMAND "${WORK_DIR}/build/hoembed_pipeline" "${WORK_DIR}/out" RESULT_VARIABLE rc)
if (NOT rc EQUAL 0)
  message(FATAL_ERROR "running the example failed")
endif ()
foreach (f fe_mesh.pvd surface.pvd fe_mesh/fe_mesh_000010.vtu surface/surface_000010.vtp)
  if (NOT EXISTS "${WORK_DIR}/out/${f}")
    message(FATAL_ERROR "the example did not write ${f}")
  endif ()
endforeach ()
message(STATUS "example built against the installed HOEmbed and ran")
