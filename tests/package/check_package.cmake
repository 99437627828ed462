# ctest's package test (cmake -P): installs toolinc into a temporary prefix, builds examples/ against that
# prefix alone and against the build tree, runs them, and checks
#  - the examples' tooltip equals find-tooltip's on the same cloud to 1e-9 m (C++ and, when built, Python);
#  - a consumer linking only toolinc::geometry links neither OpenCV nor CLI11 nor the other components.
#  - toolinc/pcl.hpp's conversions and overloads (tests/package/pcl), when PCL is installed;
#  - the project configures without GoogleTest and Google Benchmark when its tests and benchmarks are off.
# Variables: SOURCE_DIR, BUILD_DIR, WORK_DIR, INTERPRETER (a python3 for the comparisons), PYTHON (true
# when the module is built).
cmake_minimum_required(VERSION 3.16)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

# "tooltip X Y Z" in `text` against the position in find-tooltip's JSON `json`, to 1e-9 m.
function(check_tooltip what text json)
  file(WRITE ${WORK_DIR}/expected.json "${json}")
  file(WRITE ${WORK_DIR}/got.txt "${text}")
  run(${INTERPRETER} -c "
import json, re, sys
expected = json.load(open(sys.argv[1]))['position']
line = re.search(r'^tooltip (\\S+) (\\S+) (\\S+)$', open(sys.argv[2]).read(), re.M)
got = [float(v) for v in line.groups()]
diff = max(abs(g - e) for g, e in zip(got, expected))
confident = re.search(r'^confident (yes|no)$', open(sys.argv[2]).read(), re.M)
same_confidence = confident is None or (confident.group(1) == 'yes') == json.load(open(sys.argv[1]))['confidence']['confident']
print(diff)
sys.exit(0 if diff <= 1e-9 and same_confidence else 1)" ${WORK_DIR}/expected.json ${WORK_DIR}/got.txt)
  string(STRIP "${run_output}" difference)
  message(STATUS "${what}: tooltip equals find-tooltip's (largest difference ${difference} m)")
endfunction()

set(cloud ${SOURCE_DIR}/data/held/hoe.ply)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

# Without tests and benchmarks, the project configures with GoogleTest and Google Benchmark unfindable.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/without-tests -DTOOLINC_BUILD_TESTS=OFF
    -DTOOLINC_BUILD_BENCHMARKS=OFF -DTOOLINC_BUILD_PYTHON=OFF -DCMAKE_DISABLE_FIND_PACKAGE_GTest=ON
    -DCMAKE_DISABLE_FIND_PACKAGE_benchmark=ON)
run(${BUILD_DIR}/bin/find-tooltip ${cloud} -o - -q)
set(expected_json "${run_output}")

set(prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(file include/toolinc/frame/tool_frame.hpp include/toolinc/pcl.hpp bin/find-tooltip
             share/toolinc/configs/icub.json share/doc/toolinc/formats.md)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "not installed: ${file}")
  endif()
endforeach()
if(EXISTS ${prefix}/include/toolinc/app)
  message(FATAL_ERROR "the command-line glue's headers are installed")
endif()

foreach(where prefix build-tree)
  set(examples ${WORK_DIR}/examples-${where})
  if(where STREQUAL "prefix")
    set(locate -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
  else()
    set(locate -Dtoolinc_DIR=${BUILD_DIR} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
  endif()
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples -B ${examples} -G "Unix Makefiles" -DCMAKE_BUILD_TYPE=Release ${locate})
  run(${CMAKE_COMMAND} --build ${examples} -j 2)
  # The geometry-only consumer: its link line names no OpenCV, CLI11 or other component.
  file(READ ${examples}/CMakeFiles/frame_of_points.dir/link.txt link_line)
  string(TOLOWER "${link_line}" link_line_lower)
  foreach(forbidden opencv cli11 toolinc_io toolinc_session toolinc_appearance toolinc_sim)
    if(link_line_lower MATCHES "${forbidden}")
      message(FATAL_ERROR "${where}: a toolinc::geometry consumer links ${forbidden}:\n${link_line}")
    endif()
  endforeach()
  file(READ ${examples}/CMakeFiles/frame_of_points.dir/flags.make compile_flags)
  string(TOLOWER "${compile_flags}" compile_flags_lower)
  if(compile_flags_lower MATCHES "opencv")
    message(FATAL_ERROR "${where}: a toolinc::geometry consumer compiles with OpenCV's headers:\n${compile_flags}")
  endif()
  if(NOT link_line MATCHES "toolinc_geometry")
    message(FATAL_ERROR "${where}: frame_of_points does not link toolinc_geometry:\n${link_line}")
  endif()
  run(${examples}/frame_of_points)
  run(${examples}/tooltip_of_cloud ${cloud})
  check_tooltip("C++ example (${where})" "${run_output}" "${expected_json}")
  if(EXISTS ${examples}/pcl_tooltip)
    run(${examples}/pcl_tooltip ${cloud})
    message(STATUS "PCL example (${where}):\n${run_output}")
  elseif(where STREQUAL "prefix")
    message(STATUS "PCL example not built (PCL not found)")
  endif()
endforeach()

# toolinc/pcl.hpp against the installed headers and PCL's package, when PCL is there.
# (cmake -P knows no system prefixes: the usual ones are named.)
find_path(pcl_header pcl/point_cloud.h PATHS /usr/include /usr/local/include
          PATH_SUFFIXES pcl-1.14 pcl-1.13 pcl-1.12 pcl-1.11 pcl-1.10)
if(pcl_header)
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/pcl -B ${WORK_DIR}/pcl -G "Unix Makefiles"
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
  run(${CMAKE_COMMAND} --build ${WORK_DIR}/pcl -j 2)
  run(${WORK_DIR}/pcl/pcl_interop)
  message(STATUS "${run_output}")
else()
  message(STATUS "PCL not found: toolinc/pcl.hpp not checked")
endif()

if(PYTHON)
  file(GLOB module ${prefix}/lib*/python3/dist-packages/toolinc*.so)
  if(NOT module)
    message(FATAL_ERROR "the Python module is not installed")
  endif()
  get_filename_component(module_dir ${module} DIRECTORY)
  run(${CMAKE_COMMAND} -E env PYTHONPATH=${module_dir} ${INTERPRETER} ${SOURCE_DIR}/examples/tooltip.py ${cloud})
  check_tooltip("Python example (installed module)" "${run_output}" "${expected_json}")
endif()
