# Tests of the parallel HDF5 checkpoint, kept apart from the other io tests' lists;
# tests/io/CMakeLists.txt includes this.
polydem_add_test(NAME io_checkpoint SOURCES checkpoint_test.cpp checkpoint_checksum_test.cpp
                 DEPENDS polydem::io PROCESSES 1 2 4)
polydem_add_test(NAME io_checkpoint_errors
                 SOURCES checkpoint_errors_test.cpp checkpoint_edit_test.cpp checkpoint_write_test.cpp
                 DEPENDS polydem::io PROCESSES 1 2 4)

# The Python summary script (Debian's /usr/bin/python3 with h5py, not the python3 on PATH) on a
# checkpoint written by 2 ranks: same figures and checksums as the C++ reader. Skipped (exit 77)
# when h5py is missing.
if(EXISTS /usr/bin/python3)
  set(sample ${CMAKE_CURRENT_BINARY_DIR}/checkpoint_sample)
  add_test(NAME io_checkpoint_sample
           COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 --oversubscribe
                   $<TARGET_FILE:test_io_checkpoint> --gtest_filter=CheckpointSample.*)
  set_tests_properties(io_checkpoint_sample PROPERTIES
                       ENVIRONMENT "POLYDEM_CHECKPOINT_SAMPLE_DIR=${sample};${POLYDEM_MPI_TEST_ENV}"
                       FIXTURES_SETUP io_checkpoint_sample PROCESSORS 2)
  add_test(NAME io_checkpoint_python
           COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/checkpoint_summary_test.py
                   ${PROJECT_SOURCE_DIR}/python_coupling/scripts/checkpoint_summary.py ${sample})
  set_tests_properties(io_checkpoint_python PROPERTIES FIXTURES_REQUIRED io_checkpoint_sample
                                                       SKIP_RETURN_CODE 77)
endif()
