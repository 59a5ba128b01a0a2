# The Python tools' tests, included from the top CMakeLists.txt (inside if(TETCONTACT_TESTS)):
# `ctest -L tools`. One pytest file per tool, tests/tools/test_<tool>.py; the program under test
# is passed as TETCONTACT_BINARY, outputs go to build/test-output/tools/.
set(TETCONTACT_TOOLS_ENV
    "TETCONTACT_BINARY=$<TARGET_FILE:tetcontact>"
    "TETCONTACT_TEST_OUTPUT=${PROJECT_BINARY_DIR}/test-output/tools"
    "PYTHONDONTWRITEBYTECODE=1")

# tetcontact_tool_test(NAME FILE): ctest NAME runs tests/tools/FILE with pytest.
function(tetcontact_tool_test name file)
  add_test(NAME ${name}
    COMMAND /usr/bin/python3 -m pytest -q -p no:cacheprovider ${PROJECT_SOURCE_DIR}/tests/tools/${file}
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  set_tests_properties(${name} PROPERTIES LABELS tools TIMEOUT 300
    ENVIRONMENT "${TETCONTACT_TOOLS_ENV}")
endfunction()

# tools/post/
tetcontact_tool_test(section_png_cubes test_section_png.py)     # exact areas, on/off overlap
tetcontact_tool_test(tools_sequence_png test_sequence_png.py)   # one extent, the debris slab
tetcontact_tool_test(plot_sweep_bars test_plot_sweep.py)        # a real sweep plotted
tetcontact_tool_test(tools_plot_limit test_plot_limit.py)
tetcontact_tool_test(tools_plot_campaign test_plot_campaign.py)
tetcontact_tool_test(tools_plot_taylor test_plot_taylor.py)
tetcontact_tool_test(tools_taylor_profiles test_taylor_profiles.py)   # exact outline of a known law
tetcontact_tool_test(tools_whipple_scores test_whipple_scores.py)   # against christiansen.py
tetcontact_tool_test(tools_ball_plate_report test_ball_plate_report.py)
tetcontact_tool_test(tools_check_vtu test_check_vtu.py)         # the arrays a run asked for
# tools/docs/
tetcontact_tool_test(tools_tables test_tables.py)               # markers, rows, a real table
# tools/dev/
tetcontact_tool_test(tools_scale_frames test_scale_frames.py)
tetcontact_tool_test(tools_random_ccd_queries test_random_ccd_queries.py)
tetcontact_tool_test(tools_compare_runs test_compare_runs.py)
tetcontact_tool_test(tools_make_sample_msh test_make_sample_msh.py)
# tools/common/
tetcontact_tool_test(tools_christiansen test_christiansen.py)   # the published equations
tetcontact_tool_test(tools_summary_keys test_summary_keys.py)   # the keys in real summaries
tetcontact_tool_test(tools_missing_modules test_missing_modules.py)   # a package named, no traceback
# All of tools/ and tests/tools/: no tracker numbers or shorthand.
tetcontact_tool_test(tools_wording test_wording.py)
# The manual's command lines: cases checked, options listed, tools' arguments.
tetcontact_tool_test(docs_commands test_docs_commands.py)

# check_vtu.py's own modes on shipped cases (as tests/parallel/test_mpi.cpp calls it): the .vtu
# series must open in a real VTK reader (the one ParaView is built on).
add_test(NAME vtk_reader_opens_output
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tools/post/check_vtu.py
          --run $<TARGET_FILE:tetcontact>
          ${PROJECT_SOURCE_DIR}/data/cases/elastic-vibration.yaml
          ${PROJECT_BINARY_DIR}/test-output/vtk-reader)
# The particle series beside it (the spall plate makes particles from 1.2 µs).
add_test(NAME vtk_reader_opens_particles
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tools/post/check_vtu.py
          --run $<TARGET_FILE:tetcontact>
          ${PROJECT_SOURCE_DIR}/data/cases/spall-plate.yaml
          ${PROJECT_BINARY_DIR}/test-output/vtk-reader-particles 2.0e-6)
# The three output formats (ascii, binary appended, zlib-compressed) read by VTK: the same
# values bit for bit, binary smaller than ascii, compressed smaller still (particles too).
add_test(NAME vtk_reader_reads_all_formats
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tools/post/check_vtu.py
          --formats $<TARGET_FILE:tetcontact>
          ${PROJECT_SOURCE_DIR}/data/cases/spall-plate.yaml
          ${PROJECT_BINARY_DIR}/test-output/vtk-formats 2.0e-6)
# The same on the elastic bar (3,840 cells): its larger arrays span several compressed blocks of
# 64 KiB (the connectivity two), which VTK's reader must join to the same values.
add_test(NAME vtk_reader_reads_compressed_blocks
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tools/post/check_vtu.py
          --formats $<TARGET_FILE:tetcontact>
          ${PROJECT_SOURCE_DIR}/data/cases/elastic-vibration.yaml
          ${PROJECT_BINARY_DIR}/test-output/vtk-blocks)
set_tests_properties(vtk_reader_opens_output vtk_reader_opens_particles
  vtk_reader_reads_all_formats vtk_reader_reads_compressed_blocks PROPERTIES LABELS tools ENVIRONMENT "PYTHONDONTWRITEBYTECODE=1")
