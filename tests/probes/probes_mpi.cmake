# svo_bake under mpirun (issue 22): 1, 2 and 3 ranks give the single bake's
# bytes; a killed or failing rank ends the job with no output; resumes.
# Registered where svo_bake is built with MPI; skipped (77) without mpirun.
if(TARGET svo_bake AND VX_WITH_MPI AND MPI_C_FOUND)
  set(VX_MPIEXEC "${MPIEXEC_EXECUTABLE}")
  if(NOT VX_MPIEXEC)
    set(VX_MPIEXEC mpirun)
  endif()
  add_test(NAME test_svo_bake_mpi COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/test_svo_bake_mpi.sh ${CMAKE_BINARY_DIR}/bin
                                          ${VX_MPIEXEC})
  # OpenMPI's own allocations are not freed at exit (not ours to suppress)
  set_tests_properties(test_svo_bake_mpi PROPERTIES TIMEOUT 300 SKIP_RETURN_CODE 77 LABELS probes
                       ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
  # under the sanitizers the uneven split alone (3 ranks; the release run: 2 and 3): each rank is a whole tool
  # process, lavapipe's time (tests/CMakeLists.txt vx_sanitize_trim)
  vx_sanitize_trim(test_svo_bake_mpi ENV VX_MPI_RANKS=3)
endif()
