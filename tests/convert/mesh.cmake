# Mesh voxelizer tests (brute-force reference) and the glTF reader fuzz target.
if(TARGET vx_conv_mesh_core)
  vx_add_test(mesh_test SOURCES ${CMAKE_CURRENT_LIST_DIR}/mesh_test.c LIBS vx_conv_mesh_core m)
endif()
if(TARGET vx_conv_mesh)
  vx_add_test(mesh_scene_test SOURCES ${CMAKE_CURRENT_LIST_DIR}/mesh_scene_test.c LIBS vx_conv_mesh m)
endif()
if(TARGET vx_conv_mesh_core)
  set(VX_GLTF_SEEDS "")
  foreach(f aleph_Box.glb tinygltf_box01.glb rtxgi_furnace.glb rtxgi_cornell.glb rtxgi_two-rooms.glb
            tinygltf_CubeImageUriSpaces/CubeImageUriSpaces.gltf)
    list(APPEND VX_GLTF_SEEDS ${VX_CORPUS_DIR}/gltf/${f})
  endforeach()
  vx_add_fuzz(gltf_fuzz ${CMAKE_SOURCE_DIR}/tests/fuzz/gltf_fuzz.c LIBS vx_conv_mesh ARGS -n 300
              SEEDS ${VX_GLTF_SEEDS})
endif()
if(TARGET vx_conv_mesh_gpu)
  vx_add_test(mesh_gpu_test SOURCES ${CMAKE_CURRENT_LIST_DIR}/mesh_gpu_test.c LIBS vx_conv_mesh_gpu ${CMAKE_DL_LIBS} m)
  # the corpus meshes at three resolutions are 250 s of lavapipe's float64 emulation in Release; under the
  # sanitizers the generated meshes (random, collisions, solid) run the same host code, and
  # mesh_test reads the corpus meshes on the CPU path (tests/CMakeLists.txt vx_sanitize_trim)
  # and the lattice's exactness sweep (22 s under ASan, stop 60): the GPU build's host code runs in the solid,
  # random and collision tests
  vx_sanitize_trim(mesh_gpu_test SKIP test_corpus test_lattice)
  vx_test_cost(mesh_gpu_test 358)
endif()
