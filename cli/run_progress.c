/* What frig run shows while it works: on a terminal one bar, redrawn in place, with the
 * stage, its step, item i of n, the time since the run began and the step's estimated time
 * left; elsewhere (a log file, CI) plain lines: each stage's start and end, and a line per
 * quarter of a long step. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "run.h"

static void clock_text(double s, char *buf, size_t size) {
    long t = (long)(s + 0.5);
    if (t >= 3600) snprintf(buf, size, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
    else snprintf(buf, size, "%ld:%02ld", t / 60, t % 60);
}

static void clear_line(run_ctx *r) {
    if (r->env->progress_shown) {
        fputs("\r\033[K", stderr);
        r->env->progress_shown = 0;
    }
}

static void on_progress(void *user, const char *step, size_t done, size_t total) {
    run_ctx *r = user;
    if (r->env->quiet) return;
    double now = run_now();
    if (strcmp(step, r->sub) != 0) {
        snprintf(r->sub, sizeof r->sub, "%s", step);
        r->sub_t0 = now;
    }
    /* detect in batches: the batch's items are part of the whole set's */
    size_t all = total, at = done;
    if (r->total && strcmp(step, "detect") == 0) all = r->total, at = r->offset + done;
    const char *stage = run_stages[r->stage].name;
    if (!r->tty) { /* a line every 10 s of a long step */
        if (at < all && now - r->line_t >= 10.0 && now - r->sub_t0 >= 10.0) {
            fprintf(stderr, "frig run: %s: %s %zu/%zu\n", stage, step, at, all);
            r->line_t = now;
        }
        return;
    }
    char elapsed[32], eta[64] = "";
    clock_text(now - r->t0, elapsed, sizeof elapsed);
    double spent = now - r->sub_t0;
    if (at > 0 && at < all && spent > 0.5) {
        char left[32];
        clock_text(spent / (double)(at - (r->total && strcmp(step, "detect") == 0 ? r->offset : 0) + 1e-9) *
                       (double)(all - at),
                   left, sizeof left);
        snprintf(eta, sizeof eta, ", ETA %s", left);
    }
    int width = 24, filled = all ? (int)((double)at / (double)all * width) : width;
    char bar[32];
    for (int i = 0; i < width; i++) bar[i] = i < filled ? '#' : '.';
    bar[width] = 0;
    fprintf(stderr, "\r\033[K[%d/%d %s] %-15.15s [%s] %zu/%zu  %s%s", r->stage + 1, run_stage_count, stage, step, bar,
            at, all, elapsed, eta);
    r->env->progress_shown = 1;
    fflush(stderr);
}

void run_progress_install(run_ctx *r) {
    r->tty = isatty(2);
    if (!r->env->quiet) frig_ctx_set_progress(r->env->ctx, on_progress, r);
}

void run_progress_range(run_ctx *r, size_t offset, size_t total) {
    r->offset = offset;
    r->total = total;
}

void run_progress_stage(run_ctx *r, const char *fmt, ...) {
    if (r->env->quiet) return;
    clear_line(r);
    char elapsed[32];
    clock_text(run_now() - r->t0, elapsed, sizeof elapsed);
    fprintf(stderr, "frig run: [%d/%d] %-8s ", r->stage + 1, run_stage_count, run_stages[r->stage].name);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "  (%s)\n", elapsed);
    r->sub[0] = 0;
    r->line_t = run_now();
}

void run_progress_done(run_ctx *r) { clear_line(r); }
