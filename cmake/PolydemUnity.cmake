# Files that a unity build (POLYDEM_UNITY, cmake/PolydemHelpers.cmake) compiles on their own: each
# defines a file-local helper (anonymous namespace or static) under the same name as another file
# of its target, which two files of one batch cannot both do. One list per target, named
# POLYDEM_UNITY_ALONE_<module> (the polydem program: POLYDEM_UNITY_ALONE_polydem), with paths
# relative to the target's folder.
# A file that is renamed or removed here only stops being listed; one that is not listed joins
# the batches.
set(POLYDEM_UNITY_ALONE_contact
    # Scratch, scratch() (fcp/fcp_search.cpp): each kernel's own thread-local work space
    fcp/fcp_point.cpp point/ipm.cpp potential/distance_potential.cpp potential/fdem.cpp
    potential/lp.cpp # also separatedAlong (sat/sat.cpp)
    face/face_contact_box.cpp # kCosFacing (face/face_contact.cpp)
)
set(POLYDEM_UNITY_ALONE_geometry
    qhull_facets.cpp # F (mass_properties.cpp)
    point_cloud_checks.cpp # checkCount (joint_planes.cpp)
)
set(POLYDEM_UNITY_ALONE_output
    vtk_writer.cpp # formatTime (xdmf_writer.cpp), perContact, perFace (snapshot_h5.cpp)
)
set(POLYDEM_UNITY_ALONE_run
    fos_mechanism.cpp # receivedSignal (fos.cpp), gatherPoses, PoseRow (runout_deposit.cpp)
    realizations.cpp # receivedSignal, pack, unpack (fos.cpp)
    runout.cpp # receivedSignal (fos.cpp)
    tracker.cpp # unpack (fos.cpp)
    motion_checks.cpp # kNaN (checks.cpp)
)
set(POLYDEM_UNITY_ALONE_scene
    scene_checks.cpp # direction (check_kinds.cpp), rangeText, readParameter (scene_joints.cpp),
                     # show (toml_values.cpp)
    scene_water.cpp # readTable (scene_ground_record.cpp)
)
set(POLYDEM_UNITY_ALONE_polydem
    bench_kernels.cpp # Measurement (bench_scaling.cpp), printTable (bench_lammps.cpp),
                      # threadSeconds (bench_pile.cpp)
    bench_contact_model.cpp # median (bench_checkpoint.cpp)
    cmd_fos.cpp # programPath (cmd_run.cpp), usage (main.cpp)
    cmd_runout.cpp # programPath (cmd_run.cpp), usage (main.cpp)
    fos_realizations.cpp # usage (main.cpp)
    contact_type_report.cpp # randomRotation (bench_pairs.cpp), resolve (cmd_contact.cpp)
)
