/* The context's inside, and the helpers every part of the library uses to report errors,
 * log, advance progress, honour cancellation and read parameters. Internal. */
#ifndef FR_CORE_CONTEXT_H
#define FR_CORE_CONTEXT_H

#include <stdarg.h>
#include <stdatomic.h>

#include "frig/frig.h"

#define FR_ERRMSG_SIZE 1024
#define FR_PARAM_MAX 256

struct frig_ctx {
    int threads;
    frig_log_fn log_fn;
    void *log_user;
    frig_log_level log_max;
    frig_progress_fn progress_fn;
    void *progress_user;
    atomic_int cancel;
    frig_status status;
    char errmsg[FR_ERRMSG_SIZE];
    double params[FR_PARAM_MAX];
    /* retarget's outer loop (lib/retarget/refine.c): 1 while a loop runs, so that a recovery of the
     * clouds keeps its sfs computation for the albedo texture instead of drawing it each round
     * (only the last one's is kept); that computation, freed with the context if still held */
    int rt_defer_albedo;
    void *rt_pending;
    void (*rt_pending_free)(void *);
};

/* Set the context's error and return 'status' (so callers can 'return fr_error(...)').
 * Safe to call from inside parallel loops: the first error of a call wins. */
frig_status fr_error(frig_ctx *ctx, frig_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
frig_status fr_verror(frig_ctx *ctx, frig_status status, const char *fmt, va_list ap);
frig_status fr_nomem(frig_ctx *ctx, const char *what);

void fr_log(frig_ctx *ctx, frig_log_level level, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Report progress; done is clamped to total. */
void fr_progress(frig_ctx *ctx, const char *stage, size_t done, size_t total);
/* Inside a parallel loop: count one more item done and report it. */
void fr_progress_tick(frig_ctx *ctx, atomic_size_t *counter, const char *stage, size_t total);

/* A context for one item of a parallel loop (e.g. one photo), so each item's error sentence
 * is its own: the parent's parameters and log callback, one thread, no progress callback, no
 * error, not cancelled (check the parent's flag between items). Needs no freeing. */
void fr_ctx_init_child(frig_ctx *child, const frig_ctx *parent);

/* Run fn(child, i, user) for every i < n in an OpenMP loop with ctx's thread count, each item
 * with its own child context (above), so items fail independently and each sentence is its
 * own; progress ticks under 'stage'; after frig_ctx_cancel() the items not started are
 * skipped and FRIG_ERR_CANCELLED is returned. Otherwise the first failing item in index order
 * gives the status and its sentence (the same whatever the thread count); FRIG_OK when none. */
typedef frig_status (*fr_item_fn)(frig_ctx *child, size_t i, void *user);
frig_status fr_parallel_items(frig_ctx *ctx, size_t n, const char *stage, fr_item_fn fn, void *user);

/* Nonzero once frig_ctx_cancel() was called. */
int fr_cancelled(const frig_ctx *ctx);
/* Sets the error and returns FRIG_ERR_CANCELLED when cancelled, else FRIG_OK. */
frig_status fr_check_cancel(frig_ctx *ctx, const char *where);

/* Number of OpenMP threads a parallel loop should use. */
int fr_threads(const frig_ctx *ctx);

/* Parallel loops run single-threaded BLAS inside (see docs/api.md); begin returns the BLAS
 * thread count to restore with end. */
int fr_blas_serial_begin(void);
void fr_blas_serial_end(int saved);

double fr_param(const frig_ctx *ctx, frig_param param);
int fr_param_int(const frig_ctx *ctx, frig_param param);

#endif
