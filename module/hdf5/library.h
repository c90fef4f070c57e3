// The HDF5 library as a whole: what a program does with it once, at its end.
#pragma once

namespace polydem::hdf5 {

/// Closes the HDF5 library before MPI_Finalize, quietly. HDF5 1.10 keeps internal objects it
/// cannot release after it has read damaged metadata, and its own shutdown at MPI_Finalize would
/// then print "HDF5: infinite loop closing library" after polydem's error message; with its
/// error printing off it says nothing. Call once, after the last HDF5 use of the process.
void closeHdf5Library();

}  // namespace polydem::hdf5
