# Tests of the parallel HDF5 checkpoint, kept apart from the other io tests' lists;
# tests/io/CMakeLists.txt includes this.
polydem_add_test(NAME io_checkpoint SOURCES checkpoint_test.cpp checkpoint_checksum_test.cpp
                 DEPENDS polydem::io PROCESSES 1 2 4)
polydem_add_test(NAME io_checkpoint_errors
                 SOURCES checkpoint_errors_test.cpp checkpoint_write_test.cpp
                 DEPENDS polydem::io PROCESSES 1 2 4)
