# Included by the top-level CMakeLists.txt: builds the fuzz targets (fuzz/CMakeLists.txt) with
# clang in build/fuzz and runs each briefly as a ctest test (fuzz/run.py --smoke).
option(HRPP_FUZZ "build the libFuzzer targets with clang and run each briefly in ctest" ON)
if(HRPP_FUZZ)
  find_program(HRPP_CLANGXX NAMES clang++ clang++-14)
  if(NOT HRPP_CLANGXX)
    message(FATAL_ERROR "clang++ not found: the fuzz targets need clang and its libFuzzer runtime "
                        "(run `make setup`, or configure with -DHRPP_FUZZ=OFF)")
  endif()
  include(ExternalProject)
  ExternalProject_Add(hrpp_fuzz
    SOURCE_DIR "${PROJECT_SOURCE_DIR}/fuzz"
    BINARY_DIR "${CMAKE_BINARY_DIR}/fuzz"
    CMAKE_GENERATOR "${CMAKE_GENERATOR}"
    CMAKE_ARGS -DCMAKE_CXX_COMPILER=${HRPP_CLANGXX} -DCMAKE_BUILD_TYPE=RelWithDebInfo
    BUILD_ALWAYS ON
    INSTALL_COMMAND "")
  # A fixed number of runs with a fixed seed: reproducible, a few seconds each.
  foreach(t scene:3000 stream:4000 hash:20000 traverse:6000)
    string(REPLACE ":" ";" tr "${t}")
    list(GET tr 0 target)
    list(GET tr 1 runs)
    add_test(NAME fuzz.${target}
             COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/fuzz/run.py --smoke
                     --bin-dir ${CMAKE_BINARY_DIR}/fuzz --runs ${runs} ${target})
    set_tests_properties(fuzz.${target} PROPERTIES TIMEOUT 300)
  endforeach()
endif()
