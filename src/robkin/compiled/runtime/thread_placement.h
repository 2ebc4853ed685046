/* Where robkin's OpenMP worker threads may run: every CPU of the calling thread but the one it is on.

   Why: on a virtual machine whose other cores are busy, a worker woken from sleep for a parallel region
   is often queued on the calling thread's own CPU (the only one not running another process's work), and
   waits there until the caller has done its share and left the barrier: two threads then took 3-20x the
   one-thread time (2-core AMD EPYC VM, a busy loop on the other core, FK and Jacobians of 1e4 Panda
   configurations). Kept off the caller's CPU, the worker runs beside it at once (1.8-2.2x in the same
   test) and nothing changes on an idle machine. OpenMP's own binding (OMP_PROC_BIND) would do it too, but
   it binds the calling thread, and every thread the program starts later inherits that binding.

   Linux only (sched_getcpu, sched_setaffinity on a thread id); elsewhere the functions do nothing. */

#ifndef RK_THREAD_PLACEMENT_H
#define RK_THREAD_PLACEMENT_H

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
/* This process's id: a forked child must not take its parent's thread ids for its own, nor start
   OpenMP threads when its parent had (threads.pyx). */
static inline int rk_pid(void) { return (int)getpid(); }
#else
static inline int rk_pid(void) { return 0; }
#endif

#if defined(__linux__)
#include <sched.h>
#include <sys/syscall.h>

#define RK_PLACEMENT 1

/* The calling thread's kernel id. */
static inline int rk_gettid(void) { return (int)syscall(SYS_gettid); }

/* The CPU the calling thread runs on (-1 if unknown). */
static inline int rk_current_cpu(void) { return sched_getcpu(); }

/* Let the threads tids[0..count-1] run on the calling thread's CPUs except `cpu`. 0 on success; -1 if
   that leaves no CPU, the CPU is out of range, or a call fails (e.g. more than CPU_SETSIZE CPUs). */
static inline int rk_exclude_cpu(const int* tids, int count, int cpu) {
    cpu_set_t set;
    int i, failed = 0;
    if (cpu < 0 || cpu >= CPU_SETSIZE) return -1;
    if (sched_getaffinity(0, sizeof set, &set) != 0) return -1;
    CPU_CLR(cpu, &set);
    if (CPU_COUNT(&set) == 0) return -1;
    for (i = 0; i < count; ++i)
        if (sched_setaffinity((pid_t)tids[i], sizeof set, &set) != 0) failed = 1;
    return failed ? -1 : 0;
}
#else
#define RK_PLACEMENT 0
static inline int rk_gettid(void) { return -1; }
static inline int rk_current_cpu(void) { return -1; }
static inline int rk_exclude_cpu(const int* tids, int count, int cpu) { (void)tids; (void)count; (void)cpu; return -1; }
#endif

#endif
