/* The mass matrix's walk over a block (dynamics_blocks.pxi, crba_block), after the block's transforms:
   the composite bodies, tip to base (Featherstone's CRBA, each composite kept as a spatial inertia about
   its frame's origin: first moment m c and the rotational inertia, no centre of mass, so a merge is a
   rotation, a shift and a sum), then the columns: column i is the force and moment (about frame i's
   origin) that a unit motion of joint i asks of composite body i, carried down to the base frame by
   frame; entry (j, i) is its component along joint j, written to (j, i) and (i, j), so M is exactly
   symmetric.

   The walk holds the composite body and each column's force and moment in registers from joint to joint,
   for a group of lanes at once: 4 configurations in a GCC/Clang vector (one AVX2 instruction, or two SSE2
   ones, per operation), and one configuration in plain doubles for the lanes left over (a block of one: a
   single call). Both are the same body (crba_walk_body.h) with the same IEEE operations in the same order
   lane by lane (-ffp-contract=off, no fused multiply-add), so every lane gets the same bits whichever
   group it falls in, in either build. Measured (benchmarks/bench_dynamics.py): the batch mass matrix
   ~1.25x faster than the compiler-vectorised lane loops, which kept the columns in memory between steps.

   S holds the block's transforms X_i = (R, p), structure-of-arrays (B lanes a row, PJ rows a joint:
   rows 0-8 R row-major, 9-11 p; see dynamics_blocks.pxi) and gets the composites' rows 12-20 that the
   columns read; M the m matrices, n x n each, row-major. mass, com, inertia: body i's mass, centre and
   inertia about it (3 x 3) in frame i; beyond[i]: the mass of bodies i+1..n-1. */

#ifndef ROBKIN_CRBA_WALK_H
#define ROBKIN_CRBA_WALK_H

#include <string.h>

#if defined(_MSC_VER) && !defined(__cplusplus) && !defined(__clang__)
#define RK_CRBA_INLINE static __inline   /* MSVC's C before C11 */
#else
#define RK_CRBA_INLINE static inline
#endif

#define RK_WALK rk_crba_walk_1
#define RK_T double
#define RK_W 1
#define RK_LOAD(p) (*(p))
#define RK_SPLAT(x) (x)
#define RK_STORE(p, v) (*(p) = (v))
#define RK_LANE(v, k) (v)
#include "crba_walk_body.h"   /* (it undefines its parameters) */

#if defined(__GNUC__) || defined(__clang__)
typedef double rk_crba_v4 __attribute__((vector_size(32)));

#define RK_WALK rk_crba_walk_4
#define RK_T rk_crba_v4
#define RK_W 4
/* 4 lanes from p, any alignment (macros, not functions: a function returning a 32-byte vector has
   another ABI in a build without AVX, and GCC warns of it) */
#define RK_LOAD(p) __extension__ ({ rk_crba_v4 v_; memcpy(&v_, (p), sizeof v_); v_; })
#define RK_SPLAT(x) ((rk_crba_v4){(x), (x), (x), (x)})
#define RK_STORE(p, v) do { rk_crba_v4 s_ = (v); memcpy((p), &s_, sizeof s_); } while (0)
#define RK_LANE(v, k) ((v)[k])
#include "crba_walk_body.h"   /* (it undefines its parameters) */
#define RK_CRBA_GROUP 4
#else
#define RK_CRBA_GROUP 1   /* no vector extension: every lane on its own, the same bits */
#endif

/* Lanes 0..m-1: groups of RK_CRBA_GROUP lanes, then the rest one by one. */
RK_CRBA_INLINE void rk_crba_walk(double* S, const unsigned char* rev, int n, int m, const double* mass,
                                 const double* com, const double* inertia, const double* beyond, double* M,
                                 Py_ssize_t B, Py_ssize_t PJ)
{
    Py_ssize_t b = 0;
#if RK_CRBA_GROUP == 4
    for (; b + 4 <= m; b += 4)
        rk_crba_walk_4(S, rev, n, mass, com, inertia, beyond, M, b, B, PJ);
#endif
    for (; b < m; b++)
        rk_crba_walk_1(S, rev, n, mass, com, inertia, beyond, M, b, B, PJ);
}

#endif
