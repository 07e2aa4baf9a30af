# The Debian package of what `cmake --install` installs (CPack's DEB
# generator; no debhelper needed): `cpack --config build/CPackConfig.cmake`
# or deploy/make-deb.sh. Its dependencies are the Debian packages the
# programs link against (found by dpkg-shlibdeps when it is installed).
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME hapsim)
set(CPACK_PACKAGE_VENDOR "hapsim")
set(CPACK_PACKAGE_CONTACT "hapsim developers <hapsim@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "networked haptic soft-tissue simulator for surgical training")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The Eigen headers hapsim::core's headers include, for find_package(hapsim).
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libeigen3-dev (>= 3.4)")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "systemd")
# dpkg keeps an admin's edits of these over upgrades.
set(CPACK_DEBIAN_PACKAGE_CONFFILES "/etc/hapsim/server.env;/etc/hapsim/bridge.env")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${PROJECT_SOURCE_DIR}/deploy/debian/conffiles
                                       ${PROJECT_SOURCE_DIR}/deploy/debian/postinst
                                       ${PROJECT_SOURCE_DIR}/deploy/debian/prerm
                                       ${PROJECT_SOURCE_DIR}/deploy/debian/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
