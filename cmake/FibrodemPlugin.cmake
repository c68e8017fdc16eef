# fibrodem_add_cell_model(NAME source...)
# Builds a cell-model plugin as a shared module named libfibrodem_<NAME>.so in the
# plugin directory. A plugin sees the header-only plugin contract of the core
# (core/model/cell_model.hpp, block_access.hpp, simd.hpp; xsimd is header-only)
# and links nothing of the core.
function(fibrodem_add_cell_model name)
  set(target fibrodem_${name})
  add_library(${target} MODULE ${ARGN})
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/core)
  target_link_libraries(${target} PRIVATE fibrodem_xsimd)
  set_target_properties(${target} PROPERTIES
    LIBRARY_OUTPUT_DIRECTORY ${FIBRODEM_PLUGIN_OUTPUT_DIR}
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON)
  install(TARGETS ${target} LIBRARY DESTINATION ${FIBRODEM_PLUGIN_INSTALL_DIR})
  set_property(GLOBAL APPEND PROPERTY FIBRODEM_PLUGIN_TARGETS ${target})
endfunction()
