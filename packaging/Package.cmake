# The installable package (issue 26): `cpack -G DEB` in a Release build tree writes
# laptrainer_VERSION_ARCH.deb with the binaries, the scenarios and the assets they refer to
# (under share/laptrainer, in the same relative layout, so that the binaries find them beside
# themselves: sim/setup/scenario_loader.h default_scenario_path), a desktop entry and icon, and
# the docs. packaging/test-package.sh builds, installs, runs and removes it.
include(GNUInstallDirs)

install(TARGETS laptrainer laptrainer-cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenarios DESTINATION ${CMAKE_INSTALL_DATADIR}/laptrainer
        PATTERN "README.md" EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/assets DESTINATION ${CMAKE_INSTALL_DATADIR}/laptrainer)
install(FILES ${PROJECT_SOURCE_DIR}/packaging/deb/laptrainer.desktop
        DESTINATION ${CMAKE_INSTALL_DATADIR}/applications)
install(FILES ${PROJECT_SOURCE_DIR}/packaging/deb/laptrainer.svg
        DESTINATION ${CMAKE_INSTALL_DATADIR}/icons/hicolor/scalable/apps)
set(LAP_DOC_DIR ${CMAKE_INSTALL_DATADIR}/doc/laptrainer)
install(FILES ${PROJECT_SOURCE_DIR}/packaging/deb/copyright DESTINATION ${LAP_DOC_DIR})
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${LAP_DOC_DIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${LAP_DOC_DIR}/docs
        FILES_MATCHING PATTERN "*.md")
install(FILES ${PROJECT_SOURCE_DIR}/scenarios/README.md DESTINATION ${LAP_DOC_DIR}
        RENAME scenarios.md)
# Debian wants the changelog compressed, reproducibly (no name or time in the gzip header).
set(LAP_CHANGELOG_GZ ${CMAKE_BINARY_DIR}/packaging/changelog.gz)
file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/packaging)
execute_process(COMMAND gzip -9nc ${PROJECT_SOURCE_DIR}/packaging/deb/changelog
                OUTPUT_FILE ${LAP_CHANGELOG_GZ})
install(FILES ${LAP_CHANGELOG_GZ} DESTINATION ${LAP_DOC_DIR})
foreach(page laptrainer laptrainer-cli)
  execute_process(COMMAND gzip -9nc ${PROJECT_SOURCE_DIR}/packaging/deb/${page}.1
                  OUTPUT_FILE ${CMAKE_BINARY_DIR}/packaging/${page}.1.gz)
  install(FILES ${CMAKE_BINARY_DIR}/packaging/${page}.1.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endforeach()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME laptrainer)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "laptrainer developers <laptrainer-dev@lists.laptrainer.org>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "laparoscopic cholecystectomy trainer with haptic feedback")
set(CPACK_PACKAGE_DESCRIPTION
    "laptrainer is a training simulator for catheter insertion into the cystic\n"
    "duct in laparoscopic cholecystectomy: haptic rendering for two PHANToM-class\n"
    "arms and actuated grippers, generated patients of graded difficulty,\n"
    "training metrics, and session reports for instructors.")
string(REPLACE ";" "" CPACK_DEBIAN_PACKAGE_DESCRIPTION "${CPACK_PACKAGE_DESCRIPTION}")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Qt SQL's drivers are plugins, which shlibdeps cannot see: the training-record database
# (app/store) needs SQLite's, and a programme's server PostgreSQL's.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libqt6sql6-sqlite")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libqt6sql6-psql")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "")
set(CPACK_STRIP_FILES ON)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_OUTPUT_FILE_PREFIX ${CMAKE_BINARY_DIR}/packages)
include(CPack)
