# Compile options of the per-point kernels, for the modules' sources.cmake (so the VTK
# modules and the wheel set them alike).

# hoembed_no_math_errno(<sources>...): the kernels never read errno, so sqrt compiles to
# the instruction alone (results are unchanged: IEEE sqrt either way). A source property:
# call from the directory that compiles the sources.
function(hoembed_no_math_errno)
  if (CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    set_source_files_properties(${ARGN} PROPERTIES COMPILE_OPTIONS "-fno-math-errno")
  endif ()
endfunction()
