# Unity builds — CI time (docs/reliability.md "CI time").
# With GCC 12 a file here spends seconds parsing the same third-party
# headers (GoogleTest 2.5 s, Eigen 2 s, gRPC with our services 3.8 s, the
# standard containers 1.5 s) and instantiating the same templates; a
# target built in batches of 8 files pays that once per batch. Measured on
# the test executables: 410 s of compiler time down to 163 s.
# (Precompiled headers were measured first and lost: GCC's 100-300 MB .gch
# files cost more to load than the parse they save.)
#
# A batch is one translation unit, so two files of a target must not both
# define the same name in an anonymous namespace: give file-local helpers
# names that say whose they are (MakeCuttingTable, not MakeTable), and put a
# constant several files need in a header they share (kMaxToolSpeed_m_per_s).
# HAPSIM_UNITY_BUILD=OFF builds file by file — the way to find a file that
# compiles only because an earlier file of its batch included something.
option(HAPSIM_UNITY_BUILD "Compile each library and test executable in batches of 8 files" ON)

function(hapsim_unity target)
  if(HAPSIM_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  endif()
endfunction()
