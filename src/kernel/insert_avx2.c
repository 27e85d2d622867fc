/* insert_avx2.c -- km_insert's two instances (insert.c) compiled with AVX2 enabled: the same
 * steps (insert_steps.h), with the insphere filter evaluated four lanes at a time
 * (filter_packed.h pred_insphere_lanes4_: the same operations on the same operands as the scalar
 * filter, so the same answers and records bit for bit; proofs/filters.md section 13).  Built
 * only where the compiler takes -mavx2 for x86-64 (CMakeLists.txt, GTET_AVX2_TU); km_insert
 * calls these only when the CPU has AVX2 (kctx_init).  -ffp-contract=off holds here as
 * everywhere (CMakeLists.txt): no product is contracted into a sum, FMA or not. */
#include "insert_steps.h"

#if !defined(__AVX2__) || !defined(PRED_INSPHERE_PACKED4)
#error "insert_avx2.c must be compiled with AVX2 enabled (-mavx2)"
#endif

__attribute__((noinline)) gtet_status km_insert_static_first_avx2(kctx *c, uint32_t pid,
                                                                  int *deferred)
{
    return km_insert_t(c, pid, deferred, 0);
}

__attribute__((noinline)) gtet_status km_insert_local_first_avx2(kctx *c, uint32_t pid,
                                                                int *deferred)
{
    return km_insert_t(c, pid, deferred, 1);
}
