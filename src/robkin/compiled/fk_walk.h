/* The walk of a block of configurations along the chain (fk.pxd, walk_block): batch FK, frames and the
   Jacobians' joint origins and axes.

   T(q) = L_1 Z_1(q_1) L_2 Z_2(q_2) ... L_n Z_n(q_n) L_{n+1} (see fk.pxd). The walk first reads the block's
   joint values joint by joint (for up to RK_FK_JOINTS joints at a time) and takes the sines and cosines
   of the revolute ones over the whole block (rk_sincos_array, a loop the compiler vectorises), then walks
   the block's configurations through those joints a group of lanes at a time, each running pose (the 12
   entries of its top rows) held in registers from joint to joint: 4 configurations in a GCC/Clang vector
   (one AVX2 instruction, or two SSE2 ones, per operation), and one configuration in plain doubles for the
   lanes left over (a block of one: a single call). Both are the same body (fk_walk_body.h) with the same
   IEEE operations in the same order lane by lane (-ffp-contract=off, no fused multiply-add), so every
   lane gets the same bits whichever group it falls in, in either build, as the lane loops over a block
   in memory that this replaced. Measured (benchmarks/bench_avx2.py, N = 1e5, AVX2 build): see
   docs/compiled.md.

   P: 12 x RK_FK_BLOCK doubles, P[RK_FK_BLOCK * e + b] = entry e (row-major, top three rows) of
   configuration b's pose: the tool poses on return. F, if not NULL: the frames (m, n+1, 16). Z, if not
   NULL: Z[ld * (n * r + i) + b] = p_i[r], Z[ld * (n * (r + 3) + i) + b] = z_i[r] (r < 3), ld >= m. */

#ifndef ROBKIN_FK_WALK_H
#define ROBKIN_FK_WALK_H

#include <string.h>
#include "sincos.h"

#if defined(_MSC_VER) && !defined(__cplusplus) && !defined(__clang__)
#define RK_FK_INLINE static __inline   /* MSVC's C before C11 */
#else
#define RK_FK_INLINE static inline
#endif
/* the lane-group steps inlined into the walk whatever the compiler's estimate of their size: a call per
   group (GCC's choice in the portable build) keeps F, Z and T unknown and the group's state in memory */
#if defined(__GNUC__) || defined(__clang__)
#define RK_FK_STEPS_INLINE static inline __attribute__((always_inline))
#else
#define RK_FK_STEPS_INLINE RK_FK_INLINE
#endif

/* configurations in a block at most: fk.pxd's BLOCK (the stride of P's rows) */
#define RK_FK_BLOCK 32
/* joints whose values, sines and cosines are gathered before the lanes walk them (3 x 8 x 32 doubles:
   6 kB of stack); a longer chain is walked in stretches of this many joints */
#define RK_FK_JOINTS 8

/* Part `part` of `parts` of the `bytes` at p asked into the cache for writing (a hint: no effect on any
   value; nothing where the compiler has no prefetch). */
RK_FK_INLINE void rk_prefetch_part(const void* p, Py_ssize_t bytes, int part, int parts)
{
#if defined(__GNUC__) || defined(__clang__)
    const char* c = (const char*)p;
    Py_ssize_t o, hi = bytes * (part + 1) / parts;
    for (o = (bytes * part / parts) & ~(Py_ssize_t)63; o < hi; o += 64)
        __builtin_prefetch(c + o, 1, 3);
#endif
}

/* The `bytes` at p asked into the cache for reading (a hint, as above). */
RK_FK_INLINE void rk_prefetch_read(const void* p, Py_ssize_t bytes)
{
#if defined(__GNUC__) || defined(__clang__)
    const char* c = (const char*)p;
    Py_ssize_t o;
    for (o = 0; o < bytes; o += 64)
        __builtin_prefetch(c + o, 0, 3);
#endif
}

