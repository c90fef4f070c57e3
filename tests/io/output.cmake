# Tests of the output writers (snapshots, series.csv, summary.json), kept apart from the scene
# reader's tests so that both lists grow independently; tests/io/CMakeLists.txt includes this.
polydem_add_test(NAME io_output_file SOURCES output_file_test.cpp DEPENDS polydem::io
                 PROCESSES 1 2)
polydem_add_test(NAME io_vtk_writer SOURCES vtk_writer_test.cpp DEPENDS polydem::io
                 PROCESSES 1 2)
polydem_add_test(NAME io_series_writer SOURCES series_writer_test.cpp DEPENDS polydem::io
                 PROCESSES 1 2)
polydem_add_test(NAME io_summary_json SOURCES summary_json_test.cpp DEPENDS polydem::io)

# Independent checks with Debian's /usr/bin/python3 (not the python3 on PATH): the snapshot files
# of a 2-rank run parsed with Python's XML and base64 modules, and the plot script on a sample run.
if(EXISTS /usr/bin/python3)
  set(sample ${CMAKE_CURRENT_BINARY_DIR}/vtk_sample)
  add_test(NAME io_vtk_sample
           COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 --oversubscribe
                   $<TARGET_FILE:test_io_vtk_writer> --gtest_filter=VtkSample.*)
  set_tests_properties(io_vtk_sample PROPERTIES
                       ENVIRONMENT "POLYDEM_VTK_SAMPLE_DIR=${sample};${POLYDEM_MPI_TEST_ENV}"
                       FIXTURES_SETUP io_vtk_sample PROCESSORS 2)
  add_test(NAME io_vtk_files_python
           COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/check_vtk_files.py ${sample})
  set_tests_properties(io_vtk_files_python PROPERTIES FIXTURES_REQUIRED io_vtk_sample)

  execute_process(COMMAND /usr/bin/python3 -c "import matplotlib, numpy"
                  RESULT_VARIABLE polydem_no_matplotlib OUTPUT_QUIET ERROR_QUIET)
  if(polydem_no_matplotlib EQUAL 0)
    add_test(NAME io_plot_series
             COMMAND /usr/bin/python3 ${CMAKE_CURRENT_SOURCE_DIR}/plot_series_test.py
                     ${PROJECT_SOURCE_DIR}/python_coupling/plots/plot_series.py
                     ${CMAKE_CURRENT_BINARY_DIR}/plot_sample)
  else()
    message(STATUS "io_plot_series not registered: /usr/bin/python3 lacks matplotlib or numpy")
  endif()
endif()
