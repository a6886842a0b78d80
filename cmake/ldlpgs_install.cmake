# cmake --install: the five libraries, their headers (only those), version.h, and the package
# config that lets a consumer do find_package(ldlpgs 0.2 REQUIRED) and link ldlpgs::ldlpgs or one
# layer; plus the program and the Python module where they are built.
include(CMakePackageConfigHelpers)
set(LDLPGS_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/ldlpgs)
get_property(layers GLOBAL PROPERTY LDLPGS_LAYERS)
set(targets ldlpgs_all)
foreach(layer IN LISTS layers)
  list(APPEND targets ldlpgs_${layer})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${layer}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/ldlpgs/${layer}
          FILES_MATCHING PATTERN "*.h" PATTERN "scenes" EXCLUDE)
endforeach()
install(FILES ${LDLPGS_INCLUDE_DIR}/ldlpgs/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/ldlpgs)
install(TARGETS ${targets} EXPORT ldlpgsTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT ldlpgsTargets NAMESPACE ldlpgs:: DESTINATION ${LDLPGS_CMAKE_DIR})
configure_package_config_file(cmake/ldlpgsConfig.cmake.in ${PROJECT_BINARY_DIR}/ldlpgsConfig.cmake
                              INSTALL_DESTINATION ${LDLPGS_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/ldlpgsConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)  # 0.x: minor versions may break the API
install(FILES ${PROJECT_BINARY_DIR}/ldlpgsConfig.cmake ${PROJECT_BINARY_DIR}/ldlpgsConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindSuiteSparse.cmake ${PROJECT_SOURCE_DIR}/cmake/FindMETIS.cmake
        DESTINATION ${LDLPGS_CMAKE_DIR})
if(TARGET ldlpgs)
  install(TARGETS ldlpgs RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  # What `ldlpgs report` runs and reads, found beside the installed program
  # (apps/report_command.cpp, report_files): its scripts, the default test matrices and the MJCF
  # models of its last stage (Gymnasium's, with their licence).
  install(FILES ${PROJECT_SOURCE_DIR}/papers/scripts/talk_figures.py ${PROJECT_SOURCE_DIR}/papers/scripts/plot_spy.py
                ${PROJECT_SOURCE_DIR}/papers/scripts/run_ldlpgs.py ${PROJECT_SOURCE_DIR}/papers/scripts/debian_python.py
                ${PROJECT_SOURCE_DIR}/papers/scripts/plot_speed_vs_error.py ${PROJECT_SOURCE_DIR}/papers/scripts/render_html.py
          DESTINATION ${CMAKE_INSTALL_DATADIR}/ldlpgs/scripts)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/tests/data/matrices/ DESTINATION ${CMAKE_INSTALL_DATADIR}/ldlpgs/matrices
          FILES_MATCHING PATTERN "*.mtx")
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/tests/data/mjcf/gymnasium/ DESTINATION ${CMAKE_INSTALL_DATADIR}/ldlpgs/mjcf/gymnasium)
endif()
