# The library's components: one static library per concern, each made of every .cpp in its folders under
# lib/, so a file added to a folder lands in its component without touching CMake. Each is exported as
# toolinc::<name> (see ToolincInstall.cmake); `toolinc` links them all (the tests and benchmarks use it).

set(TOOLINC_COMPONENTS "" CACHE INTERNAL "")
set(TOOLINC_COMPONENT_FOLDERS app yarp CACHE INTERNAL "")  # the apps' glue and the YARP adapter: not components

# toolinc_component(NAME FOLDERS dir... [EXTRA file...] [EXCLUDE file...] [PUBLIC dep...] [PRIVATE dep...])
function(toolinc_component name)
  cmake_parse_arguments(ARG "" "" "FOLDERS;EXTRA;EXCLUDE;PUBLIC;PRIVATE" ${ARGN})
  set(sources "")
  foreach(folder ${ARG_FOLDERS})
    file(GLOB folder_sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/lib/${folder}/*.cpp)
    list(APPEND sources ${folder_sources})
  endforeach()
  foreach(file ${ARG_EXTRA})
    list(APPEND sources ${PROJECT_SOURCE_DIR}/lib/${file})
  endforeach()
  foreach(file ${ARG_EXCLUDE})
    get_filename_component(file ${file} ABSOLUTE BASE_DIR ${PROJECT_SOURCE_DIR}/lib)
    list(REMOVE_ITEM sources ${file})
  endforeach()
  set(target toolinc_${name})
  add_library(${target} STATIC ${sources})
  add_library(toolinc::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME toolinc_${name})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
                                              $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/lib)  # the internals' headers
  target_compile_definitions(${target} PRIVATE TOOLINC_VERSION="${PROJECT_VERSION}")
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})
  set(TOOLINC_COMPONENTS ${TOOLINC_COMPONENTS} ${name} CACHE INTERNAL "")
  set(TOOLINC_COMPONENT_FOLDERS ${TOOLINC_COMPONENT_FOLDERS} ${ARG_FOLDERS} CACHE INTERNAL "")
endfunction()

# Eigen only.
toolinc_component(core FOLDERS core ann PUBLIC Eigen3::Eigen)
toolinc_component(geometry FOLDERS cloud frame registration PUBLIC toolinc::core PRIVATE spdlog::spdlog)
# Clouds (PLY, PCD) and JSON files: reading a cloud needs no geometry.
toolinc_component(io FOLDERS io PUBLIC toolinc::core nlohmann_json::nlohmann_json PRIVATE spdlog::spdlog liblzf::liblzf)
# The result files the executables exchange (tool_frame, tooltip, tool_pose, merge_report), which speak
# the geometry's types.
toolinc_component(results FOLDERS results PUBLIC toolinc::io toolinc::geometry)
# OpenCV from here on.
toolinc_component(session FOLDERS session PUBLIC toolinc::io toolinc::geometry opencv_core PRIVATE opencv_imgproc opencv_imgcodecs spdlog::spdlog)
toolinc_component(appearance FOLDERS appearance PUBLIC toolinc::session opencv_dnn
                  PRIVATE opencv_imgproc opencv_imgcodecs spdlog::spdlog)
toolinc_component(render FOLDERS render PUBLIC toolinc::session PRIVATE opencv_imgproc opencv_imgcodecs spdlog::spdlog)
toolinc_component(report FOLDERS report PUBLIC toolinc::results PRIVATE spdlog::spdlog)
# The recorder but its simulated robot, which is the simulator's (sim_backend drives lib/synth, and
# lib/synth uses the recorder's exploration poses).
toolinc_component(record FOLDERS record EXCLUDE record/sim_backend.cpp PUBLIC toolinc::session PRIVATE spdlog::spdlog)
toolinc_component(sim FOLDERS synth EXTRA record/sim_backend.cpp PUBLIC toolinc::record
                  PRIVATE opencv_imgproc opencv_calib3d spdlog::spdlog)

# A new folder of lib/ in no component would be silently left out of the build: say so.
file(GLOB lib_entries RELATIVE ${PROJECT_SOURCE_DIR}/lib LIST_DIRECTORIES true ${PROJECT_SOURCE_DIR}/lib/*)
foreach(entry ${lib_entries})
  if(IS_DIRECTORY ${PROJECT_SOURCE_DIR}/lib/${entry} AND NOT entry IN_LIST TOOLINC_COMPONENT_FOLDERS)
    message(FATAL_ERROR "lib/${entry}/ belongs to no component: add it to one in cmake/ToolincComponents.cmake")
  endif()
endforeach()

add_library(toolinc INTERFACE)
add_library(toolinc::toolinc ALIAS toolinc)
foreach(component ${TOOLINC_COMPONENTS})
  target_link_libraries(toolinc INTERFACE toolinc::${component})
endforeach()

# The executables' shared command-line glue (CLI11): linked by the apps only, never installed.
file(GLOB TOOLINC_APP_GLUE_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/lib/app/*.cpp)
add_library(toolinc_app STATIC ${TOOLINC_APP_GLUE_SOURCES})
target_compile_definitions(toolinc_app PRIVATE TOOLINC_VERSION="${PROJECT_VERSION}")
target_compile_options(toolinc_app PRIVATE -Wall -Wextra)
target_link_libraries(toolinc_app PUBLIC toolinc CLI11::CLI11 spdlog::spdlog)
