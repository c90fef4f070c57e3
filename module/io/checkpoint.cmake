# Sources of the parallel HDF5 checkpoint (write, read, verify, file names), kept apart from the
# scene reader's and the output writers' lists; module/io/CMakeLists.txt merges them.
set(POLYDEM_IO_CHECKPOINT_SOURCES checkpoint_checksum.cpp checkpoint_digest.cpp checkpoint_files.cpp checkpoint_read.cpp
                                  checkpoint_summary.cpp checkpoint_write.cpp checkpoint_writer.cpp
                                  hdf5_dataset.cpp
                                  hdf5_file.cpp)
