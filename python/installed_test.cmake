# ctest's python_installed (python/CMakeLists.txt): the package from the install prefix, run from
# a directory outside the source and build trees: `import ldlpgs` gives the bindings as the build
# tree's package does, and `python3 -m ldlpgs.study` runs the installed study (a LocalCluster's
# workers import the same installed package). cmake -DBUILD=... -DWORK=... -DPYTHON=... -DPACKAGE_DIR=... -P this
cmake_minimum_required(VERSION 3.25)
foreach(var BUILD WORK PYTHON PACKAGE_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "installed_test.cmake: -D${var}= is required")
  endif()
endforeach()

function(run)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${WORK}/prefix/${PACKAGE_DIR} PYTHONDONTWRITEBYTECODE=1 ${ARGN}
                  WORKING_DIRECTORY ${WORK} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(FATAL_ERROR "failed (${rc}): ${cmd}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix)
# (no semicolon: it would split the argument in two)
run(${PYTHON} -c "import ldlpgs, ldlpgs.study\nprint(ldlpgs.__file__, ldlpgs._ldlpgs.__file__, ldlpgs.study.__file__, \
ldlpgs.order.__module__, ldlpgs.InputError.__module__)")
foreach(file __init__.py _ldlpgs study.py)
  string(FIND "${out}" "${WORK}/prefix/${PACKAGE_DIR}/ldlpgs/${file}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the package did not come from the prefix: ${out}")
  endif()
endforeach()
if(NOT out MATCHES " ldlpgs ldlpgs\n$")
  message(FATAL_ERROR "the bindings are not named ldlpgs.X: ${out}")
endif()
run(${PYTHON} -m ldlpgs.study --workers 1 --quiet orderings ${WORK}/prefix/share/ldlpgs/matrices/bcsstk01.mtx)
if(NOT out MATCHES "^orderings: 1 tasks \\(0 failed\\)")
  message(FATAL_ERROR "the installed study did not run: ${out}")
endif()
