# svo_render under mpirun (issue 22): the path tracer's image on 2 and 3
# ranks equals one process's, byte for byte (GPU and --cpu); a failing rank
# ends the job with no output. Skipped (77) without mpirun.
if(TARGET svo_render AND TARGET vx_tool_mpi_device)
  set(VX_MPIEXEC_R "${MPIEXEC_EXECUTABLE}")
  if(NOT VX_MPIEXEC_R)
    set(VX_MPIEXEC_R mpirun)
  endif()
  add_test(NAME test_svo_render_mpi COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_svo_render_mpi.sh
                                            ${CMAKE_BINARY_DIR}/bin ${VX_MPIEXEC_R})
  set_tests_properties(test_svo_render_mpi PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77 LABELS tools
                       ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
  # under the sanitizers the uneven split alone (3 ranks; the release run: 2 and 3): each rank is a whole tool
  # process, lavapipe's time (tests/CMakeLists.txt vx_sanitize_trim)
  vx_sanitize_trim(test_svo_render_mpi ENV VX_MPI_RANKS=3)
endif()
vx_test_cost(test_svo_render_mpi 50)
