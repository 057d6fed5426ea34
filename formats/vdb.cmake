# OpenVDB reader (C shim over Debian's libopenvdb). Imath and TBB are named
# explicitly: libopenvdb's public headers use them but the .so does not
# re-export them to our link line.
if(VX_WITH_OPENVDB)
  find_path(VX_OPENVDB_INCLUDE openvdb/openvdb.h)
  find_library(VX_OPENVDB_LIB openvdb)
  find_library(VX_TBB_LIB tbb)
  find_library(VX_IMATH_LIB NAMES Imath Imath-3_1)
  # blosc and zlib: the shim carries corrected chunk readers (see vdb_openvdb.cpp)
  find_library(VX_BLOSC_LIB blosc)
  find_path(VX_BLOSC_INCLUDE blosc.h)
  find_package(ZLIB)
  if(VX_OPENVDB_INCLUDE AND VX_OPENVDB_LIB AND VX_TBB_LIB AND VX_IMATH_LIB AND VX_BLOSC_LIB AND VX_BLOSC_INCLUDE
     AND ZLIB_FOUND)
    add_library(vx_vdb STATIC ${CMAKE_CURRENT_LIST_DIR}/vdb_openvdb.cpp ${CMAKE_CURRENT_LIST_DIR}/vdb_scan.c)
    target_include_directories(vx_vdb SYSTEM PRIVATE ${VX_OPENVDB_INCLUDE})
    target_include_directories(vx_vdb SYSTEM PRIVATE ${VX_BLOSC_INCLUDE})
    target_link_libraries(vx_vdb PUBLIC vx_core ${VX_OPENVDB_LIB} ${VX_TBB_LIB} ${VX_IMATH_LIB} ${VX_BLOSC_LIB}
                          ZLIB::ZLIB)
    # OpenVDB's headers read file bytes straight into bool members (a root
    # tile's active flag in RootNode::readTopology, instantiated here): a
    # garbled byte is an invalid bool load inside OpenVDB, where the sanitizer
    # build would stop (a fuzzing input in tests/fuzz/regress/vdb/ has one)
    if(VX_SANITIZE)
      target_compile_options(vx_vdb PRIVATE -fno-sanitize=bool)
    endif()
  else()
    message(STATUS "OpenVDB not found: .vdb input disabled")
  endif()
endif()
