"""tools/dev/make_sample_msh.py writes exactly the two Gmsh files the mesh tests read
(data/meshes/two-blocks-v22.msh and -v41.msh), and the program reads them as two bodies."""
import filecmp
import os

from conftest import ROOT, case, run_case, run_tool


def test_writes_the_shipped_meshes(tmp_path):
    run_tool("dev/make_sample_msh.py", str(tmp_path), check=0)
    for name in ("two-blocks-v22.msh", "two-blocks-v41.msh"):
        shipped = os.path.join(ROOT, "data", "meshes", name)
        assert filecmp.cmp(str(tmp_path / name), shipped, shallow=False), name
    v22 = (tmp_path / "two-blocks-v22.msh").read_text()
    assert v22.startswith("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n")
    assert '3 1 "left"' in v22 and '3 2 "right"' in v22


def test_the_program_reads_them(binary, out):
    s = run_case(binary, case("two-blocks-msh"), out, "end_time=1e-7")
    assert s["mesh"]["tets"] == 12
    assert sorted(b["name"] for b in s["bodies"]) == ["left", "right"]
