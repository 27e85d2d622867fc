#!/usr/bin/env python3
"""gen_moore_table.py -- generator of src/sort/moore_table.h (the Moore/Hilbert state tables).

Run:  python3 src/sort/gen_moore_table.py > src/sort/moore_table.h

What it builds.  A 3D Hilbert curve is a finite automaton: a state is the orientation (a cube
symmetry) of the sub-cube being refined; reading the 3 bits of the next level (one per axis,
octant l = xbit | ybit<<1 | zbit<<2) yields the next 3-bit Hilbert digit w (the child's rank
on the curve) and the child's state.  The states and transitions come from Hamilton's
formulation ("Compact Hilbert indices", Dalhousie CS-2006-07): a state is a pair (e, d), entry
corner e and intra-cube direction d, with
    T_(e,d)(l) = rotr(l ^ e, d + 1),   w = gray^-1(T(l)),
    e' = e ^ rotl(entry(w), d + 1),    d' = (d + dir(w) + 1) mod 3,
    entry(0) = 0, entry(w) = gray(2 floor((w-1)/2)),
    dir(0) = 0, dir(w) = tsb(w-1) mod 3 for w even, tsb(w) mod 3 for w odd
(tsb = number of trailing set bits).  A state's curve enters its cube at corner e and leaves
it at corner e ^ (1 << d).

The Moore curve (the looping Hilbert curve, seed paper Fig. 1b) visits the 8 top-level octants
in the cyclic Gray order gray(0..7) and runs a Hilbert sub-curve in each; the sub-curve states
are found here by search: octant j's exit must be face-adjacent to octant j+1's entry, octant
7's exit to octant 0's entry.  The Hilbert states reachable from these 8 are numbered 0..S-1.

Why it is correct: the script checks, before printing anything, that on full grids of 2^k
cells per axis (k = 1..4) the keys are a bijection onto [0, 8^k), consecutive keys are
face-adjacent cells and the last cell is adjacent to the first (the loop); the C tests
(tests/test_sort_moore.c) check the same properties again on the C code, up to 21 bits.
"""
import itertools
import sys

N = 3


def gray(i):
    return i ^ (i >> 1)


def gray_inv(g):
    i = 0
    while g:
        i ^= g
        g >>= 1
    return i


def rotr(x, r):
    r %= N
    return ((x >> r) | (x << (N - r))) & 7


def rotl(x, r):
    r %= N
    return ((x << r) | (x >> (N - r))) & 7


def tsb(i):
    c = 0
    while i & 1:
        c += 1
        i >>= 1
    return c


