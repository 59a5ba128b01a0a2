#!/usr/bin/python3
"""Random CCD queries in the ccd file format (no ground truth), for `tetcontact ccd FILE
--confirm cgal`: the CGAL oracle against our exact path.

    tools/dev/random_ccd_queries.py N OUT [--seed S]

Alternating vf and ee. Half are generic (four points in [-1, 1]^3, each moving by up to 1 per
coordinate); half lie on the integer grid {-2, ..., 2}^3 at both ends of the step, where
coplanar, touching and parallel configurations are common.
"""
import argparse
import random


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("n", type=int)
    ap.add_argument("out")
    ap.add_argument("--seed", type=int, default=15)
    a = ap.parse_args()
    rng = random.Random(a.seed)
    with open(a.out, "w") as out:
        for i in range(a.n):
            kind = "ee" if i % 2 else "vf"
            if i % 4 < 2:
                start = [[rng.uniform(-1, 1) for _ in range(3)] for _ in range(4)]
                pts = start + [[c + rng.uniform(-1, 1) for c in p] for p in start]
            else:
                pts = [[float(rng.randint(-2, 2)) for _ in range(3)] for _ in range(8)]
            out.write(kind + " " + " ".join(repr(c) for p in pts for c in p) + "\n")


if __name__ == "__main__":
    main()
