"""scipy_ele.py POINTS.node OUT_BASE [--shuffle SEED] -- scipy.spatial.Delaunay of a .node file,
written as OUT_BASE.node / OUT_BASE.ele (0-based, simplices as scipy gives them: unoriented)."""
import sys
import numpy as np
from scipy.spatial import Delaunay
def read_node(path):
    rows = [l.split('#')[0].split() for l in open(path)]
    rows = [r for r in rows if r]
    n = int(rows[0][0])
    return np.array([[float(x) for x in r[1:4]] for r in rows[1:1 + n]])
pts = read_node(sys.argv[1])
d = Delaunay(pts)
simp = d.simplices.copy()
order = np.arange(len(pts))
if len(sys.argv) > 4 and sys.argv[3] == '--shuffle':
    rng = np.random.default_rng(int(sys.argv[4]))
    order = rng.permutation(len(pts))     # new id of old vertex i is order[i]
    newpts = np.empty_like(pts); newpts[order] = pts
    pts, simp = newpts, order[simp]
base = sys.argv[2]
with open(base + '.node', 'w') as f:
    f.write('%d 3 0 0\n' % len(pts))
    for i, p in enumerate(pts): f.write('%d %.17g %.17g %.17g\n' % (i, p[0], p[1], p[2]))
with open(base + '.ele', 'w') as f:
    f.write('%d 4 0\n' % len(simp))
    for i, t in enumerate(simp): f.write('%d %d %d %d %d\n' % (i, t[0], t[1], t[2], t[3]))
print(len(simp))
