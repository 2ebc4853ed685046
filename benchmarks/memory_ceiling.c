/* The memory-bandwidth ceiling of this machine for robkin's batch kernels (docs/compiled.md, "Threads,
 * memory and scaling"): GB/s of a buffer written with ordinary stores (each missed line is read first:
 * write-allocate), with streaming (non-temporal) stores, read, and written for the first time (fresh
 * memory: the operating system's page faults, 4 kB pages or transparent huge pages), on 1 and 2 threads,
 * each thread on its own half. Best of 7 repetitions (the machine's other load only slows a run down).
 * Not part of robkin and not run by any test:
 *
 *     cc -O2 -mavx2 -fopenmp benchmarks/memory_ceiling.c -o /tmp/memory_ceiling && /tmp/memory_ceiling [MB]
 *
 * (default 64 MB: twice this machine's 32 MB L3, so the traffic goes to memory).
 */
#define _GNU_SOURCE
#include <immintrin.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static void write_plain(double *a, long n)
{
    for (long i = 0; i < n; i++)
        a[i] = 1.0 + i;
}

static void write_stream(double *a, long n)
{
    __m256d v = _mm256_set1_pd(1.0);
    for (long i = 0; i < n; i += 4)
        _mm256_stream_pd(a + i, v);
    _mm_sfence();
}

static double read_all(const double *a, long n)
{
    __m256d s0 = _mm256_setzero_pd(), s1 = s0, s2 = s0, s3 = s0;
    double t[4];
    for (long i = 0; i < n; i += 16) {
        s0 = _mm256_add_pd(s0, _mm256_load_pd(a + i));
        s1 = _mm256_add_pd(s1, _mm256_load_pd(a + i + 4));
        s2 = _mm256_add_pd(s2, _mm256_load_pd(a + i + 8));
        s3 = _mm256_add_pd(s3, _mm256_load_pd(a + i + 12));
    }
    _mm256_storeu_pd(t, _mm256_add_pd(_mm256_add_pd(s0, s1), _mm256_add_pd(s2, s3)));
    return t[0] + t[1] + t[2] + t[3];
}

/* best GB/s of `kind` (0 write, 1 stream, 2 read, 3 fresh 4 kB, 4 fresh huge pages) on `threads` */
static double measure(int kind, int threads, long bytes)
{
    long n = bytes / 8;
    double best = 1e30;
    volatile double sink = 0.0;
    double *a = aligned_alloc(2 << 20, bytes);
    memset(a, 0, bytes);
    for (int rep = 0; rep < 7; rep++) {
        double *b = a;
        if (kind >= 3) {
            b = aligned_alloc(2 << 20, bytes);
            if (kind == 4)
                madvise(b, bytes, MADV_HUGEPAGE);
        }
        double t0 = now();
#pragma omp parallel num_threads(threads)
        {
            int id = omp_get_thread_num();
            long lo = (n * id / threads) & ~15L, hi = (n * (id + 1) / threads) & ~15L;
            if (kind == 1)
                write_stream(b + lo, hi - lo);
            else if (kind == 2)
                sink += read_all(b + lo, hi - lo);
            else
                write_plain(b + lo, hi - lo);
        }
        double dt = now() - t0;
        if (dt < best)
            best = dt;
        if (kind >= 3)
            free(b);
    }
    free(a);
    return bytes / best / 1e9;
}

int main(int argc, char **argv)
{
    long bytes = (argc > 1 ? atol(argv[1]) : 64) << 20;
    const char *names[] = {"write (ordinary stores)", "write (streaming stores)", "read",
                           "first write, 4 kB pages", "first write, huge pages"};
    printf("%ld MB buffer, best of 7, GB/s\n%-26s%10s%10s\n", bytes >> 20, "", "1 thread", "2 threads");
    for (int kind = 0; kind < 5; kind++)
        printf("%-26s%10.1f%10.1f\n", names[kind], measure(kind, 1, bytes), measure(kind, 2, bytes));
    return 0;
}
