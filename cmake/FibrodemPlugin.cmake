# fibrodem_add_cell_model(NAME source...)
# fibrodem_add_contact_law(NAME source...)
# Build a plugin as a shared module: libfibrodem_<NAME>.so (target
# fibrodem_<NAME>) for a cell model, libfibrodem_contact_law_<NAME>.so (target
# fibrodem_contact_law_<NAME>) for a contact law. One definition for
# both routes: the in-tree build (plugins/, tests/) and an out-of-tree plugin
# after `find_package(fibrodem)`, which includes this file from the install.
#
# A plugin compiles against the target fibrodem::plugin_sdk only: the
# header-only plugin contract (model/cell_model.hpp, block_access.hpp,
# simd.hpp with xsimd; mechanics/contact_law_plugin.hpp) and links nothing.
#
# Optional variables, read when the function is called:
#   FIBRODEM_PLUGIN_OUTPUT_DIR   where the .so is built (default: the
#                                project's build directory)
#   FIBRODEM_PLUGIN_INSTALL_DIR  where `cmake --install` puts it (default:
#                                lib/fibrodem/plugins, where an installed
#                                fibrodem of the same prefix looks)
#   FIBRODEM_PLUGIN_NO_INSTALL   TRUE: no install rule (test plugins)

# The rule for a plugin's name, the one `fibrodem new-model` and `fibrodem
# import-cellml` check (core/util/plugin_name.hpp): ASCII letters, digits and '_',
# starting with a letter, at most 64 characters. The name becomes a file name,
# a CMake target, the model's name in manifests and a C++ class name.
# Script mode can call it too: cmake -D name=NAME -P <this file>.
function(fibrodem_check_plugin_name name)
  string(LENGTH "${name}" length)
  if(NOT name MATCHES "^[A-Za-z][A-Za-z0-9_]*$" OR length GREATER 64)
    message(FATAL_ERROR "fibrodem plugin name '${name}': expected ASCII letters, digits and '_', "
                        "starting with a letter, at most 64 characters")
  endif()
endfunction()
if(CMAKE_SCRIPT_MODE_FILE STREQUAL CMAKE_CURRENT_LIST_FILE)
  fibrodem_check_plugin_name("${name}")
  return()
endif()

# A plugin project configured on its own (the top-level project, as the
# skeletons of `fibrodem new-model` and `fibrodem import-cellml`) without a
# build type is built as Release, as fibrodem itself is: a build without a
# type has no optimisation flags at all. -DCMAKE_BUILD_TYPE=Debug,
# RelWithDebInfo or None (no flags: the compiler's defaults) choose another.
get_property(_fibrodem_multi_config GLOBAL PROPERTY GENERATOR_IS_MULTI_CONFIG)
if(NOT CMAKE_BUILD_TYPE AND NOT _fibrodem_multi_config AND CMAKE_SOURCE_DIR STREQUAL PROJECT_SOURCE_DIR)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type (default Release)" FORCE)
  message(STATUS "fibrodem plugin: no CMAKE_BUILD_TYPE given, building Release")
endif()
unset(_fibrodem_multi_config)

function(fibrodem_add_cell_model name)
  _fibrodem_add_plugin(fibrodem_${name} ${name} ${ARGN})
endfunction()

function(fibrodem_add_contact_law name)
  _fibrodem_add_plugin(fibrodem_contact_law_${name} ${name} ${ARGN})
endfunction()

function(_fibrodem_add_plugin target name)
  fibrodem_check_plugin_name("${name}")
  if(NOT ARGN)
    message(FATAL_ERROR "fibrodem plugin '${name}': no source files given")
  endif()
  if(NOT TARGET fibrodem::plugin_sdk)
    message(FATAL_ERROR "fibrodem plugin '${name}': the target fibrodem::plugin_sdk is missing; "
                        "call find_package(fibrodem REQUIRED) first")
  endif()
  set(output_dir ${CMAKE_BINARY_DIR})
  if(DEFINED FIBRODEM_PLUGIN_OUTPUT_DIR)
    set(output_dir ${FIBRODEM_PLUGIN_OUTPUT_DIR})
  endif()
  set(install_dir lib/fibrodem/plugins)
  if(DEFINED FIBRODEM_PLUGIN_INSTALL_DIR)
    set(install_dir ${FIBRODEM_PLUGIN_INSTALL_DIR})
  endif()

  add_library(${target} MODULE ${ARGN})
  target_link_libraries(${target} PRIVATE fibrodem::plugin_sdk)
  set_target_properties(${target} PROPERTIES
    PREFIX "lib"
    OUTPUT_NAME ${target}
    SUFFIX ".so"
    LIBRARY_OUTPUT_DIRECTORY ${output_dir}
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  if(NOT FIBRODEM_PLUGIN_NO_INSTALL)
    install(TARGETS ${target} LIBRARY DESTINATION ${install_dir})
  endif()
  set_property(GLOBAL APPEND PROPERTY FIBRODEM_PLUGIN_TARGETS ${target})
endfunction()