#define RK_STEPS rk_fk_steps_1
#define RK_T double
#define RK_W 1
#define RK_LOAD(p) (*(p))
#define RK_SPLAT(x) (x)
#define RK_STORE(p, v) (*(p) = (v))
#define RK_LANE(v, k) (v)
#include "fk_walk_body.h"   /* (it undefines its parameters) */

#if (defined(__GNUC__) || defined(__clang__)) && defined(__AVX__)
/* 4 lanes in one 256-bit register */
typedef double rk_fk_v __attribute__((vector_size(32)));
#define RK_FK_GROUP 4
#define RK_SPLAT(x) ((rk_fk_v){(x), (x), (x), (x)})
#elif defined(__GNUC__) || defined(__clang__)
/* 2 lanes (SSE2): 12 running poses of 4 lanes would not fit the 16 registers */
typedef double rk_fk_v __attribute__((vector_size(16)));
#define RK_FK_GROUP 2
#define RK_SPLAT(x) ((rk_fk_v){(x), (x)})
#else
#define RK_FK_GROUP 1   /* no vector extension: every lane on its own, the same bits */
#endif

#if RK_FK_GROUP > 1
#define RK_STEPS rk_fk_steps_v
#define RK_T rk_fk_v
#define RK_W RK_FK_GROUP
/* RK_W lanes from p, any alignment (macros, not functions: a function returning a 32-byte vector has
   another ABI in a build without AVX, and GCC warns of it) */
#define RK_LOAD(p) __extension__ ({ rk_fk_v v_; memcpy(&v_, (p), sizeof v_); v_; })
#define RK_STORE(p, v) do { rk_fk_v s_ = (v); memcpy((p), &s_, sizeof s_); } while (0)
#define RK_LANE(v, k) ((v)[k])
#include "fk_walk_body.h"   /* (it undefines its parameters) */
#endif

/* The walk of m <= RK_FK_BLOCK configurations Q (m x n, row-major). ahead, if not NULL: the ahead_bytes
   the caller writes after the walk, asked into the cache a part at each joint (a hint). */
RK_FK_INLINE void rk_fk_walk(const double* L, const unsigned char* rev, int n, const double* Q, int m,
                             double* P, double* F, double* Z, Py_ssize_t ld, double* T, const double* ahead,
                             Py_ssize_t ahead_bytes)
{
    double qt[RK_FK_JOINTS * RK_FK_BLOCK], st[RK_FK_JOINTS * RK_FK_BLOCK], ct[RK_FK_JOINTS * RK_FK_BLOCK];
    int i0, i1, i, b;
    for (i0 = 0;; i0 = i1) {     /* (once for n = 0: the tool pose L_1) */
        i1 = n - i0 < RK_FK_JOINTS ? n : i0 + RK_FK_JOINTS;
        for (i = i0; i < i1; i++) {
            double* q = qt + RK_FK_BLOCK * (i - i0);
            if (ahead)
                rk_prefetch_part(ahead, ahead_bytes, i, n);
            for (b = 0; b < m; b++)
                q[b] = Q[(Py_ssize_t)n * b + i];
            if (rev[i]) {
                if (m == 1)   /* inline: no call, no loop set-up for one angle */
                    rk_sincos_one(q[0], st + RK_FK_BLOCK * (i - i0), ct + RK_FK_BLOCK * (i - i0));
                else
                    rk_sincos_array(q, st + RK_FK_BLOCK * (i - i0), ct + RK_FK_BLOCK * (i - i0), m);
            }
        }
        b = 0;
#if RK_FK_GROUP > 1
        for (; b + RK_FK_GROUP <= m; b += RK_FK_GROUP)
            rk_fk_steps_v(L, rev, n, i0, i1, qt, st, ct, P, F, Z, ld, T, b);
#endif
        for (; b < m; b++)
            rk_fk_steps_1(L, rev, n, i0, i1, qt, st, ct, P, F, Z, ld, T, b);
        if (i1 == n)
            break;
    }
}

#endif
