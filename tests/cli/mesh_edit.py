"""mesh_edit.py -- rewrite a TetGen mesh (NAME.node + NAME.ele, 0- or 1-based) for the checker's
end-to-end tests.

    mesh_edit.py flip23 IN.ele OUT_BASE
        replace two tets sharing a facet by the three tets around their apexes' edge (the first
        such pair whose union is convex): a valid triangulation of the same points that is not
        Delaunay on random points.  Written 0-based, oriented as the input was.
"""
import sys
import numpy as np


def rows(path):
    out = []
    for line in open(path):
        r = line.split('#')[0].split()
        if r:
            out.append(r)
    return out


def read(base):
    nr, er = rows(base + '.node'), rows(base + '.ele')
    nn, ne = int(nr[0][0]), int(er[0][0])
    pts = np.array([[float(x) for x in r[1:4]] for r in nr[1:1 + nn]])
    first = int(nr[1][0])
    tets = np.array([[int(x) - first for x in r[1:5]] for r in er[1:1 + ne]])
    return pts, tets


def write(base, pts, tets):
    with open(base + '.node', 'w') as f:
        f.write('%d 3 0 0\n' % len(pts))
        for i, p in enumerate(pts):
            f.write('%d %.17g %.17g %.17g\n' % (i, p[0], p[1], p[2]))
    with open(base + '.ele', 'w') as f:
        f.write('%d 4 0\n' % len(tets))
        for i, t in enumerate(tets):
            f.write('%d %d %d %d %d\n' % (i, t[0], t[1], t[2], t[3]))


def orient(p, a, b, c, d):
    return np.linalg.det(np.array([p[b] - p[a], p[c] - p[a], p[d] - p[a]]))


def flip23(pts, tets):
    facets = {}
    for t, tet in enumerate(tets):
        for f in range(4):
            key = tuple(sorted(int(tet[i]) for i in range(4) if i != f))
            facets.setdefault(key, []).append((t, int(tet[f])))
    for (a, b, c), sides in sorted(facets.items()):
        if len(sides) != 2:
            continue
        (t1, d), (t2, e) = sides
        # de must cross the triangle abc: the three new tets all have one orientation
        s = [orient(pts, x, y, d, e) for x, y in ((a, b), (b, c), (c, a))]
        if all(v > 1e-9 for v in s) or all(v < -1e-9 for v in s):
            keep = [t for t in range(len(tets)) if t not in (t1, t2)]
            new = [[a, b, d, e], [b, c, d, e], [c, a, d, e]]
            return np.vstack([tets[keep], np.array(new)])
    sys.exit('mesh_edit.py: no flippable facet')


def main():
    if len(sys.argv) != 4 or sys.argv[1] != 'flip23' or not sys.argv[2].endswith('.ele'):
        sys.exit(__doc__)
    pts, tets = read(sys.argv[2][:-4])
    write(sys.argv[3], pts, flip23(pts, tets))


if __name__ == '__main__':
    main()
