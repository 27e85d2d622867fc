# int_exact.g -- the bound PRED_IS_INT_EXACT of src/pred/filter.h (proofs/filters.md section 12),
# checked by proofs/check_int_exact (ctest proofs_int_exact).
# X, Y, Z, M: the maxima of the translated coordinates of an insphere tuple of integers below
# 2^23 in magnitude (exact integers in [1, 2^24]; a zero maximum is section 12's other case).
# p4: the record the filter computes, ((((X*Y)*Z)*M)*M) rounded at each product.
# Goal: if p4 <= B (B = 2^46, the shipped bound) then P = X*Y*Z*M*M, the exact product, is at
# most the enclosure Gappa returns; the checker requires 72 * P.hi <= 2^53.
@rnd = float<ieee_64, ne>;
p1 = rnd(X * Y);
p2 = rnd(p1 * Z);
p3 = rnd(p2 * M);
p4 = rnd(p3 * M);
P = X * Y * Z * M * M;
{ X in [1, 16777216] /\ Y in [1, 16777216] /\ Z in [1, 16777216] /\ M in [1, 16777216]
  /\ p4 in [1, 70368744177664]
  -> P in ? }
