#!/usr/bin/python3
"""Writes data/meshes/two-blocks-v22.msh and two-blocks-v41.msh: the same small mesh in Gmsh's
ASCII formats 2.2 and 4.1. Two unit cubes side by side along x ([0,1]^3 'left' and
[1,2]x[0,1]^2 'right'), each split into 6 tetrahedra, as two physical volumes sharing the
nodes of their common face. Node tags are not contiguous (10, 20, ...), and boundary
triangles and corner points are included so that a reader must skip them.

    tools/dev/make_sample_msh.py [OUTDIR]   (default: data/meshes, the files the tests read)"""
import itertools
import os
import sys

MESHES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data", "meshes")


def main(out):
    """Writes the two files into the folder `out`."""
    nodes = {}  # (i,j,k) -> tag
    for k, j, i in itertools.product(range(2), range(2), range(3)):
        nodes[(i, j, k)] = 10 * (len(nodes) + 1)

    position = {tag: key for key, tag in nodes.items()}

    def kuhn(i0):
        tets = []
        for p in itertools.permutations(range(3)):
            o = [0, 0, 0]
            t = [nodes[(i0, 0, 0)]]
            for ax in p:
                o[ax] = 1
                t.append(nodes[(i0 + o[0], o[1], o[2])])
            # Positive orientation, as Gmsh writes it: det[x1-x0, x2-x0, x3-x0] > 0.
            a, b, c, d = (position[n] for n in t)
            u, v, w = ([q[i] - a[i] for i in range(3)] for q in (b, c, d))
            det = (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                   + u[2] * (v[0] * w[1] - v[1] * w[0]))
            tets.append(t if det > 0 else [t[0], t[1], t[3], t[2]])
        return tets

    blocks = {1: kuhn(0), 2: kuhn(1)}
    # Two triangles on the face x = 0 and two corner points (to be skipped).
    tris = [[nodes[(0, 0, 0)], nodes[(0, 1, 0)], nodes[(0, 1, 1)]],
            [nodes[(0, 0, 0)], nodes[(0, 1, 1)], nodes[(0, 0, 1)]]]
    points = [nodes[(0, 0, 0)], nodes[(2, 1, 1)]]
    names = {1: "left", 2: "right"}

    def coords(tag):
        (i, j, k), = [key for key, t in nodes.items() if t == tag]
        return f"{i} {j} {k}"

    with open(os.path.join(out, "two-blocks-v22.msh"), "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n")
        f.write("$PhysicalNames\n3\n2 5 \"inlet face\"\n3 1 \"left\"\n3 2 \"right\"\n$EndPhysicalNames\n")
        f.write(f"$Nodes\n{len(nodes)}\n")
        for tag in sorted(nodes.values()):
            f.write(f"{tag} {coords(tag)}\n")
        f.write("$EndNodes\n")
        elems = [(15, [0, 1], [p]) for p in points] + [(2, [5, 3], t) for t in tris]
        for phys, tets in blocks.items():
            elems += [(4, [phys, phys], t) for t in tets]
        f.write(f"$Elements\n{len(elems)}\n")
        for n, (typ, tags, conn) in enumerate(elems, 1):
            f.write(f"{n} {typ} {len(tags)} {' '.join(map(str, tags))} {' '.join(map(str, conn))}\n")
        f.write("$EndElements\n")

    with open(os.path.join(out, "two-blocks-v41.msh"), "w") as f:
        f.write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
        f.write("$PhysicalNames\n3\n2 5 \"inlet face\"\n3 1 \"left\"\n3 2 \"right\"\n$EndPhysicalNames\n")
        # Entities: 2 points, 0 curves, 1 surface, 2 volumes.
        f.write("$Entities\n2 0 1 2\n")
        f.write("1 0 0 0 0\n2 2 1 1 0\n")
        f.write("1 0 0 0 0 1 1 1 5 0\n")
        f.write("1 0 0 0 1 1 1 1 1 0\n2 1 0 0 2 1 1 1 2 0\n")
        f.write("$EndEntities\n")
        tags = sorted(nodes.values())
        f.write(f"$Nodes\n1 {len(tags)} {tags[0]} {tags[-1]}\n3 1 0 {len(tags)}\n")
        f.write("".join(f"{t}\n" for t in tags))
        f.write("".join(f"{coords(t)}\n" for t in tags))
        f.write("$EndNodes\n")
        nel = len(points) + len(tris) + sum(len(t) for t in blocks.values())
        f.write(f"$Elements\n5 {nel} 1 {nel}\n")
        n = 1
        for ent, p in enumerate(points, 1):
            f.write(f"0 {ent} 15 1\n{n} {p}\n"); n += 1
        f.write(f"2 1 2 {len(tris)}\n")
        for t in tris:
            f.write(f"{n} {' '.join(map(str, t))}\n"); n += 1
        for vol, tets in blocks.items():
            f.write(f"3 {vol} 4 {len(tets)}\n")
            for t in tets:
                f.write(f"{n} {' '.join(map(str, t))}\n"); n += 1
        f.write("$EndElements\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else MESHES)
