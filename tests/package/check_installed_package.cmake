# The package as a user gets it: `cmake --install` into a fresh prefix, then the C++ examples
# built with find_package(fnopt) against that prefix alone and run, and `import fnopt` with the
# documented PYTHONPATH finding the installed module and its installed model. Run by CTest
# (tests/CMakeLists.txt) as
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DPYTHON=... -P check_installed_package.cmake
function(run what)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY ${WORK_DIR} RESULT_VARIABLE status OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${what} failed (${status}):\n${out}\n${err}")
  endif()
  set(output "${out}${err}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

run("configuring the examples" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples -B ${WORK_DIR}/examples -G Ninja
    -DCMAKE_PREFIX_PATH=${prefix})
run("building the examples" ${CMAKE_COMMAND} --build ${WORK_DIR}/examples)
run("compare_with_newton" ${WORK_DIR}/examples/compare_with_newton pqn 10 8)
if(NOT output MATCHES "pqn 10 on 8x8, 60 frames: .* e_CD [0-9.]+ x 10\\^-3")
  message(FATAL_ERROR "compare_with_newton printed:\n${output}")
endif()
message(STATUS "${output}")
run("closed_loop" ${WORK_DIR}/examples/closed_loop)
message(STATUS "${output}")

file(GLOB site ${prefix}/lib/python3*/dist-packages)
foreach(name _fnopt.pyi py.typed records.py)
  if(NOT EXISTS ${site}/fnopt/${name})
    message(FATAL_ERROR "cmake --install did not install fnopt/${name}")
  endif()
endforeach()
run("import fnopt" ${CMAKE_COMMAND} -E env PYTHONPATH=${site} OMP_WAIT_POLICY=PASSIVE ${PYTHON}
    ${CMAKE_CURRENT_LIST_DIR}/import_installed.py)
if(NOT output MATCHES "^${prefix}/lib/python3[^\n]*/fnopt/__init__.py\n${prefix}/share/fnopt/models/fnopt-32.pt")
  message(FATAL_ERROR "the installed module is not the one imported, or its model is not the installed one:\n${output}")
endif()
file(REMOVE_RECURSE ${WORK_DIR})
