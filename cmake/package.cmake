# The .deb (issue 19): `cpack -G DEB` in the build folder (or `cmake --build
# build --target package`) packs what `cmake --install` installs, under the
# prefix /usr: libvoxkit, headers, CMake package, pkg-config file, tools and
# the Python module (lib/python3/dist-packages for /usr, python/CMakeLists.txt).
# Depends are computed from the binaries by dpkg-shlibdeps (dpkg-dev); the
# Python module adds python3-numpy. tests/package/ builds it and checks it.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME voxkit)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "voxel scenes: sparse voxel octrees (.svo), converters from .vox, glTF and OpenVDB, a Vulkan tracer")
set(CPACK_PACKAGE_CONTACT "voxkit developers <voxkit@localhost>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(TARGET voxkit_python)
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3-numpy")
endif()
set(CPACK_PACKAGE_DIRECTORY ${CMAKE_BINARY_DIR}/package)
include(CPack)
