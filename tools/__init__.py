"""tetcontact's Python tools, one package:

    tools/post/    pictures and plots of a run (section_png, sequence_png, plot_sweep,
                   plot_limit, ball_plate_report) and the VTK reader check (check_vtu)
    tools/docs/    the tables of README.md and docs/ regenerated from runs (tables)
    tools/dev/     developer aids: frames at scale, random CCD queries, run comparisons,
                   sample Gmsh meshes
    tools/common/  what the tools share: the summary.json / history.csv key names
                   (summary_keys), Christiansen's Whipple shield equations (christiansen), what
                   a figure draws as numbers for the tests (figure_data), and a missing
                   third-party module said with its Debian package (on import)

Every script runs by path (`/usr/bin/python3 tools/post/check_vtu.py ...`) and as a module from
the repository root (`python3 -m tools.post.check_vtu ...`). A script run by path finds the
package the one way they all share, in its first lines:

    if not __package__:  # run by path: the repository root on sys.path, for `tools.*`
        sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

Their tests: tests/tools/test_<tool>.py (pytest), `ctest -L tools`."""
