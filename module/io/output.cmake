# Sources of the output writers (snapshots, series.csv, summary.json), kept apart from the scene
# reader's list so that both can grow independently; module/io/CMakeLists.txt merges them.
set(POLYDEM_IO_OUTPUT_SOURCES output_file.cpp series_writer.cpp snapshot_fields.cpp snapshot_h5.cpp
                              summary_json.cpp vtk_writer.cpp xdmf_writer.cpp
                              vtk_xml.cpp)
