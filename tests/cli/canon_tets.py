"""canon_tets.py -- print the tets of a gigatet mesh file (.ele, .msh, .vtu) in a canonical
form, one per line, sorted: 0-based vertex ids, rotated by an even permutation so that the
smallest id comes first and the smallest of the other three second.  Even permutations keep
the orientation, so two files print the same text exactly when they hold the same oriented
tets over the same vertex numbering, in whatever order and rotation they were written (a
parallel kernel need not emit its tets in a reproducible order).

    python3 canon_tets.py MESH
"""
import re
import sys


def tets_of(path):
    text = open(path).read()
    if path.endswith(".ele"):
        lines = [l.split("#")[0].split() for l in text.splitlines()]
        lines = [l for l in lines if l]
        return [[int(v) - 1 for v in l[1:5]] for l in lines[1:]]
    if path.endswith(".msh"):
        body = text.split("$Elements\n")[1].split("$EndElements")[0].splitlines()
        return [[int(v) - 1 for v in l.split()[1:5]] for l in body[2:] if l.strip()]
    if path.endswith(".vtu"):
        m = re.search(r'Name="connectivity"[^>]*>(.*?)</DataArray>', text, re.S)
        ids = [int(v) for v in m.group(1).split()]
        return [ids[i:i + 4] for i in range(0, len(ids), 4)]
    sys.exit("unknown mesh extension: " + path)


def canon(t):
    # the 12 even permutations of (a, b, c, d)
    a, b, c, d = t
    even = [(a, b, c, d), (a, c, d, b), (a, d, b, c), (b, a, d, c), (b, c, a, d), (b, d, c, a),
            (c, a, b, d), (c, b, d, a), (c, d, a, b), (d, a, c, b), (d, b, a, c), (d, c, b, a)]
    return min(even)


for t in sorted(canon(t) for t in tets_of(sys.argv[1])):
    print(*t)
