# The plugin SDK: the headers a plugin may include, as the target
# fibrodem::plugin_sdk, and what `cmake --install` ships for out-of-tree
# plugins (headers, the CMake package `fibrodem`, a pkg-config file).
#
# In the tree the plugins compile against a copy of exactly these headers
# (build/sdk/include), not against core/: a plugin that includes anything else
# of the core fails here, as it would out of tree.
include(CMakePackageConfigHelpers)

# Header-only and self-contained: the C++ standard library and xsimd only.
set(FIBRODEM_SDK_HEADERS
  model/cell_model.hpp
  model/block_access.hpp
  model/simd.hpp
  cellml/cellml_math.hpp
  mechanics/contact_law_plugin.hpp)
set(FIBRODEM_SDK_STAGE ${CMAKE_BINARY_DIR}/sdk/include)
foreach(header IN LISTS FIBRODEM_SDK_HEADERS)
  configure_file(${PROJECT_SOURCE_DIR}/sdk/${header} ${FIBRODEM_SDK_STAGE}/${header} COPYONLY)
endforeach()

add_library(fibrodem_plugin_sdk INTERFACE)
add_library(fibrodem::plugin_sdk ALIAS fibrodem_plugin_sdk)
target_include_directories(fibrodem_plugin_sdk INTERFACE ${FIBRODEM_SDK_STAGE})
target_compile_features(fibrodem_plugin_sdk INTERFACE cxx_std_20)
target_link_libraries(fibrodem_plugin_sdk INTERFACE fibrodem_xsimd)

# The ABI numbers, for the CMake package and the pkg-config file.
file(STRINGS ${PROJECT_SOURCE_DIR}/sdk/model/cell_model.hpp abi REGEX "kPluginAbiVersion = [0-9]+")
string(REGEX MATCH "[0-9]+" FIBRODEM_PLUGIN_ABI_VERSION "${abi}")
file(STRINGS ${PROJECT_SOURCE_DIR}/sdk/mechanics/contact_law_plugin.hpp abi REGEX "kContactLawAbiVersion = [0-9]+")
string(REGEX MATCH "[0-9]+" FIBRODEM_CONTACT_LAW_ABI_VERSION "${abi}")

# ---- install: headers, xsimd, CMake package, pkg-config ---------------------
set(FIBRODEM_SDK_INCLUDE_DIR include/fibrodem)
set(FIBRODEM_CMAKE_DIR lib/cmake/fibrodem)
foreach(header IN LISTS FIBRODEM_SDK_HEADERS)
  get_filename_component(subdir ${header} DIRECTORY)
  install(FILES sdk/${header} DESTINATION ${FIBRODEM_SDK_INCLUDE_DIR}/${subdir})
endforeach()
# xsimd is header-only (Debian's libxsimd-dev): the install carries a copy of
# the headers fibrodem was built with, and its licence, so that a plugin needs
# only a compiler and CMake.
option(FIBRODEM_SDK_BUNDLE_XSIMD "Install xsimd's headers with the plugin SDK" ON)
if(FIBRODEM_SDK_BUNDLE_XSIMD)
  install(DIRECTORY ${XSIMD_INCLUDE_DIR}/xsimd DESTINATION ${FIBRODEM_SDK_INCLUDE_DIR})
  foreach(licence /usr/share/doc/libxsimd-dev/copyright ${XSIMD_INCLUDE_DIR}/../share/doc/xsimd/LICENSE)
    if(EXISTS ${licence})
      install(FILES ${licence} DESTINATION ${FIBRODEM_SDK_INCLUDE_DIR}/xsimd RENAME LICENSE.xsimd)
      break()
    endif()
  endforeach()
endif()

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/fibrodemConfig.cmake.in
  ${CMAKE_BINARY_DIR}/sdk/fibrodemConfig.cmake
  INSTALL_DESTINATION ${FIBRODEM_CMAKE_DIR}
  PATH_VARS FIBRODEM_SDK_INCLUDE_DIR)
# Minor versions may change the plugin ABI while the major is 0 (the loader
# checks the ABI number at run time anyway).
write_basic_package_version_file(${CMAKE_BINARY_DIR}/sdk/fibrodemConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/sdk/fibrodemConfig.cmake
              ${CMAKE_BINARY_DIR}/sdk/fibrodemConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FibrodemPlugin.cmake
        DESTINATION ${FIBRODEM_CMAKE_DIR})
configure_file(${PROJECT_SOURCE_DIR}/cmake/fibrodem.pc.in ${CMAKE_BINARY_DIR}/sdk/fibrodem.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/sdk/fibrodem.pc DESTINATION lib/pkgconfig)
