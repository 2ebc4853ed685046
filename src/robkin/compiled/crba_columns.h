/* The mass matrix's column walk (dynamics_blocks.pxi, crba_block): column i is the force and moment
   (about frame i's origin) that a unit motion of joint i asks of composite body i, carried down to the
   base frame by frame; entry (j, i) is its component along joint j, written to (j, i) and (i, j).

   The walk keeps each column's force and moment in registers from frame to frame, for a group of lanes at
   once: 4 configurations in a GCC/Clang vector (one AVX2 instruction, or two SSE2 ones, per operation),
   and one configuration in plain doubles for the lanes left over (a block of one: a single call). Both are
   the same body (crba_columns_body.h) with the same IEEE operations in the same order lane by lane
   (-ffp-contract=off, no fused multiply-add), so every lane gets the same bits whichever group it falls
   in, in either build. (The lane loops of Cython code that the compiler vectorises keep the force and
   moment in memory between steps: measured ~1.2x slower for the whole mass matrix.)

   S holds the block's transforms X_i = (R, p) and composite bodies, structure-of-arrays (B lanes a row,
   PJ rows a joint: see dynamics_blocks.pxi); M the m matrices, n x n each, row-major. */

#ifndef ROBKIN_CRBA_COLUMNS_H
#define ROBKIN_CRBA_COLUMNS_H

#include <string.h>

#define RK_COLUMNS rk_crba_columns_1
#define RK_T double
#define RK_W 1
#define RK_LOAD(p) (*(p))
#define RK_SPLAT(x) (x)
#define RK_LANE(v, k) (v)
#include "crba_columns_body.h"
#undef RK_COLUMNS
#undef RK_T
#undef RK_W
#undef RK_LOAD
#undef RK_SPLAT
#undef RK_LANE

#if defined(__GNUC__) || defined(__clang__)
typedef double rk_crba_v4 __attribute__((vector_size(32)));

#define RK_COLUMNS rk_crba_columns_4
#define RK_T rk_crba_v4
#define RK_W 4
/* 4 lanes from p, any alignment (macros, not functions: a function returning a 32-byte vector has
   another ABI in a build without AVX, and GCC warns of it) */
#define RK_LOAD(p) __extension__ ({ rk_crba_v4 v_; memcpy(&v_, (p), sizeof v_); v_; })
#define RK_SPLAT(x) ((rk_crba_v4){(x), (x), (x), (x)})
#define RK_LANE(v, k) ((v)[k])
#include "crba_columns_body.h"
#undef RK_COLUMNS
#undef RK_T
#undef RK_W
#undef RK_LOAD
#undef RK_SPLAT
#undef RK_LANE
#define RK_CRBA_GROUP 4
#else
#define RK_CRBA_GROUP 1   /* no vector extension: every lane on its own, the same bits */
#endif

/* The columns of lanes 0..m-1: groups of RK_CRBA_GROUP lanes, then the rest one by one. */
static inline void rk_crba_columns(const double* S, const unsigned char* rev, int n, int m, const double* mass,
                                   const double* beyond, double* M, Py_ssize_t B, Py_ssize_t PJ)
{
    Py_ssize_t b = 0;
#if RK_CRBA_GROUP == 4
    for (; b + 4 <= m; b += 4)
        rk_crba_columns_4(S, rev, n, mass, beyond, M, b, B, PJ);
#endif
    for (; b < m; b++)
        rk_crba_columns_1(S, rev, n, mass, beyond, M, b, B, PJ);
}

#endif
