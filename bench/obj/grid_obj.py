#!/usr/bin/env python3
"""Writes a wavy n x n grid of vertices as an OBJ file, for timing mosaic's OBJ loader.

usage: grid_obj.py N v|vn|vtn OUT.obj
  v    positions only (the loader gives each triangle its face normal: no shared vertices)
  vn   a normal per vertex, faces v//n (one mesh vertex per position)
  vtn  a normal and a UV per vertex, faces v/t/n
The grid's (N-1)^2 quads are two triangles each: N = 1000 gives 1,996,002 triangles.
"""
import math
import sys


def main():
    if len(sys.argv) != 4 or sys.argv[2] not in ("v", "vn", "vtn"):
        sys.exit(__doc__)
    n, mode, out = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    with open(out, "w") as f:
        f.write("".join("v %.6f %.6f %.6f\n" % (i / (n - 1), j / (n - 1),
                                                 0.05 * math.sin(12 * i / (n - 1)) *
                                                 math.cos(9 * j / (n - 1)))
                        for j in range(n) for i in range(n)))
        if mode in ("vn", "vtn"):
            f.write("vn 0 0 1\n" * (n * n))
        if mode == "vtn":
            f.write("".join("vt %.5f %.5f\n" % (i / (n - 1), j / (n - 1))
                            for j in range(n) for i in range(n)))
        corner = {"v": "{0}", "vn": "{0}//{0}", "vtn": "{0}/{0}/{0}"}[mode]
        for j in range(n - 1):
            rows = []
            for i in range(n - 1):
                a = j * n + i + 1
                b, c, d = a + 1, a + n, a + n + 1
                for tri in ((a, b, d), (a, d, c)):
                    rows.append("f " + " ".join(corner.format(v) for v in tri) + "\n")
            f.write("".join(rows))


if __name__ == "__main__":
    main()
