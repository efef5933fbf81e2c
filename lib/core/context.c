/* The context handle: settings, callbacks, cancellation and the last error. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "core/context.h"
#include "core/params.h"

frig_ctx *frig_ctx_create(void) {
    frig_ctx *ctx = calloc(1, sizeof *ctx);
    if (!ctx) return NULL;
    ctx->log_max = FRIG_LOG_WARNING;
    atomic_init(&ctx->cancel, 0);
    fr_params_init(ctx->params);
    return ctx;
}

void frig_ctx_free(frig_ctx *ctx) {
    if (ctx && ctx->rt_pending && ctx->rt_pending_free) ctx->rt_pending_free(ctx->rt_pending);
    free(ctx);
}

const char *frig_ctx_errmsg(const frig_ctx *ctx) { return ctx ? ctx->errmsg : "no context"; }
frig_status frig_ctx_status(const frig_ctx *ctx) { return ctx ? ctx->status : FRIG_ERR_INVALID_ARGUMENT; }

void frig_ctx_clear_error(frig_ctx *ctx) {
    if (!ctx) return;
    ctx->status = FRIG_OK;
    ctx->errmsg[0] = 0;
}

frig_status frig_ctx_set_threads(frig_ctx *ctx, int threads) {
    if (!ctx) return FRIG_ERR_INVALID_ARGUMENT;
    if (threads < 0 || threads > 4096)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "thread count %d is outside [0, 4096]", threads);
    ctx->threads = threads;
    return FRIG_OK;
}

int frig_ctx_threads(const frig_ctx *ctx) { return ctx ? ctx->threads : 0; }

void frig_ctx_set_log(frig_ctx *ctx, frig_log_fn fn, void *user, frig_log_level max_level) {
    if (!ctx) return;
    ctx->log_fn = fn;
    ctx->log_user = user;
    ctx->log_max = max_level;
}

void frig_ctx_set_progress(frig_ctx *ctx, frig_progress_fn fn, void *user) {
    if (!ctx) return;
    ctx->progress_fn = fn;
    ctx->progress_user = user;
}

void frig_ctx_cancel(frig_ctx *ctx) {
    if (ctx) atomic_store(&ctx->cancel, 1);
}

void frig_ctx_reset_cancel(frig_ctx *ctx) {
    if (ctx) atomic_store(&ctx->cancel, 0);
}

frig_status fr_verror(frig_ctx *ctx, frig_status status, const char *fmt, va_list ap) {
    if (!ctx) return status;
    int in_parallel = omp_in_parallel();
    /* Inside a parallel loop the first error wins; outside, the newest does. */
#pragma omp critical(frig_error)
    {
        if (!in_parallel || ctx->status == FRIG_OK) {
            vsnprintf(ctx->errmsg, sizeof ctx->errmsg, fmt, ap);
            ctx->status = status;
        }
    }
    return status;
}

frig_status fr_error(frig_ctx *ctx, frig_status status, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    fr_verror(ctx, status, fmt, ap);
    va_end(ap);
    return status;
}

frig_status fr_nomem(frig_ctx *ctx, const char *what) {
    return fr_error(ctx, FRIG_ERR_NO_MEMORY, "out of memory while allocating %s", what);
}

void fr_log(frig_ctx *ctx, frig_log_level level, const char *fmt, ...) {
    if (!ctx || !ctx->log_fn || level > ctx->log_max) return;
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
#pragma omp critical(frig_callback)
    ctx->log_fn(ctx->log_user, level, line);
}

void fr_progress(frig_ctx *ctx, const char *stage, size_t done, size_t total) {
    if (!ctx || !ctx->progress_fn) return;
    if (done > total) done = total;
#pragma omp critical(frig_callback)
    ctx->progress_fn(ctx->progress_user, stage, done, total);
}

void fr_progress_tick(frig_ctx *ctx, atomic_size_t *counter, const char *stage, size_t total) {
    if (!ctx || !ctx->progress_fn) {
        atomic_fetch_add(counter, 1);
        return;
    }
    /* Increment and report under one lock so reports arrive in increasing order. */
#pragma omp critical(frig_callback)
    {
        size_t done = atomic_fetch_add(counter, 1) + 1;
        ctx->progress_fn(ctx->progress_user, stage, done > total ? total : done, total);
    }
}

void fr_ctx_init_child(frig_ctx *child, const frig_ctx *parent) {
    memset(child, 0, sizeof *child);
    atomic_init(&child->cancel, 0);
    child->threads = 1;
    child->log_fn = parent->log_fn;
    child->log_user = parent->log_user;
    child->log_max = parent->log_max;
    memcpy(child->params, parent->params, sizeof child->params);
}

int fr_cancelled(const frig_ctx *ctx) { return ctx && atomic_load(&((frig_ctx *)ctx)->cancel); }

frig_status fr_check_cancel(frig_ctx *ctx, const char *where) {
    if (!fr_cancelled(ctx)) return FRIG_OK;
    return fr_error(ctx, FRIG_ERR_CANCELLED, "cancelled during %s", where);
}

int fr_threads(const frig_ctx *ctx) {
    int t = ctx ? ctx->threads : 0;
    if (t <= 0) t = omp_get_num_procs();
    return t < 1 ? 1 : t;
}

int fr_blas_serial_begin(void) {
    int saved = openblas_get_num_threads();
    openblas_set_num_threads(1);
    return saved;
}

void fr_blas_serial_end(int saved) { openblas_set_num_threads(saved); }
