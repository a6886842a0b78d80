# One library layer (sparse, ordering, factor, solver, physics): target ldlpgs_<layer>, alias and
# export name ldlpgs::<layer>.
#
# Include paths: consumers write <ldlpgs/<layer>/<header>.h>, from the install prefix and from the
# build tree alike. The layers stay top-level folders (design card), so the build tree holds
# ${LDLPGS_INCLUDE_DIR}/ldlpgs/<layer> as a symbolic link to the source folder, and that staged
# tree (not the source root) is the targets' include directory: apps/, bench/ and tests/ are not
# reachable through it. The install copies only the layers' headers (cmake/ldlpgs_install.cmake).
set(LDLPGS_INCLUDE_DIR ${PROJECT_BINARY_DIR}/include)

function(ldlpgs_library layer)
  file(MAKE_DIRECTORY ${LDLPGS_INCLUDE_DIR}/ldlpgs)
  if(NOT EXISTS ${LDLPGS_INCLUDE_DIR}/ldlpgs/${layer})
    file(CREATE_LINK ${PROJECT_SOURCE_DIR}/${layer} ${LDLPGS_INCLUDE_DIR}/ldlpgs/${layer} SYMBOLIC)
  endif()
  set(target ldlpgs_${layer})
  add_library(${target} ${ARGN})
  add_library(ldlpgs::${layer} ALIAS ${target})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${LDLPGS_INCLUDE_DIR}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(${target} PUBLIC cxx_std_20)
  # PIC: the Python module (python/) links these static libraries into a shared object.
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${layer} POSITION_INDEPENDENT_CODE ON)
  # Unity sources of up to 8 files (CMake's batch): a layer's files parse and instantiate the same
  # Eigen, SuiteSparse and nlohmann-json headers, once per batch instead of once per file
  # (DEVELOPERS.md, "Where CI's time goes"). factor/ opts out (factor/CMakeLists.txt).
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON)
  if(NOT PROJECT_IS_TOP_LEVEL)
    # A consumer's warnings (-Wconversion, ...) are about its code, not our headers: -isystem.
    # (Imported targets of the installed package are SYSTEM already.)
    set_target_properties(${target} PROPERTIES SYSTEM ON)
  endif()
  set_property(GLOBAL APPEND PROPERTY LDLPGS_LAYERS ${layer})
endfunction()
