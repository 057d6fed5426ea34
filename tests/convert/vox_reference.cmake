# vox_reference: vox2svo against an independent .vox reader written from
# MagicaVoxel's format notes (vox_reference.py, standard library only): the
# corpus .vox files up to 1 MiB (VX_REF_MAX_BYTES; larger ones are named and
# left out), every .vox under $VX_EXTRA_VOX when set, and scenes it writes
# itself (all 48 rotation bytes, nested turned groups, group instances, sides of 256, hidden
# nodes and layers, keyframes, the default palette, Teardown's TDCZ chunks and
# short RGBA chunks, files both must refuse). Any python3 will do.
find_program(VX_REF_PYTHON3 NAMES python3)
if(TARGET vox2svo AND TARGET svo_info AND VX_REF_PYTHON3)
  add_test(NAME vox_reference
           COMMAND ${VX_REF_PYTHON3} ${CMAKE_CURRENT_LIST_DIR}/vox_reference.py ${CMAKE_BINARY_DIR}/bin ${VX_CORPUS_DIR}
                   ${CMAKE_CURRENT_BINARY_DIR}/vox_reference)
  set_tests_properties(vox_reference PROPERTIES TIMEOUT 300)
endif()
