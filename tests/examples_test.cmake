# ctest's examples tests (tests/CMakeLists.txt): builds examples/ as an outside project would and
# runs its programs. cmake -DMODE=installed|subdirectory -DSOURCE=... -DBUILD=... -DWORK=... -P this
#   installed:    cmake --install BUILD into WORK/prefix, then examples/ with find_package(ldlpgs)
#                 against that prefix, from a clean build directory; checks that only the
#                 library's headers were installed.
#   subdirectory: examples/ with add_subdirectory(SOURCE), CLI11, GTest, Google Benchmark and
#                 pybind11 hidden from CMake: the libraries must build with their own dependencies.
# Both: the examples compile with -Wconversion -Werror and as C++17 consumers (our targets must
# raise them to C++20), our include directories must arrive as -isystem, no LDLPGS_ definition
# of ours may reach them, and no CTest dashboard target or ldlpgs program may appear.
cmake_minimum_required(VERSION 3.25)
foreach(var MODE SOURCE BUILD WORK)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "examples_test.cmake: -D${var}= is required")
  endif()
endforeach()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(FATAL_ERROR "failed (${rc}): ${cmd}\n${out}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK})
# Make, whatever CMAKE_GENERATOR says: the leak check below reads Make's `help` listing (Ninja's
# lists no executables).
set(common -G "Unix Makefiles" -DEXAMPLES_WERROR=ON -DCMAKE_CXX_STANDARD=17 -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
if(MODE STREQUAL "installed")
  run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix)
  file(GLOB_RECURSE headers RELATIVE ${WORK}/prefix/include ${WORK}/prefix/include/*)
  foreach(h IN LISTS headers)
    if(NOT h MATCHES "^ldlpgs/((sparse|ordering|factor|solver|physics|physics/io)/[a-z_]+\\.h|version\\.h)$")
      message(FATAL_ERROR "installed a header that is not the library's: include/${h}")
    endif()
  endforeach()
  if(NOT "ldlpgs/factor/factor.h" IN_LIST headers)
    message(FATAL_ERROR "include/ldlpgs/factor/factor.h was not installed")
  endif()
  run(${CMAKE_COMMAND} -S ${SOURCE}/examples -B ${WORK}/build -DCMAKE_PREFIX_PATH=${WORK}/prefix ${common})
  set(our_include ${WORK}/prefix/include)
elseif(MODE STREQUAL "subdirectory")
  # -O0: this builds the libraries again, and only their compilation is under test. Build type
  # None (no flags: -O0, assertions on, as Debug) rather than Debug: without -g the libraries
  # compile in less CPU time (DEVELOPERS.md, "Where CI's time goes").
  run(${CMAKE_COMMAND} -S ${SOURCE}/examples -B ${WORK}/build -DLDLPGS_SOURCE_DIR=${SOURCE} -DCMAKE_BUILD_TYPE=None
      -DCMAKE_DISABLE_FIND_PACKAGE_CLI11=ON -DCMAKE_DISABLE_FIND_PACKAGE_GTest=ON
      -DCMAKE_DISABLE_FIND_PACKAGE_benchmark=ON -DCMAKE_DISABLE_FIND_PACKAGE_pybind11=ON ${common})
  set(our_include ${WORK}/build/ldlpgs/include)  # the staged tree (cmake/ldlpgs_library.cmake)
else()
  message(FATAL_ERROR "examples_test.cmake: MODE is installed or subdirectory, not ${MODE}")
endif()

run(${CMAKE_COMMAND} --build ${WORK}/build --target help)
foreach(target Experimental Nightly Continuous ldlpgs ldlpgs_test factor_bench)
  if(run_output MATCHES "\\.\\.\\. ${target}\n")
    message(FATAL_ERROR "the consumer's build has a target ${target} (CTest dashboards, program or tests leaked)")
  endif()
endforeach()
include(ProcessorCount)
ProcessorCount(jobs)
run(${CMAKE_COMMAND} --build ${WORK}/build -j ${jobs})

file(READ ${WORK}/build/compile_commands.json commands)
string(JSON count LENGTH "${commands}")
math(EXPR last "${count} - 1")
foreach(i RANGE ${last})
  string(JSON file GET "${commands}" ${i} file)
  if(NOT file MATCHES "/examples/[a-z_]+\\.cpp$")
    continue()
  endif()
  string(JSON command GET "${commands}" ${i} command)
  if(command MATCHES "-DLDLPGS_")
    message(FATAL_ERROR "a definition of ours reached the consumer: ${command}")
  endif()
  string(FIND "${command}" "-isystem ${our_include} " at)
  if(at EQUAL -1)
    message(FATAL_ERROR "our include directory is not a system one for the consumer: ${command}")
  endif()
endforeach()

foreach(example order_and_solve step_chain drive_between_steps)
  run(${WORK}/build/${example})
  message(STATUS "${example}:\n${run_output}")
endforeach()

# The README's smallest consumer, as printed there (examples/consumer/CMakeLists.txt).
if(MODE STREQUAL "installed")
  run(${CMAKE_COMMAND} -S ${SOURCE}/examples/consumer -B ${WORK}/consumer -DCMAKE_PREFIX_PATH=${WORK}/prefix)
  run(${CMAKE_COMMAND} --build ${WORK}/consumer)
  run(${WORK}/consumer/consumer)
  if(NOT run_output MATCHES "x = \\(0\\.090909, 0\\.636364\\)")
    message(FATAL_ERROR "consumer printed: ${run_output}")
  endif()
endif()