def entry(w):
    return 0 if w == 0 else gray(2 * ((w - 1) // 2))


def direction(w):
    if w == 0:
        return 0
    return (tsb(w - 1) if w % 2 == 0 else tsb(w)) % N


def step(state, l):
    """Hilbert state (e, d), octant l -> (digit w, next state)."""
    e, d = state
    w = gray_inv(rotr(l ^ e, d + 1))
    return w, (e ^ rotl(entry(w), d + 1), (d + direction(w) + 1) % N)


def hilbert_cells(state, k):
    """cells (x, y, z) of a 2^k grid in curve order for Hilbert state `state`."""
    if k == 0:
        return [(0, 0, 0)]
    children = {}
    for l in range(8):
        w, s = step(state, l)
        children[w] = (l, s)
    out = []
    half = 1 << (k - 1)
    for w in range(8):
        l, s = children[w]
        off = ((l & 1) * half, ((l >> 1) & 1) * half, ((l >> 2) & 1) * half)
        for c in hilbert_cells(s, k - 1):
            out.append((c[0] + off[0], c[1] + off[1], c[2] + off[2]))
    return out


def adjacent(a, b):
    return sum(abs(p - q) for p, q in zip(a, b)) == 1


def corner_cell(octant, corner, k):
    """global cell, on a 2^k grid, of `corner` (bit per axis) of top-level octant `octant`."""
    half = 1 << (k - 1)
    return tuple(((octant >> a) & 1) * half + ((corner >> a) & 1) * (half - 1) for a in range(N))


def find_moore_states():
    k = 3
    states = [(e, d) for e in range(8) for d in range(N)]
    for first in states:
        for dirs in itertools.product(range(N), repeat=7):
            chain = [first]
            ok = True
            for j in range(7):
                e, d = chain[-1]
                exit_cell = corner_cell(gray(j), e ^ (1 << d), k)
                # the entry of octant j+1 is the corner of octant j+1 next to exit_cell
                ne = None
                for c in range(8):
                    if adjacent(exit_cell, corner_cell(gray(j + 1), c, k)):
                        ne = c
                if ne is None:
                    ok = False
                    break
                chain.append((ne, dirs[j]))
            if not ok:
                continue
            e, d = chain[7]
            if adjacent(corner_cell(gray(7), e ^ (1 << d), k), corner_cell(gray(0), first[0], k)):
                return chain
    raise SystemExit("no Moore curve found")


def moore_cells(moore, k):
    out = []
    half = 1 << (k - 1)
    for j in range(8):
        o = gray(j)
        off = ((o & 1) * half, ((o >> 1) & 1) * half, ((o >> 2) & 1) * half)
        for c in hilbert_cells(moore[j], k - 1):
            out.append((c[0] + off[0], c[1] + off[1], c[2] + off[2]))
    return out


def verify(cells, k, loop):
    assert len(cells) == 8 ** k and len(set(cells)) == 8 ** k, "not a bijection"
    assert all(0 <= v < (1 << k) for c in cells for v in c)
    for a, b in zip(cells, cells[1:]):
        assert adjacent(a, b), ("not adjacent", a, b, k)
    if loop and k >= 1:
        assert adjacent(cells[-1], cells[0]), ("does not loop", k)


def main():
    moore = find_moore_states()
    # number the Hilbert states reachable from the Moore octant states
    order = []
    queue = list(moore)
    while queue:
        s = queue.pop(0)
        if s in order:
            continue
        order.append(s)
        for l in range(8):
            queue.append(step(s, l)[1])
    num = {s: i for i, s in enumerate(order)}
    assert len(order) <= 31
    for s in order:
        for k in range(1, 4):
            verify(hilbert_cells(s, k), k, False)
    for k in range(1, 5):
        verify(moore_cells(moore, k), k, True)

    out = sys.stdout
    out.write("/* moore_table.h -- generated by src/sort/gen_moore_table.py, do not edit.\n"
              " *\n"
              " * State tables of the 3D Moore curve (looping Hilbert curve) used by moore.c.\n"
              " * Octant l = xbit | ybit << 1 | zbit << 2 of the level being read.\n"
              " * sort_moore3_[l]     = next_state << 3 | digit  (top level of the Moore curve)\n"
              " * sort_hilbert3_[s][l] = next_state << 3 | digit  (every finer level)\n"
              " * The generator verified bijection, face adjacency and the loop on 2^1..2^4 grids.\n"
              " */\n")
    out.write("#ifndef GTET_SORT_MOORE_TABLE_H\n#define GTET_SORT_MOORE_TABLE_H\n\n"
              "#include <stdint.h>\n\n")
    out.write("#define SORT_HILBERT_STATES %d\n\n" % len(order))
    mt = [0] * 8
    for l in range(8):
        j = gray_inv(l)
        mt[l] = (num[moore[j]] << 3) | j
    out.write("static const uint8_t sort_moore3_[8] = {%s};\n\n" % ", ".join(str(v) for v in mt))
    out.write("static const uint8_t sort_hilbert3_[SORT_HILBERT_STATES][8] = {\n")
    for s in order:
        row = []
        for l in range(8):
            w, ns = step(s, l)
            row.append((num[ns] << 3) | w)
        out.write("    {%s},\n" % ", ".join("%3d" % v for v in row))
    out.write("};\n\n#endif\n")


if __name__ == "__main__":
    main()
